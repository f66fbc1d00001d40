// test_link.cpp — strand identities, hair linking, the alpha fix and the orientation-aware
// filter (Huang et al. 2025; kernels/link.cl, host/stages/link_stage.h).
//
// Synthetic G-buffers drive the link kernels directly, the curve layers filled as the curve
// pass would fill them (one pixel per column on the strand's line): a dashed diagonal strand
// comes out linked along its line only, with alpha = M / (M + N) from its own counts and
// its radiance conserved to 1 %; two crossing strands are each linked along their own line
// with their own identity; nothing is filled past a strand's end or over a filled pixel, nor
// past a nearer strand's pixel, while a walk passes its own drawn pixels and farther strands'
// ones (which count into its N); a hash table too small for the strands turns the rest
// away, counts them and leaves them at alpha 1; the anisotropic filter keeps a uniform
// strand's colour and does not mix two parallel strands two pixels apart, reaches no
// farther than 3 px and, on a hair only a few pixels large, still 1 px (its 2 px floor),
// and in dense hair takes in a little of the row beside a pixel, nothing of rows farther. Rendered
// frames: the identity layer leaves the centre layer word for word as it was and carries the centre
// word's depth; its strands are the groom's (two known strands give two ids, read back from the
// CLI's EXR with OpenImageIO); linking of a sub-pixel strand file keeps the hair's total coverage;
// for a hair mesh the regenerated centre lines of the source strands run through their drawn
// pixels. Tiny sizes: each test takes about a second or two.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "cl/device_impl.h"
#include "clhair/gpu_types.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "io/cyhair.h"
#include "stages/link_stage.h"
#include "test_util.h"

namespace clhair {
namespace {

using namespace gpu;
constexpr int W = 40, H = 36;
constexpr std::size_t kPlane = std::size_t(W) * H;
constexpr clh_u64 kEmpty = CLH_GBUF_EMPTY;
constexpr float kNear = 1.0f, kFar = 2.0f;

// A G-buffer of CLH_LAYER_LINKED + 1 layers and the shaded colour of its centre layer.
struct Synthetic {
  std::vector<clh_u64> gbuf = std::vector<clh_u64>((CLH_LAYER_LINKED + 1) * kPlane, kEmpty);
  std::vector<cl_float4> colour = std::vector<cl_float4>(kPlane, cl_float4{{0, 0, 0, 0}});

  // view space = world space, +y up; a screen direction (sx, sy) with y down is the world
  // tangent (sx, -sy, 0)
  static clh_u64 word(float z, float sx, float sy) {
    return clh_gbuf_pack(clh_depth_encode(z, kNear, kFar), clh_oct_encode(sx, -sy, 0.0f), 10, 20,
                         30, 63);
  }
  static clh_u64 id(float z, clh_u32 strand, float u, clh_u32 linked = 0) {
    return clh_id_pack(clh_depth_encode(z, kNear, kFar), strand, clh_id_pos_code(u), linked);
  }
  clh_u64& at(clh_u32 layer, int x, int y) { return gbuf[layer * kPlane + std::size_t(y) * W + x]; }
  // a pixel the strand pass drew
  void drawn(int x, int y, clh_u32 strand, float u, float z, float sx, float sy, cl_float4 c) {
    at(0, x, y) = word(z, sx, sy);
    at(1, x, y) = word(z, sx, sy);
    at(CLH_LAYER_ID, x, y) = id(z, strand, u);
    colour[std::size_t(y) * W + x] = c;
  }
  // a pixel of the strand's centre line (what the curve pass writes when it is a source)
  void line(int x, int y, clh_u32 strand, float u, float z, float sx, float sy) {
    const clh_u64 w = word(z, sx, sy), i = id(z, strand, u);
    at(CLH_LAYER_CURVE, x, y) = std::min(at(CLH_LAYER_CURVE, x, y), w);
    clh_u64& ci = at(CLH_LAYER_CURVE_ID, x, y);
    if (clh_gbuf_depth(w) < (ci >> 40)) ci = i;
  }
};

struct LinkResult {
  std::vector<clh_u64> gbuf;   // after the merge
  std::vector<cl_float4> out;  // premultiplied RGBA after the alpha fix (and filter)
  LinkCounters counters;
};

// Runs select, propagate, merge, then "shades" every centre word with the colour of its
// strand (shade(strand)) and runs the alpha fix (and the filter when f.aniso).
template <typename Shade>
LinkResult runLink(Synthetic s, const FilterParams& f, Shade shade, PixelRect box = PixelRect{}) {
  Device::Impl& d = *test::sharedDevice().impl();
  ClhGroomGpu groom{};
  groom.depth_near = kNear;
  groom.depth_far = kFar;
  ClhViewGpu view{};
  for (int i = 0; i < 3; ++i) view.world_to_view[i * 4 + i] = view.view_to_world[i * 4 + i] = 1.0f;
  view.fx = view.fy = 40.0f;
  view.cx = W / 2.0f;
  view.cy = H / 2.0f;
  view.width = W;
  view.height = H;
  view.samples = 1;
  auto buf = [&](const void* data, std::size_t bytes) {
    return cl::Buffer(d.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, bytes,
                      const_cast<void*>(data));
  };
  cl::Buffer bg = buf(&groom, sizeof(groom)), bv = buf(&view, sizeof(view));
  cl::Buffer gb = buf(s.gbuf.data(), s.gbuf.size() * 8);
  LinkStage stage(d);
  LinkStage::Params p{{&bv, W, H}, &bg, &gb, 16, CLH_LAYER_LINKED + 1, box};
  stage.select(f, p, nullptr);
  stage.propagate(p, nullptr);
  stage.merge(p, true, nullptr);
  LinkResult r;
  r.gbuf.resize(s.gbuf.size());
  d.queue.enqueueReadBuffer(gb, CL_TRUE, 0, r.gbuf.size() * 8, r.gbuf.data());
  std::vector<cl_float4> colour(kPlane + 3, cl_float4{{-7, -7, -7, -7}});  // canaries past the end
  for (std::size_t i = 0; i < kPlane; ++i)
    if (r.gbuf[i] != kEmpty) colour[i] = shade(clh_id_strand(r.gbuf[CLH_LAYER_ID * kPlane + i]));
  cl::Buffer hair = buf(colour.data(), colour.size() * 16);
  std::vector<cl_float4> canary(kPlane + 3, cl_float4{{-7, -7, -7, -7}});
  cl::Buffer out = buf(canary.data(), canary.size() * 16);
  cl::Buffer* result = stage.finish(p, f.aniso, hair, out, nullptr);
  r.out.resize(kPlane + 3);
  d.queue.enqueueReadBuffer(*result, CL_TRUE, 0, r.out.size() * 16, r.out.data());
  for (std::size_t i = kPlane; i < kPlane + 3; ++i)
    EXPECT_EQ(r.out[i].s[0], -7.0f) << "canary overwritten";
  r.out.resize(kPlane);
  r.counters = stage.counters();
  return r;
}

FilterParams linkOnly() {
  FilterParams f;
  f.method = FilterParams::Method::Huang;
  f.aniso = false;
  return f;
}

const cl_float4 kRed{{0.6f, 0.2f, 0.1f, 1.0f}};
const cl_float4 kBlue{{0.1f, 0.2f, 0.7f, 1.0f}};

// A diagonal strand (screen direction (1, 1)) from (first, first) to (last, last), u from 0
// to 1, drawn where drawnAt(i) says, the rest of its line left for linking.
template <typename Pred>
void diagonal(Synthetic& s, clh_u32 strand, int first, int last, float z, Pred drawnAt) {
  for (int i = first; i <= last; ++i) {
    const float u = float(i - first) / float(last - first);
    s.line(i, i, strand, u, z, 1.0f, 1.0f);
    if (drawnAt(i)) s.drawn(i, i, strand, u, z, 1.0f, 1.0f, kRed);
  }
}

}  // namespace

TEST(Link, DashedDiagonalStrandIsLinkedAlongItsLineWithAlphaMOverMPlusN) {
  Synthetic s;
  const int first = 3, last = 30;
  auto dash = [&](int i) { return (i - first) % 5 < 2 || i == last; };
  diagonal(s, 5, first, last, 1.3f, dash);
  int M = 0;
  for (int i = first; i <= last; ++i) M += dash(i);
  const int N = (last - first + 1) - M;
  const LinkResult r = runLink(s, linkOnly(), [](clh_u32) { return kRed; });
  const float alpha = float(M) / float(M + N);
  double sumBefore = 0.0, sumAfter = 0.0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const std::size_t p = std::size_t(y) * W + x;
      const bool onLine = x == y && x >= first && x <= last;
      SCOPED_TRACE(testing::Message() << "pixel " << x << "," << y);
      if (onLine) {
        ASSERT_NE(r.gbuf[p], kEmpty) << "a gap of the strand stayed empty";
        const clh_u64 id = r.gbuf[CLH_LAYER_ID * kPlane + p];
        EXPECT_EQ(clh_id_strand(id), 5u);
        EXPECT_EQ(clh_id_linked(id), dash(x) ? 0u : 1u);
        EXPECT_NEAR(r.out[p].s[3], alpha, 1e-6f);
        sumBefore += dash(x) ? kRed.s[0] : 0.0f;
      } else {
        EXPECT_EQ(r.gbuf[p], kEmpty) << "filled off the strand's line";
        EXPECT_EQ(r.out[p].s[3], 0.0f);
      }
      sumAfter += r.out[p].s[0];
    }
  EXPECT_EQ(r.counters.filled, std::uint32_t(N));
  EXPECT_EQ(r.counters.strands, 1u);
  EXPECT_EQ(r.counters.turnedAway, 0u);
  EXPECT_NEAR(sumAfter, sumBefore, 0.01 * sumBefore) << "radiance not conserved";
}

TEST(Link, WithoutLinkingTheGapsStayEmptyAndAlphaStaysOne) {
  // the same strand with linking and the alpha fix switched off: what the test above
  // asserts is the feature's doing
  Synthetic s;
  auto dash = [](int i) { return (i - 3) % 5 < 2; };
  diagonal(s, 5, 3, 30, 1.3f, dash);
  FilterParams f = linkOnly();
  f.link = false;
  f.alphaFix = false;
  const LinkResult r = runLink(s, f, [](clh_u32) { return kRed; });
  for (int i = 3; i <= 30; ++i) {
    const std::size_t p = std::size_t(i) * W + i;
    EXPECT_EQ(r.gbuf[p] != kEmpty, dash(i)) << i;
    EXPECT_EQ(r.out[p].s[3], dash(i) ? 1.0f : 0.0f) << i;
  }
  EXPECT_EQ(r.counters.filled, 0u);
}

// Strand 1 down-right along x = y, strand 2 up-right along x + y = 33, nearer; they cross
// between (16, 17) and (17, 16).
Synthetic crossing() {
  Synthetic s;
  for (int i = 4; i <= 29; ++i) {
    const float u = float(i - 4) / 25.0f;
    s.line(i, i, 1, u, 1.6f, 1.0f, 1.0f);
    if (i % 4 == 0 || i == 29) s.drawn(i, i, 1, u, 1.6f, 1.0f, 1.0f, kRed);
    s.line(i, 33 - i, 2, u, 1.2f, 1.0f, -1.0f);
    if (i % 4 == 2 || i == 29) s.drawn(i, 33 - i, 2, u, 1.2f, 1.0f, -1.0f, kBlue);
  }
  return s;
}

TEST(Link, CrossingStrandsAreEachLinkedAlongTheirOwnLine) {
  const Synthetic s = crossing();
  const LinkResult r = runLink(s, linkOnly(), [](clh_u32 k) { return k == 1 ? kRed : kBlue; });
  int linked1 = 0, linked2 = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const std::size_t p = std::size_t(y) * W + x;
      if (r.gbuf[p] == kEmpty) continue;
      const clh_u64 id = r.gbuf[CLH_LAYER_ID * kPlane + p];
      const clh_u32 k = clh_id_strand(id);
      SCOPED_TRACE(testing::Message() << "pixel " << x << "," << y << " strand " << k);
      if (k == 1) {
        EXPECT_EQ(x, y);
        linked1 += clh_id_linked(id);
      } else {
        EXPECT_EQ(k, 2u);
        EXPECT_EQ(x + y, 33);
        linked2 += clh_id_linked(id);
      }
    }
  // every gap of both lines is filled by its own strand
  for (int i = 4; i <= 29; ++i) {
    EXPECT_NE(r.gbuf[std::size_t(i) * W + i], kEmpty) << "strand 1 at " << i;
    EXPECT_NE(r.gbuf[std::size_t(33 - i) * W + i], kEmpty) << "strand 2 at " << i;
  }
  EXPECT_GT(linked1, 15);
  EXPECT_GT(linked2, 15);
  EXPECT_EQ(r.counters.strands, 2u);
}

// The pixels holding a word in any layer: what a groom's screen box must hold, tight.
PixelRect tightBox(const Synthetic& s) {
  PixelRect b{W, H, 0, 0};
  for (std::size_t l = 0; l <= CLH_LAYER_LINKED; ++l)
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x)
        if (s.gbuf[l * kPlane + std::size_t(y) * W + x] != kEmpty)
          b = b.united({x, y, x + 1, y + 1});
  return b;
}

// Strand 3 drawn at its root, its line running on behind a nearer pixel of strand 4;
// strand 6 drawn at its tip (NothingIsFilledPastTheStrandsEndOrOverAFilledPixel).
Synthetic endsAndFilled() {
  Synthetic s;
  // strand 3: drawn at its first two pixels, its line runs on to (24, 24), where it ends; a
  // pixel of strand 4, nearer (z 1.4 against 1.5), sits on the line at (12, 12): strand 3
  // goes behind it there
  for (int i = 2; i <= 24; ++i) {
    const float u = float(i - 2) / 22.0f;
    s.line(i, i, 3, u, 1.5f, 1.0f, 1.0f);
    if (i <= 3) s.drawn(i, i, 3, u, 1.5f, 1.0f, 1.0f, kRed);
  }
  s.drawn(12, 12, 4, 0.5f, 1.4f, 0.0f, 1.0f, kBlue);
  // strand 6: drawn at its last pixel (its tip), nothing beyond it on its line
  for (int i = 4; i <= 8; ++i) s.line(i + 20, 30 - i, 6, float(i - 4) / 4.0f, 1.5f, 1.0f, -1.0f);
  s.drawn(28, 22, 6, 1.0f, 1.5f, 1.0f, -1.0f, kRed);
  s.drawn(27, 23, 6, 0.75f, 1.5f, 1.0f, -1.0f, kRed);
  return s;
}

TEST(Link, NothingIsFilledPastTheStrandsEndOrOverAFilledPixel) {
  const Synthetic s = endsAndFilled();
  const LinkResult r = runLink(s, linkOnly(), [](clh_u32 k) { return k == 4 ? kBlue : kRed; });
  for (int i = 4; i <= 11; ++i)
    EXPECT_EQ(clh_id_strand(r.gbuf[CLH_LAYER_ID * kPlane + std::size_t(i) * W + i]), 3u) << i;
  EXPECT_EQ(clh_id_strand(r.gbuf[CLH_LAYER_ID * kPlane + 12 * W + 12]), 4u) << "overwritten";
  EXPECT_EQ(clh_id_linked(r.gbuf[CLH_LAYER_ID * kPlane + 12 * W + 12]), 0u);
  for (int i = 13; i <= 24; ++i)
    EXPECT_EQ(r.gbuf[std::size_t(i) * W + i], kEmpty) << "filled past a filled pixel at " << i;
  // past the tip of strand 6 (up-right of (28, 22)) nothing
  for (int i = 1; i <= 5; ++i)
    EXPECT_EQ(r.gbuf[std::size_t(22 - i) * W + 28 + i], kEmpty) << "filled past the tip";
  // strand 6's root side is filled down to its first line pixel (24, 26), no further
  EXPECT_NE(r.gbuf[26 * W + 24], kEmpty);
  EXPECT_EQ(r.gbuf[27 * W + 23], kEmpty);
}

TEST(LinkScreenBox, PassesOverTheHairsTightBoxEqualThePassesOverTheWholeImage) {
  // The kernels over the tightest box a groom could have (every pixel holding a word in any
  // layer), each grown by its own margin (link.cl, "Screen boxes"): the G-buffer, the
  // counts and the result inside the box are those of the whole-image passes, which leave
  // 0 outside it. A margin too small fails here: the empty pixels beside a strand's first
  // and last pixels select it (select, propagate: box + 1) and lie on its tangent line,
  // where the filter reads them (the alpha fix: box + 3).
  auto colour = [](clh_u32 k) { return k == 2 || k == 4 ? kBlue : kRed; };
  Synthetic dashed;
  diagonal(dashed, 5, 3, 30, 1.3f, [](int i) { return (i - 3) % 5 < 2 || i == 30; });
  const std::pair<const char*, Synthetic> cases[] = {
      {"dashed diagonal", dashed}, {"crossing strands", crossing()}, {"ends", endsAndFilled()}};
  for (const auto& [name, s] : cases) {
    for (const bool aniso : {true, false}) {
      SCOPED_TRACE(testing::Message() << name << (aniso ? ", filtered" : ", alpha fix"));
      FilterParams f = linkOnly();
      f.aniso = aniso;
      const PixelRect box = tightBox(s);
      ASSERT_TRUE(box.x0 > 0 && box.y0 > 0 && box.x1 < W && box.y1 < H);
      const LinkResult whole = runLink(s, f, colour);
      const LinkResult bounded = runLink(s, f, colour, box);
      EXPECT_GT(whole.counters.filled, 0u);
      EXPECT_EQ(bounded.counters.selecting, whole.counters.selecting);
      EXPECT_EQ(bounded.counters.filled, whole.counters.filled);
      EXPECT_EQ(bounded.counters.strands, whole.counters.strands);
      EXPECT_EQ(bounded.counters.bounds, whole.counters.bounds);
      EXPECT_TRUE(bounded.gbuf == whole.gbuf) << "the G-buffers differ";
      std::size_t differ = 0, outside = 0;
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
          const std::size_t p = std::size_t(y) * W + x;
          if (x >= box.x0 && x < box.x1 && y >= box.y0 && y < box.y1) {
            differ += std::memcmp(&bounded.out[p], &whole.out[p], sizeof(cl_float4)) != 0;
          } else {
            outside += whole.out[p].s[3] != 0.0f || whole.out[p].s[0] != 0.0f;
          }
        }
      EXPECT_EQ(differ, 0u) << "results inside the box differ";
      EXPECT_EQ(outside, 0u) << "the whole-image result is not 0 outside the box";
    }
  }
}

TEST(Link, WalkPassesItsOwnPixelsAndFartherStrandsAndCountsThemForAlpha) {
  Synthetic s;
  // strand 3 along x = y from (2, 2) to (20, 20), z 1.5, drawn at 2, 3 and 14; strand 4, a
  // vertical one behind it (z 1.8), won the centre sample at (8, 8)
  const int first = 2, last = 20;
  auto own = [](int i) { return i == 2 || i == 3 || i == 14; };
  for (int i = first; i <= last; ++i) {
    const float u = float(i - first) / float(last - first);
    s.line(i, i, 3, u, 1.5f, 1.0f, 1.0f);
    if (own(i)) s.drawn(i, i, 3, u, 1.5f, 1.0f, 1.0f, kRed);
  }
  s.drawn(8, 8, 4, 0.5f, 1.8f, 0.0f, 1.0f, kBlue);
  const LinkResult r = runLink(s, linkOnly(), [](clh_u32 k) { return k == 4 ? kBlue : kRed; });
  // past the farther strand's pixel and past its own drawn pixel the walk goes on
  for (int i = first; i <= last; ++i) {
    const std::size_t p = std::size_t(i) * W + i;
    SCOPED_TRACE(testing::Message() << "pixel " << i);
    const clh_u64 id = r.gbuf[CLH_LAYER_ID * kPlane + p];
    if (i == 8) {  // never overwritten: one word a pixel, the sample's strand keeps it
      EXPECT_EQ(clh_id_strand(id), 4u);
      EXPECT_EQ(clh_id_linked(id), 0u);
      continue;
    }
    ASSERT_NE(r.gbuf[p], kEmpty) << "a gap of strand 3 stayed empty";
    EXPECT_EQ(clh_id_strand(id), 3u);
    EXPECT_EQ(clh_id_linked(id), own(i) ? 0u : 1u);
  }
  // M = 3 drawn; N = the 15 filled pixels and (8, 8), where strand 3 passes in front
  const int M = 3, filled = (last - first + 1) - M - 1;
  EXPECT_EQ(r.counters.filled, std::uint32_t(filled));
  const float alpha = float(M) / float(M + filled + 1);
  for (int i = first; i <= last; ++i) {
    if (i != 8) {
      EXPECT_NEAR(r.out[std::size_t(i) * W + i].s[3], alpha, 1e-6f) << i;
    }
  }
}

TEST(Link, AlphaFixBlendsLinkedPixelsOverTheBackgroundAndDrawnOnesOverTheirNeighbours) {
  Synthetic s;
  // the dashed diagonal strand 5, and beside it (one pixel to the right) a fully drawn blue
  // strand 9: a linked pixel of strand 5 saw the background, so behind its alpha there is
  // nothing (the scene, at compositing); a drawn pixel saw only strand 5, so behind it lies
  // the mean of its other neighbours, blue strand 9 among them
  const int first = 3, last = 30;
  auto dash = [&](int i) { return (i - first) % 5 < 2 || i == last; };
  diagonal(s, 5, first, last, 1.3f, dash);
  for (int i = first; i <= last; ++i)
    s.drawn(i + 1, i, 9, float(i - first) / float(last - first), 1.3f, 1.0f, 1.0f, kBlue);
  const LinkResult r = runLink(s, linkOnly(), [](clh_u32 k) { return k == 9 ? kBlue : kRed; });
  int M = 0;
  for (int i = first; i <= last; ++i) M += dash(i);
  const float alpha = float(M) / float(last - first + 1);
  int linked = 0;
  for (int i = first + 1; i < last; ++i) {
    const std::size_t p = std::size_t(i) * W + i;
    SCOPED_TRACE(testing::Message() << "pixel " << i);
    ASSERT_EQ(clh_id_strand(r.gbuf[CLH_LAYER_ID * kPlane + p]), 5u);
    if (!dash(i)) {  // exactly the strand's share, nothing of strand 9
      ++linked;
      EXPECT_NEAR(r.out[p].s[3], alpha, 1e-6f);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.out[p].s[c], alpha * kRed.s[c], 1e-6f) << c;
    } else {  // strand 9 shows behind it: more blue and more cover than the share alone
      EXPECT_GT(r.out[p].s[2], alpha * kRed.s[2] + 0.05f);
      EXPECT_GT(r.out[p].s[3], alpha + 0.05f);
    }
  }
  EXPECT_GT(linked, 10);
}

TEST(Link, AFullHashTableTurnsStrandsAwayCountedAndLeavesThemAtAlphaOne) {
  Synthetic s;
  // two dashed horizontal strands, rows 10 and 20
  for (int x = 2; x <= 33; ++x) {
    const float u = float(x - 2) / 31.0f;
    for (clh_u32 k : {7u, 8u}) {
      const int y = k == 7u ? 10 : 20;
      s.line(x, y, k, u, 1.5f, 1.0f, 0.0f);
      if (x % 3 == 0) s.drawn(x, y, k, u, 1.5f, 1.0f, 0.0f, kRed);
    }
  }
  FilterParams f = linkOnly();
  f.linkTable = 1;  // room for one strand
  const LinkResult r = runLink(s, f, [](clh_u32) { return kRed; });
  EXPECT_EQ(r.counters.strands, 1u);
  EXPECT_GT(r.counters.turnedAway, 0u) << "an overflow went uncounted";
  // one strand has its alpha fix, the other keeps alpha 1 on every pixel (linked ones too)
  int fixed = 0, kept = 0;
  for (int y : {10, 20}) {
    float a = r.out[std::size_t(y) * W + 9].s[3];
    for (int x = 3; x <= 32; ++x) EXPECT_EQ(r.out[std::size_t(y) * W + x].s[3], a) << x << "," << y;
    fixed += a < 0.5f;
    kept += a == 1.0f;
  }
  EXPECT_EQ(fixed, 1);
  EXPECT_EQ(kept, 1);
}

TEST(Link, AnisotropicFilterSmoothsAlongAStrandAndDoesNotMixParallelStrands) {
  Synthetic s;
  const cl_float4 dark{{0.2f, 0.2f, 0.2f, 1.0f}}, bright{{0.6f, 0.6f, 0.6f, 1.0f}};
  for (int x = 2; x <= 37; ++x) {
    const float u = float(x - 2) / 35.0f;
    s.drawn(x, 14, 1, u, 1.5f, 1.0f, 0.0f, kRed);
    s.drawn(x, 16, 2, u, 1.5f, 1.0f, 0.0f, kBlue);
    s.drawn(x, 25, 3 + (x & 1), u, 1.5f, 1.0f, 0.0f, dark);  // a noisy strand: two "ids"
  }
  FilterParams f = linkOnly();
  f.aniso = true;
  f.sigmaD = 1.0f;   // a wide kernel, so the normalisation and the ellipse matter
  f.kernelK = 0.2f;  // r = 0.2 sqrt(36 * 12) ~ 4 px, clamped to 3
  const LinkResult r = runLink(
      s, f, [&](clh_u32 k) { return k == 1 ? kRed : (k == 2 ? kBlue : (k == 3 ? bright : dark)); });
  // away from the strands' ends (past the kernel's reach: the ends fade into the empty
  // pixels past them, as the matte's filter does)
  for (int x = 8; x <= 31; ++x) {
    const cl_float4 a = r.out[14 * W + x], b = r.out[16 * W + x];
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(a.s[c], kRed.s[c], 2e-3f) << "red strand at " << x;
      EXPECT_NEAR(b.s[c], kBlue.s[c], 2e-3f) << "blue strand at " << x;
    }
    EXPECT_NEAR(a.s[3], 1.0f, 1e-5f);
  }
  // along the noisy strand: the alternation shrinks, the mean stays
  float lo = 1.0f, hi = 0.0f;
  double mean = 0.0;
  for (int x = 8; x <= 31; ++x) {
    const float v = r.out[25 * W + x].s[0];
    lo = std::min(lo, v);
    hi = std::max(hi, v);
    mean += v / 24.0;
  }
  EXPECT_LT(hi - lo, 0.2f) << "not smoothed along the strand (input spread 0.4)";
  EXPECT_NEAR(mean, 0.4, 0.02);
}

// A horizontal strand at y = 20 from x = 4 to 36, red with one blue pixel (strand 2) at x = 24.
Synthetic strandWithOddPixel() {
  Synthetic s;
  for (int x = 4; x <= 36; ++x)
    s.drawn(x, 20, x == 24 ? 2 : 1, float(x - 4) / 32.0f, 1.5f, 1.0f, 0.0f, x == 24 ? kBlue : kRed);
  return s;
}

TEST(Link, AnisotropicKernelReachesAtMostThreePixels) {
  // a horizontal strand of one colour with one differently coloured pixel at x = 24; the
  // screen box asks for a far longer kernel (k = 1), which is clamped to r = 3 px: the
  // pixel 2 px from the odd one takes some of it, the pixel 4 px away none
  const Synthetic s = strandWithOddPixel();
  FilterParams f = linkOnly();
  f.aniso = true;
  f.kernelK = 1.0f;
  const LinkResult r = runLink(s, f, [](clh_u32 k) { return k == 2 ? kBlue : kRed; });
  for (int c = 0; c < 4; ++c) {
    EXPECT_FLOAT_EQ(r.out[20 * W + 20].s[c], kRed.s[c]) << "reached 4 px, channel " << c;
    EXPECT_FLOAT_EQ(r.out[20 * W + 28].s[c], kRed.s[c]) << "reached 4 px, channel " << c;
  }
  EXPECT_GT(r.out[20 * W + 22].s[2], kRed.s[2] + 0.01f) << "no reach at 2 px";
  EXPECT_GT(r.out[20 * W + 26].s[2], kRed.s[2] + 0.01f) << "no reach at 2 px";
}

TEST(Link, AnisotropicKernelReachesTwoPixelsOnAHairOfAFewPixels) {
  // the same strand with its odd pixel, but a screen box that asks for r far below a pixel
  // (k = 0.001): the kernel keeps its floor of 2 px, so the odd pixel's neighbours along the
  // strand take some of it (below 2 px the ellipse would hold only P) and 3 px away nothing
  const Synthetic s = strandWithOddPixel();
  FilterParams f = linkOnly();
  f.aniso = true;
  f.kernelK = 0.001f;
  const LinkResult r = runLink(s, f, [](clh_u32 k) { return k == 2 ? kBlue : kRed; });
  for (int x : {23, 25}) {
    EXPECT_GT(r.out[20 * W + x].s[2], kRed.s[2] + 0.05f) << "no reach at 1 px, x = " << x;
    EXPECT_NEAR(r.out[20 * W + x].s[3], 1.0f, 1e-5f);
  }
  for (int c = 0; c < 4; ++c) {
    EXPECT_FLOAT_EQ(r.out[20 * W + 21].s[c], kRed.s[c]) << "reached 3 px, channel " << c;
    EXPECT_FLOAT_EQ(r.out[20 * W + 27].s[c], kRed.s[c]) << "reached 3 px, channel " << c;
  }
}

TEST(Link, AnisotropicKernelAveragesTheRowsBesideAStrandInDenseHair) {
  // dense hair, every pixel drawn with a horizontal tangent: red rows with one blue row
  // (21). With the default aspect ratio (minor axis r / 2) and sigma_theta (0.6 rad) the
  // ellipse of a red pixel next to it takes in the blue row's pixels at 27-45 degrees from
  // the tangent, so a little blue comes in; the pixel straight across (90 degrees) adds
  // next to nothing, and two rows away the red stays red
  Synthetic s;
  for (int y = 14; y <= 26; ++y)
    for (int x = 4; x <= 36; ++x)
      s.drawn(x, y, y == 21 ? 2 : 1, float(x - 4) / 32.0f, 1.5f, 1.0f, 0.0f,
              y == 21 ? kBlue : kRed);
  FilterParams f = linkOnly();
  f.aniso = true;
  f.kernelK = 0.2f;  // r = 0.2 sqrt(33 * 13) ~ 4 px, clamped to 3
  const LinkResult r = runLink(s, f, [](clh_u32 k) { return k == 2 ? kBlue : kRed; });
  for (int x = 10; x <= 30; ++x) {
    SCOPED_TRACE(testing::Message() << "x = " << x);
    const cl_float4 beside = r.out[20 * W + x], apart = r.out[19 * W + x];
    EXPECT_GT(beside.s[2], kRed.s[2] + 0.02f) << "the row beside the blue one took none of it";
    EXPECT_LT(beside.s[2], kRed.s[2] + 0.1f) << "more than the diagonal neighbours' share";
    EXPECT_NEAR(beside.s[3], 1.0f, 1e-5f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(apart.s[c], kRed.s[c], 1e-5f) << "two rows away";
  }
}

// ---- rendered frames ---------------------------------------------------------------------

namespace {

// Two straight strands: 0 vertical on the left, 1 slanted on the right, root at the bottom.
Scene twoStrands(float width) {
  StrandGroom g;
  g.name = "two";
  g.appearance.strandWidth = width;
  for (int s = 0; s < 2; ++s) {
    g.pointCounts.push_back(9);
    for (int k = 0; k < 9; ++k)
      g.points.emplace_back(-0.03f + 0.06f * s + 0.004f * s * k, -0.05f + 0.0125f * k, 0.0f);
  }
  Scene sc;
  sc.width = 48;
  sc.height = 40;
  sc.camera.position = glm::vec3(0.0f, 0.0f, 0.3f);
  sc.camera.target = glm::vec3(0.0f);
  sc.camera.fovYDegrees = 35.0f;
  Light l;
  l.direction = glm::normalize(glm::vec3(0.3f, 1.0f, 0.6f));
  sc.lights.push_back(l);
  sc.grooms.push_back(GroomInstance("two", std::make_shared<const StrandGroom>(std::move(g))));
  return sc;
}

}  // namespace

TEST(StrandId, IdentityLayerLeavesTheCentreLayerAndNamesItsStrands) {
  Renderer r(test::sharedDevice());
  for (const bool mesh : {false, true}) {
    SCOPED_TRACE(mesh ? "hair mesh" : "strand file");
    Scene s = twoStrands(0.004f);
    std::uint32_t total = 2;
    if (mesh) {
      auto m = std::make_shared<const HairMesh>(
          loadHairMesh(test::assetPath("grooms/tiny.hairmesh.json")));
      total = static_cast<std::uint32_t>(m->strandCount);
      s.grooms[0] = GroomInstance("tiny", m);
      s.camera.position = glm::vec3(0.0f, 0.03f, 0.2f);
      s.camera.target = glm::vec3(0.0f, 0.025f, 0.0f);
    }
    RenderOptions o;
    o.filter = 0;
    o.captureGBuffer = true;
    const Frame plain = r.render(s, o);
    o.aovs = true;
    o.strandIds = true;
    const Frame ided = r.render(s, o);
    ASSERT_EQ(plain.gbufferLayers, 2);
    ASSERT_EQ(ided.gbufferLayers, int(CLH_LAYER_ID) + 1);
    const std::size_t pixels = std::size_t(s.width) * s.height;
    std::size_t hits = 0;
    std::set<std::uint32_t> strands;
    for (std::size_t p = 0; p < pixels; ++p) {
      ASSERT_EQ(ided.gbuffer[p], plain.gbuffer[p]) << "centre word changed at " << p;
      ASSERT_EQ(ided.gbuffer[pixels + p], plain.gbuffer[pixels + p]) << "conservative at " << p;
      const std::uint64_t id = ided.gbuffer[CLH_LAYER_ID * pixels + p];
      ASSERT_EQ(id == kEmpty, plain.gbuffer[p] == kEmpty) << p;
      if (id == kEmpty) {
        EXPECT_EQ(ided.aovs.strand[p * 3 + 1], -1.0f);
        continue;
      }
      ++hits;
      EXPECT_EQ(clh_gbuf_depth(ided.gbuffer[p]), clh_gbuf_depth(id)) << p;
      EXPECT_EQ(clh_id_linked(id), 0u);
      strands.insert(clh_id_strand(id));
      EXPECT_EQ(ided.aovs.strand[p * 3 + 1], float(clh_id_strand(id)));
      EXPECT_EQ(ided.aovs.strand[p * 3], 0.0f);
    }
    EXPECT_GT(hits, 10u);
    if (!mesh) {
      EXPECT_EQ(strands, (std::set<std::uint32_t>{0u, 1u}));
    } else {
      EXPECT_GT(strands.size(), 10u);
      EXPECT_LT(*strands.rbegin(), total);
    }
  }
}

TEST(Link, RenderedSubPixelStrandIsLinkedWithItsCoverageKept) {
  // strand 1 of twoStrands at a fifth of a pixel's width hits a pixel centre every few rows
  Renderer r(test::sharedDevice());
  const Scene s = twoStrands(0.001f);
  FilterParams f;
  f.method = FilterParams::Method::Huang;
  f.aniso = false;
  Scene linked = s, unlinked = s;
  linked.filter = f;
  f.link = false;
  f.alphaFix = false;
  unlinked.filter = f;
  RenderOptions o;
  o.aovs = true;
  o.trueWidth = true;  // the strand at its width, not widened as a faint groom (faint_groom.h)
  const Frame a = r.render(linked, o), b = r.render(unlinked, o);
  EXPECT_GT(a.stats.linkedPixels, 5u);
  EXPECT_EQ(b.stats.linkedPixels, 0u);
  double coverageA = 0.0, coverageB = 0.0;
  std::size_t pixelsA = 0, pixelsB = 0;
  for (std::size_t p = 0; p < a.aovs.hairAlpha.size(); ++p) {
    coverageA += a.aovs.hairAlpha[p];
    coverageB += b.aovs.hairAlpha[p];
    pixelsA += a.aovs.hairAlpha[p] > 0.0f;
    pixelsB += b.aovs.hairAlpha[p] > 0.0f;
  }
  EXPECT_GT(pixelsB, 3u);
  EXPECT_GT(pixelsA, pixelsB + 5) << "linking filled nothing";
  EXPECT_NEAR(coverageA, coverageB, 0.01 * coverageB) << "the alpha fix did not keep coverage";
}

TEST(Link, DefaultFilterIsHuangsInAFrameOfOneViewAndLippsWhenNamed) {
  // DESIGN.md, "The default filter": "auto" is Huang's filter in a frame of one view at
  // MSAA 1 with the lines raster (a strand file here: its curve pass reads the strand);
  // Lipp's when the scene or the option names it
  Renderer r(test::sharedDevice());
  const Scene s = twoStrands(0.001f);
  EXPECT_EQ(s.filter.method, FilterParams::Method::Auto);
  Scene huang = s, lipp = s;
  huang.filter.method = FilterParams::Method::Huang;
  lipp.filter.method = FilterParams::Method::Lipp;
  RenderOptions o;
  o.trueWidth = true;  // the strand at its width, not widened as a faint groom (faint_groom.h)
  const Frame byDefault = r.render(s, o), named = r.render(huang, o), lipps = r.render(lipp, o);
  EXPECT_GT(byDefault.stats.linkSelecting, 0u);
  EXPECT_GT(byDefault.stats.linkedPixels, 5u);
  EXPECT_EQ(byDefault.color.rgba, named.color.rgba) << "the default is not Huang's filter";
  EXPECT_EQ(lipps.stats.linkSelecting, 0u);
  EXPECT_NE(byDefault.color.rgba, lipps.color.rgba);
  RenderOptions lippOption = o;  // --filter lipp over the scene's "auto"
  lippOption.filterMethod = 0;
  EXPECT_EQ(r.render(s, lippOption).color.rgba, lipps.color.rgba);
  // a crowd: "auto" stays Huang's however many groom instances (each one's linking runs over
  // its screen box); by name Lipp's stays Lipp's
  Scene five = s, fiveLipp = lipp;
  five.grooms.assign(5, s.grooms[0]);
  fiveLipp.grooms.assign(5, s.grooms[0]);
  EXPECT_GT(r.render(five, o).stats.linkSelecting, 0u);
  EXPECT_EQ(r.render(fiveLipp, o).stats.linkSelecting, 0u);
  // MSAA 4 and the coverage raster (no filter): Views.EachViewIsTheSingleViewRenderAtMsaa4
  // and Coverage.FrontoParallelStrandHasTheStripsCoverageAndAlphaProfile, in frames those
  // tests render anyway
}

TEST(Link, SourceStrandsCentreLinesRunThroughTheirDrawnPixels) {
  // the curve pass regenerates (hair mesh) or reads (strand file) the source strands from
  // their identity: their centre lines must be those strands
  Renderer r(test::sharedDevice());
  for (const bool mesh : {true, false}) {
    SCOPED_TRACE(mesh ? "hair mesh" : "strand file");
    Scene s = twoStrands(0.001f);
    if (mesh) {
      s.grooms[0] = GroomInstance("tiny", std::make_shared<const HairMesh>(loadHairMesh(
                                              test::assetPath("grooms/tiny.hairmesh.json"))));
      s.camera.position = glm::vec3(0.0f, 0.03f, 0.25f);
      s.camera.target = glm::vec3(0.0f, 0.025f, 0.0f);
      s.width = 96;
      s.height = 72;
    }
    s.filter.method = FilterParams::Method::Huang;
    s.filter.aniso = false;
    RenderOptions o;
    o.filter = 1;
    o.lod = 0;
    o.captureGBuffer = true;
    o.trueWidth = true;  // not widened as a faint groom (faint_groom.h): linking has gaps
    const Frame f = r.render(s, o);
    ASSERT_EQ(f.gbufferLayers, int(CLH_LAYER_LINKED) + 1);
    EXPECT_GT(f.stats.linkedPixels, 0u);
    const int w = s.width, h = s.height;
    const std::size_t plane = std::size_t(w) * h;
    std::set<std::uint32_t> sources;
    for (std::size_t p = 0; p < plane; ++p) {
      const std::uint64_t c = f.gbuffer[CLH_LAYER_CURVE_ID * plane + p];
      if (c != kEmpty) sources.insert(clh_id_strand(c));
    }
    ASSERT_FALSE(sources.empty());
    // where a source strand's centre line crosses a pixel it drew, both words name it at
    // the same place along it: the line is that strand, regenerated or read
    std::size_t same = 0, agree = 0;
    for (std::size_t p = 0; p < plane; ++p) {
      const std::uint64_t id = f.gbuffer[CLH_LAYER_ID * plane + p];
      const std::uint64_t c = f.gbuffer[CLH_LAYER_CURVE_ID * plane + p];
      if (id == kEmpty || c == kEmpty || clh_id_linked(id) || clh_id_strand(c) != clh_id_strand(id))
        continue;
      ++same;
      agree += std::abs(int(clh_id_pos(c)) - int(clh_id_pos(id))) <= 330;  // 1 % of its length
    }
    EXPECT_GE(same, 5u);
    EXPECT_EQ(agree, same);
    // and the linked pixels lie on their strand's line
    std::size_t linked = 0;
    for (std::size_t p = 0; p < plane; ++p) {
      const std::uint64_t id = f.gbuffer[CLH_LAYER_ID * plane + p];
      if (id == kEmpty || !clh_id_linked(id)) continue;
      ++linked;
      EXPECT_EQ(clh_id_strand(f.gbuffer[CLH_LAYER_CURVE_ID * plane + p]), clh_id_strand(id));
    }
    EXPECT_EQ(linked, f.stats.linkedPixels);
  }
}

TEST(StrandId, CliWritesTwoKnownStrandsAsTwoIdsWithUFromRootToTip) {
  const std::string dir = test::scratchDir();
  const Scene still = twoStrands(0.004f);
  CyHair hair;
  for (std::uint32_t n : still.grooms[0].strands->pointCounts) hair.segments.push_back(n - 1);
  for (const glm::vec3& q : still.grooms[0].strands->points)
    hair.points.insert(hair.points.end(), {q.x, q.y, q.z});
  writeCyHair(hair, dir + "/two.hair");
  const nlohmann::json scene = {
      {"resolution", {48, 40}},
      {"camera", {{"position", {0.0, 0.0, 0.3}}, {"target", {0.0, 0.0, 0.0}}, {"fov", 35}}},
      {"lights", {{{"type", "directional"}, {"direction", {0.3, 1.0, 0.6}}}}},
      {"grooms", {{{"strands_file", "two.hair"}, {"appearance", {{"strand_width", 0.004}}}}}}};
  std::ofstream(dir + "/scene.json") << scene.dump(2);
  const test::CommandResult run =
      test::runCli("render " + test::quote(dir + "/scene.json") + " -q --aov strand -o " +
                   test::quote(dir + "/s.exr"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  auto in = OIIO::ImageInput::open(dir + "/s.exr");
  ASSERT_TRUE(in) << OIIO::geterror();
  const OIIO::ImageSpec spec = in->spec();
  ASSERT_EQ(spec.width, 48);
  std::map<std::string, int> channel;
  for (int c = 0; c < spec.nchannels; ++c) channel[spec.channelnames[c]] = c;
  for (const char* name : {"strand.groom", "strand.id", "strand.u"}) {
    ASSERT_EQ(channel.count(name), 1u) << name;
    EXPECT_EQ(spec.channelformat(channel[name]), OIIO::TypeDesc::FLOAT) << name;
  }
  std::vector<float> px(std::size_t(spec.width) * spec.height * spec.nchannels);
  ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
  auto value = [&](int x, int y, const char* name) {
    return px[(std::size_t(y) * spec.width + x) * spec.nchannels + channel[name]];
  };
  std::map<int, int> count;
  std::map<int, std::pair<float, float>> lowUpper;  // per id: u at its lowest and highest row
  for (int y = 0; y < spec.height; ++y)
    for (int x = 0; x < spec.width; ++x) {
      const float id = value(x, y, "strand.id");
      ASSERT_TRUE(id == -1.0f || id == 0.0f || id == 1.0f) << id;
      if (id < 0.0f) {
        EXPECT_EQ(value(x, y, "strand.groom"), -1.0f);
        continue;
      }
      ++count[int(id)];
      EXPECT_EQ(value(x, y, "strand.groom"), 0.0f);
      EXPECT_EQ(x < 24, id == 0.0f) << "strand 0 is the left one, at " << x << "," << y;
      const float u = value(x, y, "strand.u");
      if (!lowUpper.count(int(id))) lowUpper[int(id)] = {u, u};
      lowUpper[int(id)].second = u;  // rows run top to bottom: the last is the lowest
    }
  EXPECT_GT(count[0], 10);
  EXPECT_GT(count[1], 10);
  for (const auto& [id, u] : lowUpper) EXPECT_GT(u.first, u.second + 0.5f) << "tip above root";
}

}  // namespace clhair
