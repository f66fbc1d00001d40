// cpu_raster.cpp — see cpu_raster.h.
#include "groom/cpu_raster.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <thread>

#include "clhair/error.h"
#include "clhair/gpu_types.h"
#include "clhair/raster_core.h"

namespace clhair {

namespace {

using namespace gpu;

constexpr std::uint32_t kBlockStrands = 64;  // strands a thread takes at once

// Strand s of the stored tables drawn exactly as strands_explicit_raster draws it at full
// detail: point k's tangent is the central difference (k - 1, k + 1), the root's and the
// tip's are the neighbouring tangent reflected about the end segment (Bhokare Eq. 5-6).
void drawStrand(const clh_raster_ctx& base, const ClhGroomGpu& g, const ExplicitData& d,
                const float* depth, std::uint64_t* gbuf, std::uint32_t s, std::vector<float>& tan) {
  const std::uint32_t first = d.strandOffsets[s], n = d.strandOffsets[s + 1] - first;
  if (n < 2) return;
  const glm::vec4* P = d.points.data() + first;
  static const float kUp[3] = {0.0f, 1.0f, 0.0f};
  tan.resize(std::size_t(n) * 3);
  for (std::uint32_t k = 1; k + 1 < n; ++k) {
    float* t = &tan[std::size_t(k) * 3];
    t[0] = P[k + 1].x - P[k - 1].x;
    t[1] = P[k + 1].y - P[k - 1].y;
    t[2] = P[k + 1].z - P[k - 1].z;
    clh_normalize3(t, kUp);
  }
  {  // root
    float q[3] = {P[1].x - P[0].x, P[1].y - P[0].y, P[1].z - P[0].z};
    clh_normalize3(q, kUp);
    float* t = &tan[0];
    const float* t1 = n == 2 ? q : &tan[3];
    t[0] = t1[0];
    t[1] = t1[1];
    t[2] = t1[2];
    clh_end_tangent3(q, t);
  }
  {  // tip
    const std::uint32_t m = n - 1;
    float q[3] = {P[m].x - P[m - 1].x, P[m].y - P[m - 1].y, P[m].z - P[m - 1].z};
    clh_normalize3(q, kUp);
    float* t = &tan[std::size_t(m) * 3];
    const float* tm = n == 2 ? q : &tan[std::size_t(m - 1) * 3];
    float c[3] = {tm[0], tm[1], tm[2]};
    clh_end_tangent3(q, c);
    t[0] = c[0];
    t[1] = c[1];
    t[2] = c[2];
  }

  clh_raster_ctx rc = base;
  float u, v;
  if (!d.uv.empty()) {
    u = static_cast<float>(d.uv[s] & 0xFFFFu) / 65535.0f;
    v = static_cast<float>(d.uv[s] >> 16) / 65535.0f;
  } else {
    const clh_u32 h = clh_hash2(g.seed, s);
    u = clh_u01(h);
    v = clh_u01(clh_hash(h));
  }
  rc.u6 = clh_unorm_bits(u, 6u);
  rc.v6 = clh_unorm_bits(v, 6u);

  clh_u32 counts[4] = {0, 0, 0, 0};
  ClhRasterVertex prev{};
  for (std::uint32_t k = 0; k < n; ++k) {
    ClhRasterVertex cur;
    float o[3];
    clh_xform3(g.obj_to_view, P[k].x, P[k].y, P[k].z, 1.0f, o);
    cur.x = o[0];
    cur.y = o[1];
    cur.z = o[2];
    const float* t = &tan[std::size_t(k) * 3];
    clh_xform3(g.obj_to_world, t[0], t[1], t[2], 0.0f, o);
    cur.tx = o[0];
    cur.ty = o[1];
    cur.tz = o[2];
    cur.ao = 1.0f;
    cur.w = P[k].w;
    cur.u = 0.0f;
    clh_raster_project(&rc, &cur);
    if (k > 0) clh_raster_segment(&rc, depth, gbuf, counts, prev, cur);
    prev = cur;
  }
}

}  // namespace

CpuRasterInputs cpuRasterInputs(const Frame& frame, const ExplicitData& strands) {
  CpuRasterInputs in;
  in.groom = frame.rasterGroom.empty() ? nullptr : frame.rasterGroom.data();
  in.view = frame.rasterView.empty() ? nullptr : frame.rasterView.data();
  in.sceneDepth = frame.rasterDepth.empty() ? nullptr : frame.rasterDepth.data();
  in.strands = &strands;
  return in;
}

void cpuRasterExplicit(const CpuRasterInputs& in, unsigned threads,
                       std::vector<std::uint64_t>& gbuffer) {
  if (!in.groom || !in.view || !in.sceneDepth || !in.strands)
    throw Error("CPU raster: groom, view, scene depth and strands are all needed");
  ClhGroomGpu g;
  ClhViewGpu v;
  std::memcpy(&g, in.groom, sizeof g);
  std::memcpy(&v, in.view, sizeof v);
  const ExplicitData& d = *in.strands;
  const std::uint64_t pixels = std::uint64_t(v.width) * v.height;
  gbuffer.assign(pixels * 2, CLH_GBUF_EMPTY);
  clh_raster_ctx base;
  clh_raster_init(&base, v.fx, v.fy, v.cx, v.cy, v.width, v.height, g.depth_near, g.depth_far,
                  g.strand_width, g.hit_diameter_px);
  const std::uint32_t strands =
      static_cast<std::uint32_t>(d.strandOffsets.empty() ? 0 : d.strandOffsets.size() - 1);
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  std::atomic<std::uint32_t> next{0};
  auto work = [&] {
    std::vector<float> tan;
    for (;;) {
      const std::uint32_t b = next.fetch_add(kBlockStrands);
      if (b >= strands) return;
      const std::uint32_t e = std::min(strands, b + kBlockStrands);
      for (std::uint32_t s = b; s < e; ++s)
        drawStrand(base, g, d, in.sceneDepth, gbuffer.data(), s, tan);
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
}

}  // namespace clhair
