// test_explicit.cpp — explicit strand grooms (include/clhair/strand_groom.h,
// kernels/strands_explicit.cl): the kernel against a CPU reference, LOD, determinism and
// device bytes.
// The round trips through cyHair and TressFX files: test_explicit_round_trip.cpp.
// Strand files through scenes and the command line: test_explicit_files.cpp.
//
// Inputs are built here: a synthetic groom with fixed seeds and point counts chosen to hit
// every edge of the kernel's lane layout (2 and 3 points, runs that are not multiples of
// 32, strands longer than one 128-segment round), and grooms generated from the presets.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <nlohmann/json.hpp>

#include "clhair/lod_math.h"
#include "clhair/renderer.h"
#include "clhair/strand_groom.h"
#include "float_frames.h"
#include "groom/blue_noise.h"
#include "groom/groom_data.h"
#include "groom/presets.h"
#include "io/cyhair.h"
#include "io/tressfx.h"
#include "synthetic_groom.h"
#include "test_util.h"

#include "explicit_scene.h"
namespace clhair {
namespace {

namespace fs = std::filesystem;
using explicit_test::sceneAround;
using nlohmann::json;

// ---- helpers ----------------------------------------------------------------------------

StrandGroom groomFromStrandSet(const StrandSet& s) {
  StrandGroom g;
  g.name = "generated";
  g.pointCounts = s.pointCounts;
  for (std::size_t i = 0; i < s.points.size(); i += 3)
    g.points.emplace_back(s.points[i], s.points[i + 1], s.points[i + 2]);
  return g;
}

glm::vec3 normalizeOr(glm::vec3 v, glm::vec3 fallback) {
  float l2 = glm::dot(v, v);
  return (l2 > 1e-30f && l2 < 1e30f) ? v / std::sqrt(l2) : fallback;
}

// The CPU reference of one drawn strand at LOD value L, written for clarity from the
// description in strands_explicit.cl: every step-th point plus the tip, odd points morphed
// toward their neighbours' midpoint by gamma, central-difference tangents, Bhokare's
// reflection rule at both ends.
struct DrawnStrand {
  std::vector<glm::vec4> p;  // xyz, w
  std::vector<glm::vec3> t;
};

DrawnStrand referenceStrand(const StrandGroom& g, std::size_t strand, float L) {
  std::size_t first = 0;
  for (std::size_t s = 0; s < strand; ++s) first += g.pointCounts[s];
  const std::uint32_t n = g.pointCounts[strand];
  const std::uint32_t cfull = CLH_MAX_CONTROL_POINTS;
  const std::uint32_t C = gpu::clh_lod_control_points(L, 3u, cfull);
  float gamma = gpu::clh_lod_morph(L, 3u, cfull, g.lod.morphWindow);
  std::uint32_t step = (cfull - 1) / (C - 1);
  while (step > 1 && n - 1 < 2 * step) {
    step /= 2;
    gamma = 0.0f;
  }
  if (n - 1 < 4 * step) gamma = 0.0f;
  const std::uint32_t M = (n - 1 + step - 1) / step + 1;
  std::vector<glm::vec4> raw(M);
  for (std::uint32_t j = 0; j < M; ++j) {
    const std::uint32_t k = std::min(j * step, n - 1);
    raw[j] = glm::vec4(g.points[first + k], static_cast<float>(k) / static_cast<float>(n - 1));
  }
  DrawnStrand d;
  d.p = raw;
  for (std::uint32_t j = 1; j + 1 < M; j += 2)
    d.p[j] = raw[j] + (0.5f * (raw[j - 1] + raw[j + 1]) - raw[j]) * gamma;
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  auto xyz = [&](std::uint32_t j) { return glm::vec3(d.p[j]); };
  d.t.assign(M, glm::vec3(0.0f));
  for (std::uint32_t j = 1; j + 1 < M; ++j) d.t[j] = normalizeOr(xyz(j + 1) - xyz(j - 1), up);
  auto reflect = [](glm::vec3 q, glm::vec3 t) { return 2.0f * q * glm::dot(t, q) - t; };
  glm::vec3 q0 = normalizeOr(xyz(1) - xyz(0), up);
  glm::vec3 qn = normalizeOr(xyz(M - 1) - xyz(M - 2), up);
  d.t[0] = normalizeOr(reflect(q0, M == 2 ? q0 : d.t[1]), q0);
  d.t[M - 1] = normalizeOr(reflect(qn, M == 2 ? qn : d.t[M - 2]), qn);
  return d;
}

// Exported strands of `groom` at L against the reference; returns how many were checked.
std::size_t expectMatchesReference(Renderer& r, const StrandGroom& groom, float L) {
  StrandSet e = r.generateStrands(groom, L);
  std::size_t at = 0, checked = 0;
  for (std::size_t i = 0; i < e.pointCounts.size(); ++i) {
    const std::uint32_t src = e.sourceStrand[i];
    DrawnStrand ref = referenceStrand(groom, src, L);
    EXPECT_EQ(e.pointCounts[i], ref.p.size()) << "strand " << src << " L " << L;
    const std::size_t M = std::min<std::size_t>(e.pointCounts[i], ref.p.size());
    float worstP = 0.0f, worstT = 0.0f, worstW = 0.0f;
    for (std::size_t j = 0; j < M; ++j) {
      const std::size_t q = at + j;
      glm::vec3 p(e.points[3 * q], e.points[3 * q + 1], e.points[3 * q + 2]);
      glm::vec3 t(e.tangents[3 * q], e.tangents[3 * q + 1], e.tangents[3 * q + 2]);
      worstP = std::max(worstP, glm::length(p - glm::vec3(ref.p[j])));
      worstT = std::max(worstT, glm::length(t - ref.t[j]));
      worstW = std::max(worstW, std::fabs(e.w[q] - ref.p[j].w));
    }
    EXPECT_LT(worstP, 1e-6f) << "strand " << src << " (" << groom.pointCounts[src] << " points) L "
                             << L;
    EXPECT_LT(worstT, 2e-5f) << "strand " << src << " (" << groom.pointCounts[src] << " points) L "
                             << L;
    EXPECT_LT(worstW, 1e-6f) << "strand " << src << " L " << L;
    at += e.pointCounts[i];
    ++checked;
  }
  return checked;
}

// ---- the kernel against the CPU reference -----------------------------------------------

TEST(ExplicitKernel, FullDetailDrawsEveryStoredPointWithReferenceTangents) {
  StrandGroom g = test::syntheticGroom(150);  // 3 chunks, the last of 22 strands
  Renderer r(test::sharedDevice());
  StrandSet e = r.generateStrands(g, 1.0f);
  ASSERT_EQ(e.pointCounts.size(), g.pointCounts.size());
  std::set<std::uint32_t> sources(e.sourceStrand.begin(), e.sourceStrand.end());
  EXPECT_EQ(sources.size(), g.pointCounts.size()) << "every strand exactly once";
  for (std::size_t i = 0; i < e.bundleOf.size(); ++i) ASSERT_EQ(e.bundleOf[i], i / 64);
  EXPECT_EQ(expectMatchesReference(r, g, 1.0f), g.pointCounts.size());
}

TEST(ExplicitKernel, PointSkippingAndMorphMatchTheReference) {
  StrandGroom g = test::syntheticGroom(150);
  Renderer r(test::sharedDevice());
  // L = 0.3: C 65, step 2, no morph; Lq: C 65 with gamma 0.5 (inside the window); 0.02: step 8
  const float Lq = std::pow((std::pow(2.0f, 5.25f) + 2.0f) / 129.0f, 2.0f);
  ASSERT_NEAR(gpu::clh_lod_morph(Lq, 3u, 129u, 0.5f), 0.5f, 1e-3f);
  for (float L : {0.3f, Lq, 0.02f}) {
    SCOPED_TRACE("L = " + std::to_string(L));
    StrandSet e = r.generateStrands(g, L);
    // per chunk: the first N_LOD of its shuffled strands (Lipp Eq. 1 with the chunk's delta)
    std::vector<std::uint32_t> perChunk(3, 0);
    for (std::uint32_t c : e.bundleOf) ++perChunk.at(c);
    for (std::uint32_t c = 0; c < 3; ++c) {
      const std::uint32_t n = c < 2 ? 64 : 22;
      const float delta = gpu::clh_u01(gpu::clh_hash3(g.seed, c, CLH_RNG_LOD_DELTA));
      EXPECT_EQ(perChunk[c], gpu::clh_lod_strands(L, n, delta)) << "chunk " << c;
    }
    expectMatchesReference(r, g, L);
  }
}

// ---- LOD ------------------------------------------------------------------------------------

TEST(ExplicitLod, FarDrawsFewerStrandsAndPointsAndKeepsCoverage) {
  HairMesh mesh = makeGroomPreset("long_wavy");
  mesh.strandCount = 20000;
  Renderer r(test::sharedDevice());
  StrandGroom g = groomFromStrandSet(r.generateStrands(mesh));
  g.appearance = mesh.appearance;
  Scene s;
  s.width = 480;
  s.height = 270;
  s.grooms.push_back(GroomInstance("g", std::make_shared<const StrandGroom>(std::move(g))));
  s.camera = framePreset(s, CameraPreset::Far, 30.0f);
  auto coverage = [&](Toggle lod, FrameStats* stats) {
    RenderOptions o;
    o.lod = lod;
    o.msaa = 4;  // coverage per pixel = fraction of samples hit
    o.captureGBuffer = true;
    o.rasterStats = true;
    Frame f = r.render(s, o);
    *stats = f.stats;
    const std::size_t pixels = f.color.rgba.size() / 4;
    double sum = 0.0;
    for (std::size_t i = 0; i < pixels; ++i) {
      int hits = 0;
      for (int l = 0; l < 4; ++l) hits += f.gbuffer[l * pixels + i] != ~std::uint64_t(0);
      sum += hits / 4.0;
    }
    return sum;
  };
  FrameStats off, on;
  const double cOff = coverage(Toggle::Off, &off), cOn = coverage(Toggle::On, &on);
  RecordProperty("coverage_lod_off", std::to_string(cOff));
  RecordProperty("coverage_lod_on", std::to_string(cOn));
  RecordProperty("strands_lod_on", std::to_string(on.strandsDrawn));
  RecordProperty("segments_lod_on", std::to_string(on.segmentsDrawn));
  std::printf(
      "[ explicit ] far: strands %llu -> %llu, segments %llu -> %llu, coverage %.1f -> %.1f\n",
      static_cast<unsigned long long>(off.strandsDrawn),
      static_cast<unsigned long long>(on.strandsDrawn),
      static_cast<unsigned long long>(off.segmentsDrawn),
      static_cast<unsigned long long>(on.segmentsDrawn), cOff, cOn);
  EXPECT_EQ(off.strandsDrawn, 20000u);
  EXPECT_LT(on.strandsDrawn, off.strandsDrawn / 2) << "LOD should remove most strands at far";
  EXPECT_LT(static_cast<double>(on.segmentsDrawn) / on.strandsDrawn,
            0.75 * static_cast<double>(off.segmentsDrawn) / off.strandsDrawn)
      << "vertex LOD should skip points at far";
  EXPECT_LT(std::fabs(cOn - cOff) / cOff, 0.10) << "coverage off " << cOff << " on " << cOn;
}

TEST(ExplicitLod, ChunksOffScreenAreCulled) {
  StrandGroom g = test::syntheticGroom(640);
  Scene s;
  s.width = 160;
  s.height = 120;
  s.grooms.push_back(GroomInstance("g", std::make_shared<const StrandGroom>(std::move(g))));
  s.camera.position = glm::vec3(0.0f, 0.15f, 0.6f);
  s.camera.target = glm::vec3(0.0f, 0.15f, 0.0f);
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.lod = Toggle::Off;
  EXPECT_EQ(r.render(s, o).stats.strandsDrawn, 640u);
  s.camera.target = glm::vec3(0.0f, 0.15f, 1.2f);  // looking away
  EXPECT_EQ(r.render(s, o).stats.strandsDrawn, 0u);
  s.camera.target = glm::vec3(0.33f, 0.15f, 0.0f);  // part in view
  const std::uint64_t part = r.render(s, o).stats.strandsDrawn;
  EXPECT_GT(part, 0u);
  EXPECT_LT(part, 640u);
}

// ---- determinism and dispatch sizing ------------------------------------------------------

TEST(ExplicitRender, FramesAreBitIdenticalAcrossRunsRenderersAndDispatchModes) {
  StrandGroom g = test::syntheticGroom(400);
  g.appearance.minHitDiameterPx = 1.0f;
  Scene s =
      sceneAround(GroomInstance("g", std::make_shared<const StrandGroom>(std::move(g))), 120, 90);
  s.camera = framePreset(s, CameraPreset::Close, 20.0f, 10.0f);
  RenderOptions o;
  o.lod = Toggle::On;
  Renderer a(test::sharedDevice()), b(test::sharedDevice());
  Frame f1 = a.render(s, o), f2 = a.render(s, o), f3 = b.render(s, o);
  ASSERT_EQ(f1.color.rgba.size(), f3.color.rgba.size());
  EXPECT_TRUE(f1.color.rgba == f2.color.rgba);
  EXPECT_TRUE(f1.color.rgba == f3.color.rgba);
  EXPECT_TRUE(std::memcmp(f1.depth.data(), f3.depth.data(), f1.depth.size() * 4) == 0);
  for (DispatchMode m : {DispatchMode::OverLaunch, DispatchMode::Persistent}) {
    o.dispatch = m;
    EXPECT_TRUE(a.render(s, o).color.rgba == f1.color.rgba) << dispatchModeName(m);
  }
  // the hair is there: some pixels differ from the background
  std::size_t hair = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) hair += std::fabs(f1.color.pixel(x, y)[2] - 0.3f) > 1e-3f;
  EXPECT_GT(hair, 100u);
  EXPECT_GT(f1.stageMs("strands"), 0.0);
  EXPECT_GT(f1.stageMs("shadow"), 0.0);
}

// ---- device memory ----------------------------------------------------------------------

TEST(ExplicitMemory, DeviceBytesOfAMeshAndItsExportedStrands) {
  HairMesh mesh = makeGroomPreset("tiny");
  mesh.strandCount = 2000;
  Renderer r(test::sharedDevice());
  StrandSet set = r.generateStrands(mesh);
  StrandGroom g = groomFromStrandSet(set);
  const std::uint64_t points = g.points.size(), strands = g.pointCounts.size();
  GroomInstance mi("mesh", std::make_shared<const HairMesh>(mesh));
  GroomInstance si("strands", std::make_shared<const StrandGroom>(std::move(g)));
  const std::uint64_t meshBytes = r.groomDeviceBytes(mi), strandBytes = r.groomDeviceBytes(si);
  RecordProperty("mesh_bytes", std::to_string(meshBytes));
  RecordProperty("strand_bytes", std::to_string(strandBytes));
  // 16 bytes per point, 4 per strand offset, and small per-chunk tables
  EXPECT_GE(strandBytes, 16 * points + 4 * strands);
  EXPECT_LT(strandBytes, 16 * points + 4 * strands + 4096 + 128 * (strands / 64 + 1));
  EXPECT_LT(meshBytes * 10, strandBytes);
}

}  // namespace
}  // namespace clhair
