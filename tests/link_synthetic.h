// link_synthetic.h — synthetic G-buffers for the link kernels' tests (test_link.cpp,
// test_link_filter.cpp): a G-buffer of CLH_LAYER_LINKED + 1 layers with its shaded centre
// colour, the link passes run over it on the shared device, and strands drawn into it.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "cl/device_impl.h"
#include "clhair/gpu_types.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "stages/link_stage.h"
#include "test_util.h"

namespace clhair {
namespace {  // each test file its own copy

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
}  // namespace clhair
