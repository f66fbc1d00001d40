// test_lod.cpp — the LOD formulas (Lipp Eq. 1-5, Bhokare Eq. 10-12) against hand-computed
// values, the LOD record's bytes and the scan kernel against a CPU scan (both laid out in
// gpu_types.h), the LOD kernel's culling, delta staggering, vertex-LOD morph continuity,
// and LOD's effect on coverage at a distance.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "cl/device_impl.h"
#include "clhair/lod_math.h"
#include "clhair/renderer.h"
#include "groom/groom_data.h"
#include "groom/presets.h"
#include "test_util.h"

namespace clhair {
namespace {

using namespace gpu;

TEST(LodMath, LodValueEquation2) {
  // 300 x 400 px AABB: diagonal 500 px; R_y = 1000, lambda = 1 -> 0.5
  EXPECT_FLOAT_EQ(clh_lod_value(300.0f, 400.0f, 1000.0f, 1.0f), 0.5f);
  EXPECT_FLOAT_EQ(clh_lod_value(300.0f, 400.0f, 1000.0f, 3.0f), 1.0f);  // clamped
  EXPECT_FLOAT_EQ(clh_lod_value(6.0f, 8.0f, 1080.0f, 2.7f), 10.0f / 1080.0f * 2.7f);
  EXPECT_FLOAT_EQ(clh_lod_value(0.0f, 0.0f, 1080.0f, 3.0f), 0.0f);
}

TEST(LodMath, StrandCountEquation1) {
  // ceil(L (N + delta)), clamped to [1, N]
  EXPECT_EQ(clh_lod_strands(0.5f, 100, 0.0f), 50u);
  EXPECT_EQ(clh_lod_strands(0.5f, 100, 0.9f), 51u);    // ceil(50.45)
  EXPECT_EQ(clh_lod_strands(0.001f, 100, 0.3f), 1u);   // at least one strand
  EXPECT_EQ(clh_lod_strands(1.0f, 100, 0.99f), 100u);  // at most N
  EXPECT_EQ(clh_lod_strands(0.25f, 0, 0.5f), 0u);      // empty bundles stay empty
  EXPECT_EQ(clh_lod_strands(0.3f, 10, 0.5f), 4u);      // ceil(3.15)
}

TEST(LodMath, ControlPointSnappingEquations4And5) {
  // C_raw = max(floor(sqrt(L) * C_max), layers); C = 2^ceil(log2(C_raw - 1)) + 1, C_max = 129
  struct Case {
    float L;
    unsigned layers, expected;
  };
  const Case cases[] = {
      {1.0f, 8, 129},                           // full detail
      {0.25f, 8, 65},                           // floor(64.5) = 64 -> 65
      {(65.0f / 129) * (65.0f / 129), 8, 65},   // C_raw 65 -> 65 exactly
      {(66.0f / 129) * (66.0f / 129), 8, 129},  // C_raw 66 -> 129
      {0.0625f, 8, 33},                         // floor(32.25) = 32 -> 33
      {0.0f, 8, 9},                             // layers bound 8 -> 9
      {0.0f, 2, 3},                             // at least 3
      {0.0f, 12, 17},                           // 12 layers -> 17
      {0.01f, 12, 17},                          // floor(12.9) = 12 -> 17
  };
  for (const Case& c : cases)
    EXPECT_EQ(clh_lod_control_points(c.L, c.layers, 129), c.expected)
        << "L = " << c.L << " layers = " << c.layers;
  // the snapping table itself
  const unsigned raw[] = {3, 4, 5, 6, 9, 10, 17, 18, 33, 34, 65, 66, 129};
  const unsigned snapped[] = {3, 5, 5, 9, 9, 17, 17, 33, 33, 65, 65, 129, 129};
  for (int i = 0; i < 13; ++i) EXPECT_EQ(clh_lod_snap(raw[i], 129), snapped[i]) << raw[i];
  EXPECT_EQ(clh_lod_snap(100, 65), 65u);  // never above the groom's full detail
  EXPECT_EQ(clh_lod_control_points(1.0f, 8, 65), 65u);
}

TEST(LodMath, MorphFactorIsOneExactlyWhereTheLevelSwitches) {
  // C switches 65 -> 33 when floor(sqrt(L) 129) drops from 34 to 33
  const float window = 0.5f;
  float Lswitch = (34.0f / 129.0f) * (34.0f / 129.0f);
  EXPECT_EQ(clh_lod_control_points(Lswitch * 1.0001f, 8, 129), 65u);
  EXPECT_EQ(clh_lod_control_points(Lswitch * 0.9999f, 8, 129), 33u);
  EXPECT_NEAR(clh_lod_morph(Lswitch * 1.0001f, 8, 129, window), 1.0f, 1e-3f);
  // halfway through the level (log2 scale) the morph is over
  float Lmid = std::pow((std::pow(2.0f, 5.6f) + 2.0f) / 129.0f, 2.0f);
  EXPECT_EQ(clh_lod_control_points(Lmid, 8, 129), 65u);
  EXPECT_FLOAT_EQ(clh_lod_morph(Lmid, 8, 129, window), 0.0f);
  // inside the window gamma falls linearly in log2(c - 2)
  float Lq = std::pow((std::pow(2.0f, 5.25f) + 2.0f) / 129.0f, 2.0f);
  EXPECT_NEAR(clh_lod_morph(Lq, 8, 129, window), 0.5f, 1e-3f);
  // never toward a level below the layer count
  EXPECT_EQ(clh_lod_morph(Lswitch * 1.0001f, 40, 129, window), 0.0f);
  EXPECT_EQ(clh_lod_morph(1.0f, 8, 129, window), 0.0f);
}

TEST(LodMath, DeltaStaggersTransitions) {
  // As L decreases slowly every bundle loses at most one strand per step, and the
  // per-bundle offsets spread the losses over many steps. Eq. 1 scales delta by L, so the
  // spread covers a fraction L of each unit step of L N: at L >= 0.5 a step that moves
  // L N by 0.135 changes about 0.135 / L of the bundles, never all of them; without delta
  // every bundle changes on the same step.
  const int bundles = 400;
  const std::uint32_t N = 300;
  std::vector<float> delta(bundles);
  for (int b = 0; b < bundles; ++b)
    delta[b] = clh_u01(clh_hash3(1u, static_cast<std::uint32_t>(b), CLH_RNG_LOD_DELTA));
  auto sweep = [&](bool useDelta, float Lmin) {
    std::vector<std::uint32_t> prev(bundles);
    for (int b = 0; b < bundles; ++b)
      prev[b] = clh_lod_strands(1.0f, N, useDelta ? delta[b] : 0.0f);
    int worst = 0;
    for (int step = 1;; ++step) {
      float L = 1.0f - 4.5e-4f * step;
      if (L < Lmin) break;
      int changed = 0;
      for (int b = 0; b < bundles; ++b) {
        std::uint32_t n = clh_lod_strands(L, N, useDelta ? delta[b] : 0.0f);
        EXPECT_LE(prev[b] - n, 1u) << "bundle " << b << " at L " << L;
        changed += n != prev[b];
        prev[b] = n;
      }
      worst = std::max(worst, changed);
    }
    return worst;
  };
  int staggered = sweep(true, 0.5f);
  EXPECT_LT(staggered, bundles * 2 / 5);
  EXPECT_EQ(sweep(false, 0.5f), bundles);
  sweep(true, 0.05f);  // per-bundle changes stay at one strand down to small L
}

TEST(LodRecord, HelpersFillTheDocumentedBytes) {
  // the table in gpu_types.h: N_LOD and C as uint32, then the widening and gamma as floats
  const ClhLodRecord r = clh_lod_record_make(7u, 33u, clh_lod_widening(28u, 7u), 0.5f);
  std::uint32_t words[4];
  static_assert(sizeof(words) == sizeof(r), "four 32-bit words");
  std::memcpy(words, &r, sizeof words);
  EXPECT_EQ(words[0], 7u);
  EXPECT_EQ(words[1], 33u);
  EXPECT_EQ(words[2], 0x40800000u);  // 4.0f = 28 / 7
  EXPECT_EQ(words[3], 0x3F000000u);  // 0.5f
  // the hit-diameter widening N / N_LOD, never below 1, and 1 for a bundle drawing nothing
  EXPECT_EQ(clh_lod_record_coverage(r), 4.0f);
  EXPECT_EQ(clh_lod_widening(5u, 7u), 1.0f);
  EXPECT_EQ(clh_lod_record_coverage(clh_lod_record_make(7u, 33u, 0.5f, 0.0f)), 1.0f);
  EXPECT_EQ(clh_lod_record_coverage(clh_lod_record_make(0u, 33u, 4.0f, 0.0f)), 1.0f);
}

TEST(LodRecord, FixedLevelRecordFollowsTheEquations) {
  // full detail: every strand, C_max points, no morph
  const ClhLodRecord full = clh_lod_record_at(1.0f, 300u, 0.4f, 8u, 129u, 0.5f);
  EXPECT_EQ(full.strands, 300u);
  EXPECT_EQ(full.control_points, 129u);
  EXPECT_EQ(full.coverage, 1.0f);
  EXPECT_EQ(full.gamma, 0.0f);
  // inside a transition window (gamma 0.5, as in MorphFactorIsOneExactlyWhereTheLevelSwitches)
  const float Lq = std::pow((std::pow(2.0f, 5.25f) + 2.0f) / 129.0f, 2.0f);
  for (float L : {0.6f, 0.3f, Lq, 0.05f}) {
    const ClhLodRecord r = clh_lod_record_at(L, 300u, 0.4f, 8u, 129u, 0.5f);
    EXPECT_EQ(r.strands, clh_lod_strands(L, 300u, 0.4f)) << L;
    EXPECT_EQ(r.control_points, clh_lod_control_points(L, 8u, 129u)) << L;
    EXPECT_EQ(r.coverage, 300.0f / static_cast<float>(r.strands)) << L;
    EXPECT_EQ(r.gamma, clh_lod_morph(L, 8u, 129u, 0.5f)) << L;
  }
  EXPECT_NEAR(clh_lod_record_at(Lq, 300u, 0.4f, 8u, 129u, 0.5f).gamma, 0.5f, 1e-3f);
}

// scan_bundles against a CPU scan for bundle counts around the work-group size: the
// exclusive scan, the drawn, visible and segment totals at the indices gpu_types.h names, and
// nothing written past clh_lod_offsets_length(n).
TEST(LodScan, OffsetsMatchACpuScanAtTheNamedIndices) {
  auto& d = *test::sharedDevice().impl();
  constexpr std::uint32_t kScanWg = 256;  // the kernel's default, as the LOD stage builds it
  cl::Kernel k(d.program("lod.cl", "-DSCAN_WG=" + std::to_string(kScanWg)), "scan_bundles");
  const cl_uint kCanary = 0xC0FFEEu;
  for (std::uint32_t n : {1u, 255u, 256u, 257u, 1000u}) {
    SCOPED_TRACE("n = " + std::to_string(n));
    std::vector<cl_uint> counts(clh_lod_counts_length(n), 0u);
    std::vector<cl_uint> expected(clh_lod_offsets_length(n), 0u);
    std::uint32_t drawn = 0, visible = 0, segments = 0;
    for (std::uint32_t b = 0; b < n; ++b) {
      const std::uint32_t h = clh_hash2(n, b);
      const std::uint32_t full = h % 200u;  // some bundles are empty
      const bool culled = (h >> 8) % 3u == 0u;
      const std::uint32_t n_lod = culled ? 0u : std::min(full, 1u + (h >> 16) % 200u);
      counts[b] = n_lod;
      counts[clh_lod_full_count_at(n, b)] = n_lod > 0u ? full : 0u;
      counts[clh_lod_segment_count_at(n, b)] = n_lod * (1u + (h >> 24) % 64u);
      expected[b] = drawn;
      drawn += n_lod;
      visible += counts[clh_lod_full_count_at(n, b)];
      segments += counts[clh_lod_segment_count_at(n, b)];
    }
    expected[clh_lod_drawn_total_at(n)] = drawn;
    expected[clh_lod_visible_total_at(n)] = visible;
    expected[clh_lod_segment_total_at(n)] = segments;
    std::vector<cl_uint> out(expected.size() + 4, kCanary);
    cl::Buffer bc(d.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                  counts.size() * sizeof(cl_uint), counts.data());
    cl::Buffer bo(d.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, out.size() * sizeof(cl_uint),
                  out.data());
    k.setArg(0, bc);
    k.setArg(1, bo);
    k.setArg(2, n);
    d.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(kScanWg), cl::NDRange(kScanWg));
    d.queue.enqueueReadBuffer(bo, CL_TRUE, 0, out.size() * sizeof(cl_uint), out.data());
    for (std::size_t i = 0; i < expected.size(); ++i)
      ASSERT_EQ(out[i], expected[i]) << "offsets[" << i << "]";
    for (std::size_t i = expected.size(); i < out.size(); ++i)
      EXPECT_EQ(out[i], kCanary) << "canary " << i;
  }
}

// The strands lod_bundles keeps, counted on the CPU by its rule (kernels/lod.cl,
// clh_lod_record): a bundle is culled when the screen box of its layer quads' corners, each
// widened by the styling reach, lies entirely off screen; of the others LOD off keeps every
// strand and LOD on keeps N_LOD = clh_lod_strands(L, N, delta) with L = clh_lod_value of
// the box (lod_math.h, Lipp Eq. 1-2). The projection uses the view and object-to-view
// records the frame's strand pass read. Returned as a range: a bundle whose box edge or L
// moves the outcome when the box shifts by 1e-3 px (the device's rounding) counts both ways.
struct StrandRange {
  std::uint64_t lo = 0, hi = 0;
};

StrandRange expectedStrands(const HairMesh& mesh, const Frame& f, bool lod) {
  ClhGroomGpu g;
  ClhViewGpu v;
  EXPECT_EQ(f.rasterGroom.size(), sizeof g);
  EXPECT_EQ(f.rasterView.size(), sizeof v);
  std::memcpy(&g, f.rasterGroom.data(), sizeof g);
  std::memcpy(&v, f.rasterView.data(), sizeof v);
  const GroomData d = prepareGroom(mesh);
  const float reach = d.styleMargin;  // identity transform
  const float* m = g.obj_to_view;
  const float w = static_cast<float>(v.width), h = static_cast<float>(v.height);
  StrandRange range;
  for (const ClhBundle& b : d.bundles) {
    float lox = INFINITY, loy = INFINITY, hix = -INFINITY, hiy = -INFINITY;
    bool behind = true, unprojectable = false;
    for (int l = 0; l < mesh.layerCount; ++l)
      for (int k = 0; k < 4; ++k) {
        const int vi = std::min(std::max(b.vtx[k], 0), mesh.vertexCount - 1);
        const float* p = d.vertices[static_cast<std::size_t>(l) * mesh.vertexCount + vi].pos;
        const float x = m[0] * p[0] + m[1] * p[1] + m[2] * p[2] + m[3];
        const float y = m[4] * p[0] + m[5] * p[1] + m[6] * p[2] + m[7];
        const float z = m[8] * p[0] + m[9] * p[1] + m[10] * p[2] + m[11];
        if (z >= -reach) behind = false;
        if (z <= 1e-4f) {
          unprojectable = true;
          continue;
        }
        const float sx = v.cx + v.fx * x / z, sy = v.cy - v.fy * y / z, r = v.fx * reach / z;
        lox = std::min(lox, sx - r);
        loy = std::min(loy, sy - r);
        hix = std::max(hix, sx + r);
        hiy = std::max(hiy, sy + r);
      }
    if (behind) continue;
    std::uint32_t fewest = b.strand_count, most = 0;
    for (float e : {-1e-3f, 0.0f, 1e-3f}) {  // grow or shrink the box by e on every side
      const bool off = hix + e < 0.0f || hiy + e < 0.0f || lox - e > w || loy - e > h;
      std::uint32_t n = 0;
      if (unprojectable || !lod)
        n = off && !unprojectable ? 0u : b.strand_count;
      else if (!off)
        n = clh_lod_strands(clh_lod_value(hix - lox + 2 * e, hiy - loy + 2 * e, h, g.lod_lambda),
                            b.strand_count, b.lod_delta);
      fewest = std::min(fewest, n);
      most = std::max(most, n);
    }
    range.lo += fewest;
    range.hi += most;
  }
  return range;
}

TEST(LodKernel, CullsBundlesOffScreenAndKeepsVisibleOnes) {
  HairMesh mesh = makeGroomPreset("fur_sphere");
  mesh.strandCount = 3000;
  mesh.lod.strandsPerPixel = 0.0f;  // Eq. 1-2 below: the strands from L, not from the screen
  Scene s;
  s.width = 200;
  s.height = 100;
  s.grooms.push_back({"fur", std::make_shared<const HairMesh>(mesh), glm::mat4(1.0f)});
  s.camera.position = glm::vec3(0.0f, 0.0f, 0.5f);
  s.camera.target = glm::vec3(0.0f);
  s.camera.fovYDegrees = 30.0f;
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.lod = Toggle::Off;
  o.captureGBuffer = true;                              // records the view the LOD pass used
  EXPECT_EQ(r.render(s, o).stats.strandsDrawn, 3000u);  // fully in view: nothing culled
  s.camera.target = glm::vec3(0.0f, 0.0f, 0.8f);        // looking away: everything culled
  s.camera.position = glm::vec3(0.0f, 0.0f, 0.5f);
  EXPECT_EQ(r.render(s, o).stats.strandsDrawn, 0u);
  // Looking past the ball at growing angles, LOD off and on: the drawn count is what the
  // culling rule and Eq. 1-2 give the bundles whose screen box still touches the screen.
  int partial = 0;
  for (int lod : {0, 1})
    for (float x : {0.12f, 0.16f, 0.2f, 0.24f}) {
      s.camera.target = glm::vec3(x, 0.0f, 0.0f);
      o.lod = lod ? Toggle::On : Toggle::Off;
      const Frame f = r.render(s, o);
      const StrandRange want = expectedStrands(mesh, f, lod == 1);
      const std::uint64_t drawn = f.stats.strandsDrawn;
      EXPECT_GE(drawn, want.lo) << "LOD " << lod << ", target x " << x;
      EXPECT_LE(drawn, want.hi) << "LOD " << lod << ", target x " << x;
      EXPECT_LE(want.hi - want.lo, 30u) << "the expectation should be tight";
      RecordProperty("drawn_lod" + std::to_string(lod) + "_x" + std::to_string(x),
                     std::to_string(drawn));
      partial += drawn > 0 && drawn < 3000;
    }
  EXPECT_GE(partial, 6) << "the views should cut through the groom";
}

// Max distance from each point of `fine` to the polyline `coarse`, both sampled uniformly
// in the strand parameter: fine point k sits at k / (Cf - 1).
float polylineGap(const float* fine, std::uint32_t cf, const float* coarse, std::uint32_t cc) {
  float worst = 0.0f;
  for (std::uint32_t k = 0; k < cf; ++k) {
    float u = static_cast<float>(k) / (cf - 1) * (cc - 1);
    std::uint32_t i = std::min<std::uint32_t>(static_cast<std::uint32_t>(u), cc - 2);
    float t = u - i;
    glm::vec3 a(coarse[3 * i], coarse[3 * i + 1], coarse[3 * i + 2]);
    glm::vec3 b(coarse[3 * i + 3], coarse[3 * i + 4], coarse[3 * i + 5]);
    glm::vec3 p(fine[3 * k], fine[3 * k + 1], fine[3 * k + 2]);
    worst = std::max(worst, glm::length(p - (a + (b - a) * t)));
  }
  return worst;
}

TEST(LodMorph, StrandsChangeContinuouslyAcrossALevel) {
  HairMesh mesh = makeGroomPreset("long_wavy");
  mesh.strandCount = 3000;
  mesh.controlPoints = 129;  // C_max = 129: the level switch below is at C_raw = 34
  Renderer r(test::sharedDevice());
  const float Lswitch = (34.0f / 129.0f) * (34.0f / 129.0f);  // C: 65 above, 33 below
  StrandSet above = r.generateStrands(mesh, Lswitch * 1.0002f);
  StrandSet below = r.generateStrands(mesh, Lswitch * 0.9998f);
  HairMesh noMorph = mesh;
  noMorph.lod.morphWindow = 0.0f;
  StrandSet abrupt = r.generateStrands(noMorph, Lswitch * 1.0002f);
  ASSERT_FALSE(below.pointCounts.empty());
  ASSERT_EQ(above.pointCounts[0], 65u);
  ASSERT_EQ(below.pointCounts[0], 33u);
  // compare the strands both levels draw (the first N_LOD of each bundle)
  float worstMorph = 0.0f, worstAbrupt = 0.0f;
  std::size_t ia = 0, ib = 0, sa = 0, sb = 0;
  while (sa < above.pointCounts.size() && sb < below.pointCounts.size()) {
    if (above.bundleOf[sa] != below.bundleOf[sb]) {  // N_LOD can differ by one
      if (above.bundleOf[sa] < below.bundleOf[sb])
        ia += above.pointCounts[sa++];
      else
        ib += below.pointCounts[sb++];
      continue;
    }
    worstMorph =
        std::max(worstMorph, polylineGap(&above.points[3 * ia], 65, &below.points[3 * ib], 33));
    worstAbrupt =
        std::max(worstAbrupt, polylineGap(&abrupt.points[3 * ia], 65, &below.points[3 * ib], 33));
    ia += above.pointCounts[sa++];
    ib += below.pointCounts[sb++];
  }
  RecordProperty("jump_with_morph_m", std::to_string(worstMorph));
  RecordProperty("jump_without_morph_m", std::to_string(worstAbrupt));
  // the groom is ~0.5 m: the morph keeps the jump at float noise; without it strands jump
  EXPECT_LT(worstMorph, 2e-5f);
  EXPECT_GT(worstAbrupt, 20.0f * worstMorph);
}

TEST(LodCoverage, FarCoverageStaysWithinTenPercent) {
  HairMesh mesh = makeGroomPreset("long_wavy");
  Scene s;
  s.width = 480;
  s.height = 270;
  s.grooms.push_back({"g", std::make_shared<const HairMesh>(mesh), glm::mat4(1.0f)});
  s.camera = framePreset(s, CameraPreset::Far, 30.0f);
  Renderer r(test::sharedDevice());
  auto coverage = [&](Toggle lod, std::uint64_t* strands) {
    RenderOptions o;
    o.lod = lod;
    o.msaa = 4;  // coverage per pixel = fraction of samples hit
    o.captureGBuffer = true;
    Frame f = r.render(s, o);
    *strands = f.stats.strandsDrawn;
    double sum = 0.0;
    for (std::size_t i = 0; i < f.color.rgba.size() / 4; ++i) {
      int hits = 0;
      for (int l = 0; l < 4; ++l)
        hits += f.gbuffer[l * (f.color.rgba.size() / 4) + i] != ~std::uint64_t(0);
      sum += hits / 4.0;
    }
    return sum;
  };
  std::uint64_t nOff = 0, nOn = 0;
  double off = coverage(Toggle::Off, &nOff), on = coverage(Toggle::On, &nOn);
  RecordProperty("coverage_lod_off", std::to_string(off));
  RecordProperty("coverage_lod_on", std::to_string(on));
  RecordProperty("strands_lod_on", std::to_string(nOn));
  EXPECT_LT(nOn, nOff / 2) << "LOD should remove most strands at far";
  EXPECT_LT(std::fabs(on - off) / off, 0.10) << "coverage off " << off << " on " << on;
}

// long_wavy framed far at 960x540 with no ambient light, black background and the given
// lights, rendered with LOD and the single-fibre and aggregated LOD BSDFs (the same G-buffer
// shaded both ways). Asserts that LOD thins the groom and, with perPixel, that no pixel
// channel of the aggregate is darker; returns the aggregate's total over the single fibre's
// (and the hair pixels in *hair).
double aggregateOverSingleAtFar(const std::function<std::vector<Light>(const Scene&)>& lights,
                                bool perPixel, std::size_t* hair) {
  HairMesh mesh = makeGroomPreset("long_wavy");
  Scene s;
  s.width = 960;
  s.height = 540;
  s.background = glm::vec3(0.0f);
  s.ambient = glm::vec3(0.0f);
  s.grooms.push_back({"g", std::make_shared<const HairMesh>(mesh), glm::mat4(1.0f)});
  s.camera = framePreset(s, CameraPreset::Far, 30.0f);
  s.lights = lights(s);
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.lod = Toggle::On;
  o.filter = Toggle::Off;
  const Frame single = r.render(s, o);
  o.lodAggregate = true;
  const Frame agg = r.render(s, o);
  EXPECT_EQ(agg.stats.grooms.size(), 1u);
  if (agg.stats.grooms.size() == 1) {
    EXPECT_LT(agg.stats.grooms[0].strands, agg.stats.grooms[0].visibleStrands / 2)
        << "LOD thins the groom";
  }
  double sumS = 0.0, sumA = 0.0;
  *hair = 0;
  std::size_t darker = 0;
  for (std::size_t i = 0; i < single.color.rgba.size(); i += 4) {
    double ls = 0.0, la = 0.0;
    for (int c = 0; c < 3; ++c) {
      darker += agg.color.rgba[i + c] < single.color.rgba[i + c];
      ls += single.color.rgba[i + c];
      la += agg.color.rgba[i + c];
    }
    *hair += ls > 0.0;
    sumS += ls;
    sumA += la;
  }
  if (perPixel) {
    EXPECT_EQ(darker, 0u) << "pixel channels darker with the aggregate";
  }
  return sumA / std::max(sumS, 1e-30);
}

TEST(LodAggregate, LightAtTheEyeReachesEveryClusterDirectly) {
  // The aggregated BCSDF (Huang 2024, hair_bsdf.h) on the strands LOD widened at far, lit by
  // one point light at the camera (phi = 0 at every fibre). A drawn strand widened w times for
  // k fibres stands for k fibres side by side, k / w deep: a dense cluster (rho = 1), whose
  // view-facing fibre the light reaches directly, so the aggregate adds its B lobe to the
  // single fibre and takes nothing away: no pixel darker, the hair brighter on the whole.
  // Taking the cluster as round (rho = k / w^2) shadows it by S = 1 - c_m (1 - rho) and fails.
  std::size_t hair = 0;
  const double ratio = aggregateOverSingleAtFar(
      [](const Scene& s) {
        Light eye;
        eye.type = Light::Type::Point;
        eye.position = s.camera.position;
        const glm::vec3 d = s.camera.position - s.camera.target;
        eye.intensity = glm::dot(d, d);  // about 1 at the groom
        return std::vector<Light>{eye};
      },
      true, &hair);
  std::printf("light at the eye, far: %zu hair pixels, aggregate / single %.4f\n", hair, ratio);
  RecordProperty("aggregate_over_single", std::to_string(ratio));
  EXPECT_GT(hair, 200u);
  EXPECT_GT(ratio, 1.001);
}

TEST(LodAggregate, MappedLightIsNotAttenuatedTwiceByTheCluster) {
  // A directional light behind the groom (toward the camera) with a deep opacity map: the
  // map is drawn with the LOD's coverage compensation (each drawn strand adds its k fibres'
  // opacity) and looked up with Lipp's LOD shift, so it already counts the cluster's fibres
  // between the light and the shaded one. The aggregate must not attenuate that light by
  // their a_F^(n-1) again: what it keeps of the crossing, the lobes' longitudinal spread,
  // moves light between pixels without removing it, and its B lobe adds some, so the hair is
  // brighter on the whole than with the single fibre. Applying the inherited lobes'
  // attenuation to it takes about a tenth away and fails.
  std::size_t hair = 0;
  const double ratio = aggregateOverSingleAtFar(
      [](const Scene& s) {
        Light back;
        back.direction = glm::normalize(s.camera.target - s.camera.position +
                                        glm::vec3(0.0f, 0.3f, 0.0f) *
                                            glm::length(s.camera.target - s.camera.position));
        back.shadows = true;
        return std::vector<Light>{back};
      },
      false, &hair);
  std::printf("mapped light behind, far: %zu hair pixels, aggregate / single %.4f\n", hair, ratio);
  RecordProperty("aggregate_over_single", std::to_string(ratio));
  EXPECT_GT(hair, 200u);
  EXPECT_GT(ratio, 1.0);
}

}  // namespace
}  // namespace clhair
