// test_filter.cpp — the reconstruction filter (kernels/filter.cl) on synthetic G-buffers:
// a dashed isolated strand comes out connected with alpha below one, a dense patch keeps
// alpha about one, the weights are normalised, no colour crosses a depth edge.
#include <cmath>
#include <cstring>

#include "cl/device_impl.h"
#include "clhair/gpu_types.h"
#include "stages/filter_stage.h"
#include "test_util.h"

namespace clhair {
namespace {

using namespace gpu;
constexpr int W = 48, H = 32;
constexpr clh_u64 kEmpty = CLH_GBUF_EMPTY;

struct Synthetic {
  std::vector<clh_u64> gbuf = std::vector<clh_u64>(2 * W * H, kEmpty);  // center, conservative
  std::vector<cl_float4> colour = std::vector<cl_float4>(W * H, cl_float4{{0, 0, 0, 0}});

  // depth in [1, 2] (the groom range below), tangent direction in the image plane
  static clh_u64 word(float z, float tx, float ty) {
    // view space: +x right, +y up; the image y axis points down
    return clh_gbuf_pack(clh_depth_encode(z, 1.0f, 2.0f), clh_oct_encode(tx, ty, 0.0f), 10, 20, 30,
                         63);
  }
  void center(int x, int y, clh_u64 w, float r, float g, float b) {
    gbuf[y * W + x] = w;
    gbuf[W * H + y * W + x] = std::min(gbuf[W * H + y * W + x], w);
    colour[y * W + x] = cl_float4{{r, g, b, 1.0f}};
  }
  void cons(int x, int y, clh_u64 w) {
    gbuf[W * H + y * W + x] = std::min(gbuf[W * H + y * W + x], w);
  }
};

std::vector<cl_float4> runFilter(const Synthetic& s, bool promote = true) {
  Device& dev = test::sharedDevice();
  Device::Impl& d = *dev.impl();
  ClhGroomGpu groom{};
  groom.depth_near = 1.0f;
  groom.depth_far = 2.0f;
  ClhViewGpu view{};
  for (int i = 0; i < 3; ++i) view.world_to_view[i * 4 + i] = view.view_to_world[i * 4 + i] = 1.0f;
  view.fx = view.fy = 40.0f;
  view.cx = W / 2.0f;
  view.cy = H / 2.0f;
  view.width = W;
  view.height = H;
  view.samples = 1;
  FilterParams f;
  f.radius = 5;
  f.sPar = 0.5f;
  f.sPerp = 0.1f;
  f.sigmaC = 0.9f;
  f.depthReject = 1.45e-3f;
  f.depthMismatch = 5e-4f;
  f.strip = 0.5f;
  f.promote = promote;
  auto buf = [&](const void* data, std::size_t bytes) {
    return cl::Buffer(d.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, bytes,
                      const_cast<void*>(data));
  };
  cl::Buffer bg = buf(&groom, sizeof(groom)), bv = buf(&view, sizeof(view));
  cl::Buffer gb = buf(s.gbuf.data(), s.gbuf.size() * 8),
             hair = buf(s.colour.data(), s.colour.size() * 16);
  std::vector<cl_float4> out(W * H + 3, cl_float4{{-7, -7, -7, -7}});  // canaries at the end
  cl::Buffer bo = buf(out.data(), out.size() * 16);
  FilterStage stage(d);
  // the stage checks every buffer against the W x H target: the canaries lie beyond it
  stage.enqueue(f, {{&bv, W, H}, &bg, &gb, &hair, &bo}, nullptr);
  d.queue.enqueueReadBuffer(bo, CL_TRUE, 0, out.size() * 16, out.data());
  for (int i = W * H; i < W * H + 3; ++i) EXPECT_EQ(out[i].s[0], -7.0f) << "canary overwritten";
  out.resize(W * H);
  return out;
}

TEST(Filter, DashedIsolatedStrandComesOutConnected) {
  // a strand along y = 6 + 0.5 x: every pixel it touches is conservative, only every
  // fourth column has a center hit (a sub-pixel strand missing most pixel centers)
  Synthetic s;
  const float tx = 2.0f / std::sqrt(5.0f), ty = -1.0f / std::sqrt(5.0f);  // down-right on screen
  const clh_u64 w = Synthetic::word(1.5f, tx, ty);
  std::vector<std::pair<int, int>> line;
  for (int x = 2; x < 44; ++x) {
    float y0 = 6.0f + 0.5f * x, y1 = 6.0f + 0.5f * (x + 1);
    for (int y = static_cast<int>(std::floor(y0)); y <= static_cast<int>(std::floor(y1)); ++y) {
      s.cons(x, y, w);
      line.push_back({x, y});
    }
    if (x % 4 == 0)
      s.center(x, static_cast<int>(std::floor(6.0f + 0.5f * (x + 0.5f))), w, 0.6f, 0.3f, 0.1f);
  }
  std::vector<cl_float4> out = runFilter(s);
  int covered = 0;
  for (auto [x, y] : line) {
    const cl_float4& o = out[y * W + x];
    if (x < 6 || x > 40) continue;  // the window reaches center hits from both sides
    ++covered;
    EXPECT_GT(o.s[3], 0.0f) << "gap at " << x << "," << y;
    EXPECT_LT(o.s[3], 1.0f) << "isolated strand must stay transparent at " << x << "," << y;
    // premultiplied: colour / alpha is the strand colour
    EXPECT_NEAR(o.s[0] / o.s[3], 0.6f, 1e-4f);
    EXPECT_NEAR(o.s[2] / o.s[3], 0.1f, 1e-4f);
  }
  EXPECT_GT(covered, 50);
  // far from the strand nothing is drawn
  EXPECT_EQ(out[30 * W + 2].s[3], 0.0f);
}

TEST(Filter, WithoutPromotionOnlyCenterHitsAreDrawn) {
  // the dashed strand of the test above with promotion off: the conservative-only pixels
  // stay empty, the center hits keep the strand colour with the same strip alpha
  Synthetic s;
  const float tx = 2.0f / std::sqrt(5.0f), ty = -1.0f / std::sqrt(5.0f);
  const clh_u64 w = Synthetic::word(1.5f, tx, ty);
  std::vector<std::pair<int, int>> centers;
  for (int x = 2; x < 44; ++x) {
    float y0 = 6.0f + 0.5f * x, y1 = 6.0f + 0.5f * (x + 1);
    for (int y = static_cast<int>(std::floor(y0)); y <= static_cast<int>(std::floor(y1)); ++y)
      s.cons(x, y, w);
    if (x % 4 == 0) {
      const int y = static_cast<int>(std::floor(6.0f + 0.5f * (x + 0.5f)));
      s.center(x, y, w, 0.6f, 0.3f, 0.1f);
      centers.push_back({x, y});
    }
  }
  const std::vector<cl_float4> promoted = runFilter(s, true), plain = runFilter(s, false);
  int drawn = 0;
  for (int i = 0; i < W * H; ++i) {
    const bool isCenter = s.gbuf[i] != CLH_GBUF_EMPTY;
    if (!isCenter) {
      EXPECT_EQ(plain[i].s[3], 0.0f)
          << "conservative-only pixel " << i << " drawn without promotion";
      continue;
    }
    ++drawn;
    EXPECT_FLOAT_EQ(plain[i].s[3], promoted[i].s[3]);
    EXPECT_GT(plain[i].s[3], 0.0f);
    EXPECT_NEAR(plain[i].s[0] / plain[i].s[3], 0.6f, 1e-4f);
  }
  EXPECT_EQ(drawn, static_cast<int>(centers.size()));
}

TEST(Filter, DensePatchKeepsAlphaOneAndWeightsNormalise) {
  Synthetic s;
  for (int y = 4; y < 28; ++y)
    for (int x = 8; x < 40; ++x)
      s.center(x, y, Synthetic::word(1.2f + 0.0001f * x, 1.0f, 0.0f), 0.25f, 0.5f, 0.75f);
  std::vector<cl_float4> out = runFilter(s);
  for (int y = 4; y < 28; ++y)
    for (int x = 8; x < 40; ++x) {
      const cl_float4& o = out[y * W + x];
      EXPECT_FLOAT_EQ(o.s[3], 1.0f) << x << "," << y;
      // a constant colour stays exactly that colour: the weights sum to one
      EXPECT_NEAR(o.s[0], 0.25f, 1e-6f);
      EXPECT_NEAR(o.s[1], 0.5f, 1e-6f);
      EXPECT_NEAR(o.s[2], 0.75f, 1e-6f);
    }
}

TEST(Filter, NoColourBleedsAcrossADepthEdge) {
  Synthetic s;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      bool left = x < W / 2;
      // red strands in front on the left, blue strands 0.3 behind on the right, all vertical
      s.center(x, y, Synthetic::word(left ? 1.2f : 1.5f, 0.0f, 1.0f), left ? 1.0f : 0.0f, 0.0f,
               left ? 0.0f : 1.0f);
    }
  std::vector<cl_float4> out = runFilter(s);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const cl_float4& o = out[y * W + x];
      if (x < W / 2)
        EXPECT_EQ(o.s[2], 0.0f) << "blue leaked into " << x << "," << y;
      else
        EXPECT_EQ(o.s[0], 0.0f) << "red leaked into " << x << "," << y;
    }
}

TEST(Filter, NearerConservativeStrandIsBlendedOverTheCenterHit) {
  // a dense blue patch behind, one dashed red strand across it in front
  Synthetic s;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) s.center(x, y, Synthetic::word(1.8f, 0.0f, 1.0f), 0.0f, 0.0f, 1.0f);
  const clh_u64 front = Synthetic::word(1.1f, 1.0f, 0.0f);
  for (int x = 0; x < W; ++x) {
    s.cons(x, 16, front);
    if (x % 3 == 0) s.center(x, 16, front, 1.0f, 0.0f, 0.0f);
  }
  std::vector<cl_float4> out = runFilter(s);
  for (int x = 8; x < 40; ++x) {
    const cl_float4& o = out[16 * W + x];
    EXPECT_FLOAT_EQ(o.s[3], 1.0f);
    if (x % 3 != 0) {  // a blue center hit under the red strand: blended, red on top
      EXPECT_GT(o.s[0], 0.0f);
      EXPECT_GT(o.s[2], 0.0f);
    }
  }
  // rows away from the strand stay blue
  EXPECT_EQ(out[5 * W + 20].s[0], 0.0f);
}

}  // namespace
}  // namespace clhair
