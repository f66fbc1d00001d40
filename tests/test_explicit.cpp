// test_explicit.cpp — explicit strand grooms (include/clhair/strand_groom.h,
// kernels/strands_explicit.cl): the kernel against a CPU reference, the hair-mesh ->
// cyHair -> StrandGroom round trip rendered both ways, LOD, determinism and device bytes.
// Strand files through scenes and the command line: test_explicit_files.cpp.
//
// Inputs are built here: a synthetic groom with fixed seeds and point counts chosen to hit
// every edge of the kernel's lane layout (2 and 3 points, runs that are not multiples of
// 32, strands longer than one 128-segment round), and grooms generated from the presets.
// The TressFX round trip (export-strands .tfx, resampled to 16 points) compares the file's
// points with the same resampling done here, within 1e-6 of the groom's size (the file
// stores float32; both sides run the same code), and its frame with a frame of those
// strands built in memory: points that far apart move a 200-pixel-wide groom by under
// 1e-3 px, so at least 99.9 % of the pixels must be within 1/255 and RMSE below 1e-3.
// The cyHair round trip is exact: both paths draw the same float32 points with the same
// tangent arithmetic, w = k / (n - 1) and AO 1; cyHair holds no root uv, so the test rebuilds
// it on the host (the shading's per-strand variation hashes it); and two zero-length strands
// at the hair mesh's bounds' corners give the file the mesh's bounds, which set the
// G-buffer's depth mapping and the light's view. So the frames must be equal bit for bit,
// with and without a shadowed light.
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

namespace clhair {
namespace {

namespace fs = std::filesystem;
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

// The root uv strands.cl gives strand i of a generated set: sample (index in its bundle) of
// the renderer's progressive root set, bilinear in the bundle's corner uvs.
std::vector<glm::vec2> rootUvOf(const HairMesh& mesh, const StrandSet& s) {
  GroomData d = prepareGroom(mesh);
  std::uint32_t size = 1024;
  while (size < d.maxBundleStrands && size < (1u << 16)) size <<= 1;
  RootSets roots = makeRootSets(size);
  std::vector<std::uint32_t> seen(d.bundles.size(), 0);
  std::vector<glm::vec2> out;
  for (std::size_t i = 0; i < s.pointCounts.size(); ++i) {
    const gpu::ClhBundle& b = d.bundles[s.bundleOf[i]];
    const std::uint32_t root = std::min(seen[s.bundleOf[i]]++, size - 1);
    const glm::vec2 st = b.triangle ? roots.triangle[root] : roots.quad[root];
    const float w0 = (1 - st.x) * (1 - st.y), w1 = st.x * (1 - st.y), w2 = st.x * st.y,
                w3 = (1 - st.x) * st.y;
    out.emplace_back(w0 * b.uv[0] + w1 * b.uv[2] + w2 * b.uv[4] + w3 * b.uv[6],
                     w0 * b.uv[1] + w1 * b.uv[3] + w2 * b.uv[5] + w3 * b.uv[7]);
  }
  return out;
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

double srgb(float linear) {
  double x = std::min(std::max(static_cast<double>(linear), 0.0), 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

struct ImageDiff {
  double within = 0.0;  // fraction of pixels whose largest sRGB channel difference is <= 1/255
  double rmse = 0.0;    // over sRGB r, g, b
  double worst = 0.0;
};

ImageDiff diffImages(const Image& a, const Image& b) {
  ImageDiff d;
  const std::size_t pixels = static_cast<std::size_t>(a.width) * a.height;
  std::size_t ok = 0;
  double sum = 0.0;
  for (std::size_t i = 0; i < pixels; ++i) {
    double m = 0.0;
    for (int c = 0; c < 3; ++c) {
      double e = srgb(a.rgba[4 * i + c]) - srgb(b.rgba[4 * i + c]);
      sum += e * e;
      m = std::max(m, std::fabs(e));
    }
    ok += m <= 1.0 / 255.0 + 1e-9;
    d.worst = std::max(d.worst, m);
  }
  d.within = static_cast<double>(ok) / static_cast<double>(pixels);
  d.rmse = std::sqrt(sum / (3.0 * static_cast<double>(pixels)));
  return d;
}

Image diffImage(const Image& a, const Image& b) {
  Image d = a;
  for (std::size_t i = 0; i < d.rgba.size(); ++i)
    d.rgba[i] = (i % 4 == 3) ? 1.0f : 8.0f * std::fabs(a.rgba[i] - b.rgba[i]);
  return d;
}

// A small scene around `groom`: one shadowed directional light, a head sphere.
Scene sceneAround(GroomInstance groom, int w, int h) {
  Scene s;
  s.width = w;
  s.height = h;
  s.background = glm::vec3(0.1f, 0.2f, 0.3f);
  Light l;
  l.direction = glm::normalize(glm::vec3(0.3f, 1.0f, 0.6f));
  l.intensity = 2.0f;
  l.shadows = true;
  s.lights.push_back(l);
  s.shadows.resolution = 128;
  s.grooms.push_back(std::move(groom));
  return s;
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

// ---- round trip: hair mesh -> cyHair -> StrandGroom --------------------------------------

// The hair-mesh groom and the same strands written to a .hair file and read back, in one
// scene; `shadows`: the light casts deep opacity maps.
//
// The two grooms differ in one more thing than their source: their bounds, which set the
// G-buffer's depth mapping. A hair mesh's bounds include its styling reach; a strand file's
// are its points'. So the file gets two strands of two equal points at the mesh's bounds'
// corners: zero-length segments draw nothing (raster_core.h skips segments shorter than
// 1e-6 px), and both grooms have the same bounds.
struct RoundTrip {
  Frame mesh, strands;
  std::string dir;
};

RoundTrip renderRoundTrip(bool shadows) {
  HairMesh mesh = makeGroomPreset("curly_medium");
  mesh.strandCount = 3000;
  mesh.style.lengthVariation = 0.0f;  // w of a stored point is k / (n - 1), as generated then
  auto meshPtr = std::make_shared<const HairMesh>(mesh);
  Scene a = sceneAround(GroomInstance("mesh", meshPtr), 200, 150);
  a.lights[0].shadows = shadows;
  a.spheres.push_back({glm::vec3(0.0f), 0.09f, glm::vec3(0.5f, 0.4f, 0.3f)});
  a.camera = framePreset(a, CameraPreset::Close, 30.0f, 15.0f);

  Renderer r(test::sharedDevice());
  StrandSet set = r.generateStrands(mesh);
  RoundTrip rt;
  rt.dir = test::scratchDir();
  const std::string file = rt.dir + "/curly.hair";
  CyHair hair = test::toCyHair(set, mesh.appearance.strandWidth);
  const GroomData bounds = prepareGroom(mesh);
  for (const glm::vec3& corner : {bounds.boundsMin, bounds.boundsMax}) {
    hair.segments.push_back(1);
    for (int k = 0; k < 2; ++k)
      hair.points.insert(hair.points.end(), {corner.x, corner.y, corner.z});
  }
  writeCyHair(hair, file);
  StrandGroom g = loadStrandGroom(file, test::sharedDevice().info().maxAlloc);
  EXPECT_EQ(g.pointCounts.size(), set.pointCounts.size() + 2);
  g.appearance = mesh.appearance;
  g.seed = mesh.seed;
  g.rootUv = rootUvOf(mesh, set);  // cyHair has no uv: the shading's per-strand variation needs it
  g.rootUv.resize(g.pointCounts.size(), glm::vec2(0.5f));
  Scene b = a;
  b.grooms[0] = GroomInstance("strands", std::make_shared<const StrandGroom>(std::move(g)));

  RenderOptions o;
  o.lod = Toggle::Off;
  o.ambientOcclusion = false;  // explicit strands carry AO 1
  rt.mesh = r.render(a, o);
  rt.strands = r.render(b, o);
  EXPECT_EQ(rt.mesh.stats.strandsDrawn + 2, rt.strands.stats.strandsDrawn);
  return rt;
}

void reportRoundTrip(const RoundTrip& rt, const ImageDiff& d, const char* what) {
  ::testing::Test::RecordProperty("pixels_within_1_255", std::to_string(d.within));
  ::testing::Test::RecordProperty("rmse_srgb", std::to_string(d.rmse));
  std::printf(
      "[ explicit ] round trip %s: %.3f %% of pixels within 1/255, RMSE %.5f, largest %.4f\n", what,
      100.0 * d.within, d.rmse, d.worst);
  if (::testing::Test::HasFailure()) {
    writeImage(rt.mesh.color, rt.dir + "/expected_mesh.png");
    writeImage(rt.strands.color, rt.dir + "/actual_strands.png");
    writeImage(diffImage(rt.mesh.color, rt.strands.color), rt.dir + "/diff_x8.png");
  }
}

// Same float32 points, same tangent arithmetic, same uv, w and AO, same bounds: the same
// frame, bit for bit.
TEST(ExplicitRoundTrip, CyHairFileRendersLikeTheHairMesh) {
  RoundTrip rt = renderRoundTrip(false);
  ImageDiff d = diffImages(rt.mesh.color, rt.strands.color);
  EXPECT_TRUE(rt.mesh.color.rgba == rt.strands.color.rgba);
  EXPECT_TRUE(rt.mesh.depth == rt.strands.depth);
  reportRoundTrip(rt, d, "unshadowed");
}

// The light's view frames the grooms' hair (a hair mesh's measured box, a strand file's
// strands that draw something: the corner strands draw nothing), equal here, and the opacity
// of every strand goes into the deep opacity maps by integer atomic additions, whose order
// does not matter: the same frame, bit for bit.
TEST(ExplicitRoundTrip, ShadowsOfTheStrandFileMatchTheHairMesh) {
  RoundTrip rt = renderRoundTrip(true);
  ImageDiff d = diffImages(rt.mesh.color, rt.strands.color);
  EXPECT_TRUE(rt.mesh.color.rgba == rt.strands.color.rgba);
  EXPECT_TRUE(rt.mesh.depth == rt.strands.depth);
  reportRoundTrip(rt, d, "with deep opacity shadows");
}

// ---- round trip: hair mesh -> export-strands .tfx -> StrandGroom --------------------------

TEST(ExplicitRoundTrip, TressFxExportReadsBackAsTheResampledStrandsAndRendersLikeThem) {
  const std::string dir = test::scratchDir();
  const std::string groomPath = test::assetPath("grooms/tiny.hairmesh.json");
  const std::string file = dir + "/tiny.tfx";
  test::CommandResult ex =
      test::runCli("export-strands " + test::quote(groomPath) + " -o " + test::quote(file));
  ASSERT_EQ(ex.exitCode, 0) << ex.output;

  const HairMesh mesh = loadHairMesh(groomPath);
  Renderer r(test::sharedDevice());
  const StrandSet set = r.generateStrands(mesh);
  const CyHair generated = test::toCyHair(set, mesh.appearance.strandWidth);
  const std::uint32_t n = tressFxVertexCount(generated);
  ASSERT_EQ(n, 16u);  // 17 control points: the file is resampled, not a copy
  const CyHair expected = resampleStrands(generated, n);
  const std::uint64_t maxAlloc = test::sharedDevice().info().maxAlloc;
  const TressFxHair t = readTressFx(file, maxAlloc);
  ASSERT_EQ(t.hair.segments, expected.segments);
  ASSERT_EQ(t.hair.points.size(), expected.points.size());
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (std::size_t i = 0; i < expected.points.size(); i += 3) {
    const glm::vec3 p(expected.points[i], expected.points[i + 1], expected.points[i + 2]);
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const float tolerance = 1e-6f * glm::length(hi - lo);
  std::size_t off = 0;
  for (std::size_t i = 0; i < expected.points.size(); ++i)
    off += std::fabs(t.hair.points[i] - expected.points[i]) > tolerance;
  EXPECT_EQ(off, 0u) << "coordinates further than " << tolerance << " from the resampled strands";
  EXPECT_TRUE(t.strandUv.empty());

  auto placed = [&](StrandGroom g) {
    g.name = "tiny";
    g.appearance = mesh.appearance;
    g.seed = mesh.seed;
    return GroomInstance("tiny", std::make_shared<const StrandGroom>(std::move(g)));
  };
  StrandGroom memory;
  for (std::uint32_t seg : expected.segments) memory.pointCounts.push_back(seg + 1);
  for (std::size_t i = 0; i < expected.points.size(); i += 3)
    memory.points.emplace_back(expected.points[i], expected.points[i + 1], expected.points[i + 2]);
  Scene a = sceneAround(placed(std::move(memory)), 200, 150);
  a.camera = framePreset(a, CameraPreset::Close, 30.0f, 15.0f);
  Scene b = a;
  b.grooms[0] = placed(loadStrandGroom(file, maxAlloc));
  RenderOptions o;
  o.lod = Toggle::Off;
  RoundTrip rt;
  rt.dir = dir;
  rt.mesh = r.render(a, o);
  rt.strands = r.render(b, o);
  EXPECT_GT(rt.strands.stats.strandsDrawn, 0u);
  EXPECT_EQ(rt.mesh.stats.strandsDrawn, rt.strands.stats.strandsDrawn);
  ImageDiff d = diffImages(rt.mesh.color, rt.strands.color);
  EXPECT_GE(d.within, 0.999);
  EXPECT_LT(d.rmse, 1e-3);
  reportRoundTrip(rt, d, "TressFX file against the same strands in memory");
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
