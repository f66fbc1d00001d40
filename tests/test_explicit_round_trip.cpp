// test_explicit_round_trip.cpp — a hair mesh written as a strand file and read back renders
// like the hair mesh (include/clhair/strand_groom.h, kernels/strands_explicit.cl). The kernel
// against its CPU reference, LOD, determinism and device bytes: test_explicit.cpp.
//
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

#include "explicit_scene.h"

namespace clhair {
namespace {

namespace fs = std::filesystem;
using explicit_test::sceneAround;
using nlohmann::json;

// ---- helpers ----------------------------------------------------------------------------

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

// The round trip's two frames are the same, bit for bit (colour and depth).
void expectSameFrames(bool shadows, const char* what) {
  RoundTrip rt = renderRoundTrip(shadows);
  ImageDiff d = diffImages(rt.mesh.color, rt.strands.color);
  EXPECT_TRUE(rt.mesh.color.rgba == rt.strands.color.rgba);
  EXPECT_TRUE(rt.mesh.depth == rt.strands.depth);
  reportRoundTrip(rt, d, what);
}

// Same float32 points, same tangent arithmetic, same uv, w and AO, same bounds: the same
// frame, bit for bit.
TEST(ExplicitRoundTrip, CyHairFileRendersLikeTheHairMesh) { expectSameFrames(false, "unshadowed"); }

// The light's view frames the grooms' hair (a hair mesh's measured box, a strand file's
// strands that draw something: the corner strands draw nothing), equal here, and the opacity
// of every strand goes into the deep opacity maps by integer atomic additions, whose order
// does not matter: the same frame, bit for bit.
TEST(ExplicitRoundTrip, ShadowsOfTheStrandFileMatchTheHairMesh) {
  expectSameFrames(true, "with deep opacity shadows");
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

}  // namespace
}  // namespace clhair
