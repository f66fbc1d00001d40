// test_fit.cpp — fitting a hair mesh to strands (clhair/fit.h, docs/fitting.md).
//
// Grooms with known cages and styling are generated on the CPU (fit_groom.h) and fitted:
// the styling parameters come back within the tolerances docs/fitting.md states, the
// layers follow the known cage within 5 % of a bundle's width, bundles keep their frames
// through a twist, share corners where their roots touch and not across a parting, and
// degenerate input gives a single-bundle fit or one clear error. Fitted meshes pass the
// reader's validation and render through every path of the renderer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "clhair/error.h"
#include "clhair/fit.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "fit_groom.h"
#include "io/cyhair.h"
#include "test_util.h"

namespace clhair {
namespace {

using test::PatchShape;

// The styled patch of the recovery check and its known parameters.
HairMesh styledPatch(const PatchShape& shape) {
  HairMesh m = test::patchMesh(shape);
  StyleParams& s = m.style;
  s.curlAmplitude = 0.003f;
  s.curlFrequency = 4.0f;
  s.curlHelix = 0.6f;
  s.curlPhaseJitter = 0.3f;
  s.clumpStrength = 0.5f;
  s.clumpFrequency = 20.0f;  // clumps of 150 strands, 5 mm: 6 to a bundle
  s.clumpShape = 1.5f;
  s.frizzAmplitude = 0.001f;
  s.frizzFrequency = 6.0f;
  s.flyawayFraction = 0.05f;
  s.flyawayAmplitude = 0.004f;
  s.lengthVariation = 0.2f;
  return m;
}

// Object-space size of the fitted mesh's uv unit at the patch (metres per uv unit along u).
float metresPerUv(const HairMesh& m) {
  float best = 0.0f;
  for (const auto& f : m.faces) {
    const glm::vec2 duv = m.uv[f[1]] - m.uv[f[0]];
    const float d = glm::length(m.position(0, f[1]) - m.position(0, f[0]));
    if (glm::length(duv) > 0.0f) best = std::max(best, d / glm::length(duv));
  }
  return best;
}

TEST(FitSynthetic, RecoversStylingParametersAndCage) {
  const PatchShape shape;
  HairMesh known = styledPatch(shape);
  known.strandCount = 60000;
  FitOptions o;
  o.bundles = 64;  // as many as the known mesh has
  o.layers = 5;
  o.evaluate = false;
  const FitResult r = fitHairMesh(test::strandsOf(known), o);
  const FittedStyle& f = r.report.fitted;
  const StyleParams& k = known.style;
  // tolerances of docs/fitting.md, "Checks"
  EXPECT_NEAR(f.curlAmplitude, k.curlAmplitude, 0.10 * k.curlAmplitude);
  EXPECT_NEAR(f.curlFrequency, k.curlFrequency, 0.05 * k.curlFrequency);
  EXPECT_NEAR(f.curlHelix, k.curlHelix, 0.1);
  EXPECT_NEAR(f.curlPhaseJitter, k.curlPhaseJitter, 0.1);
  EXPECT_NEAR(f.clumpStrength, k.clumpStrength, 0.15);
  EXPECT_NEAR(f.clumpShape, k.clumpShape, 0.5);
  // clump cells per metre: the fitted uv has its own scale
  const double cellsPerMetre = k.clumpFrequency / shape.size;
  EXPECT_NEAR(f.clumpFrequency / metresPerUv(r.mesh), cellsPerMetre, 0.3 * cellsPerMetre);
  EXPECT_NEAR(f.frizzAmplitude, k.frizzAmplitude, 0.3 * k.frizzAmplitude);
  EXPECT_NEAR(f.frizzFrequency, k.frizzFrequency, 0.5 * k.frizzFrequency);
  EXPECT_NEAR(f.flyawayFraction, k.flyawayFraction, 0.03);
  EXPECT_NEAR(f.flyawayAmplitude, k.flyawayAmplitude, 0.4 * k.flyawayAmplitude);
  EXPECT_NEAR(f.lengthVariation, k.lengthVariation, 0.05);
  // the mesh carries them
  EXPECT_EQ(r.mesh.style.curlAmplitude, f.curlAmplitude);
  EXPECT_EQ(r.mesh.style.clumpStrength, f.clumpStrength);

  // every fitted vertex whose bundles the patch's edge does not cut lies where the known
  // cage puts a strand rooted there, on every layer, within 5 % of a bundle's width
  const float width = shape.size / shape.cells;
  int checked = 0;
  for (int v = 0; v < r.mesh.vertexCount; ++v) {
    const glm::vec3 root = r.mesh.position(0, v);
    if (std::fabs(root.x) > 0.35f * shape.size || std::fabs(root.z) > 0.35f * shape.size) continue;
    ++checked;
    for (int l = 0; l < r.mesh.layerCount; ++l) {
      const glm::vec3 want = test::patchCagePoint(known, shape, root.x, root.z, l);
      EXPECT_LT(glm::length(r.mesh.position(l, v) - want), 0.05f * width)
          << "vertex " << v << " layer " << l;
    }
  }
  EXPECT_GE(checked, 16);
}

TEST(FitSynthetic, WithoutStylingNothingIsInvented) {
  const PatchShape shape;
  FitOptions o;
  o.bundles = 64;
  o.layers = 5;
  o.evaluate = false;
  const FitResult r = fitHairMesh(test::strandsOf(test::patchMesh(shape)), o);
  EXPECT_EQ(r.mesh.style.curlAmplitude, 0.0f);
  EXPECT_EQ(r.mesh.style.clumpStrength, 0.0f);
  EXPECT_LT(r.mesh.style.frizzAmplitude, 1e-4f);
  EXPECT_EQ(r.mesh.style.flyawayFraction, 0.0f);
  EXPECT_LT(r.mesh.style.lengthVariation, 0.02f);
}

// The angle of a face's corner 0 about its centre on layer l, in the plane across `axis`.
float cornerAngle(const HairMesh& m, int face, int l, const glm::vec3& axis, const glm::vec3& ref) {
  glm::vec3 c(0.0f);
  for (int k = 0; k < 4; ++k) c += 0.25f * m.position(l, m.faces[face][k]);
  glm::vec3 d = m.position(l, m.faces[face][0]) - c;
  d -= glm::dot(d, axis) * axis;
  const glm::vec3 r2 = glm::cross(axis, ref);
  return std::atan2(glm::dot(d, r2), glm::dot(d, ref));
}

TEST(FitCage, FollowsATwistWithoutFlips) {
  PatchShape shape;
  shape.cells = 4;
  shape.size = 0.04f;
  shape.layers = 6;
  shape.twist = 0.35f;  // 20 degrees per layer, 100 degrees at the tip
  const HairMesh known = test::patchMesh(shape);
  FitOptions o;
  o.bundles = 16;
  o.layers = 6;
  o.evaluate = false;
  const FitResult r = fitHairMesh(test::strandsOf(known), o);
  const HairMesh& m = r.mesh;
  ASSERT_GE(m.faces.size(), 12u);
  float total = 0.0f;  // the mean turn of the faces from root to tip
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    float prev = cornerAngle(m, static_cast<int>(f), 0, glm::vec3(0, 1, 0), glm::vec3(1, 0, 0));
    for (int l = 1; l < m.layerCount; ++l) {
      // the quad keeps its orientation about the bundle's direction ...
      const auto& q = m.faces[f];
      const glm::vec3 n = glm::cross(m.position(l, q[1]) - m.position(l, q[0]),
                                     m.position(l, q[3]) - m.position(l, q[0]));
      const glm::vec3 n0 = glm::cross(m.position(0, q[1]) - m.position(0, q[0]),
                                      m.position(0, q[3]) - m.position(0, q[0]));
      EXPECT_GT(glm::dot(n, n0), 0.0f) << "face " << f << " flips on layer " << l;
      // ... and its corners turn the way the twist turns (20 degrees a layer), by less than
      // twice that: never back, never on to the next corner (90 degrees)
      const float a =
          cornerAngle(m, static_cast<int>(f), l, glm::vec3(0, 1, 0), glm::vec3(1, 0, 0));
      float step = a - prev;
      step = std::atan2(std::sin(step), std::cos(step));
      EXPECT_GT(step, 0.0f) << "face " << f << " layer " << l;
      EXPECT_LT(step, 2.0f * shape.twist) << "face " << f << " layer " << l;
      total += step / static_cast<float>(m.faces.size());
      prev = a;
    }
  }
  EXPECT_NEAR(total, shape.twist * (m.layerCount - 1), 0.15f);
}

TEST(FitCage, SharesCornersWhereRootsTouchButNotAcrossAParting) {
  // two halves whose strands part to -x and +x from x = 0
  PatchShape left, right;
  left.cells = right.cells = 4;
  left.size = right.size = 0.04f;
  left.spread = right.spread = 0.05f;
  left.xShift = -0.02f;
  right.xShift = 0.02f;
  HairMesh lm = test::patchMesh(left), rm = test::patchMesh(right);
  lm.strandCount = rm.strandCount = 4000;
  StrandGroom g = test::strandsOf(lm);
  test::append(g, test::strandsOf(rm));
  FitOptions o;
  o.bundles = 32;
  o.layers = 5;
  o.evaluate = false;
  const FitResult r = fitHairMesh(g, o);
  const HairMesh& m = r.mesh;
  // which side each face's strands go: its tip centre
  std::vector<float> side(m.faces.size());
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    glm::vec3 root(0.0f), tip(0.0f);
    for (int k = 0; k < 4; ++k) {
      root += 0.25f * m.position(0, m.faces[f][k]);
      tip += 0.25f * m.position(m.layerCount - 1, m.faces[f][k]);
    }
    side[f] = tip.x - root.x;
    EXPECT_GT(std::fabs(side[f]), 0.02f) << "face " << f << " does not part";
  }
  // no vertex joins faces of the two sides; most interior corners are shared
  std::vector<int> uses(m.vertexCount, 0), positive(m.vertexCount, 0);
  for (std::size_t f = 0; f < m.faces.size(); ++f)
    for (int k = 0; k < 4; ++k) {
      ++uses[m.faces[f][k]];
      positive[m.faces[f][k]] += side[f] > 0.0f;
    }
  int shared = 0;
  for (int v = 0; v < m.vertexCount; ++v) {
    EXPECT_TRUE(positive[v] == 0 || positive[v] == uses[v])
        << "vertex " << v << " spans the parting";
    shared += uses[v] > 1;
  }
  // two 4 x 4 grids have 2 x 9 interior corners shared by 4 faces and 2 x 12 edge corners
  // shared by 2: at least most of those
  EXPECT_GE(shared, 30);
  // generated strands stay on their side
  const fit::GeneratedStrands gen = fit::generateStrandsCpu(m, 0);
  for (std::size_t i = 0; i < gen.count(); ++i) {
    const glm::vec3 root = gen.data[i * gen.points],
                    tip = gen.data[i * gen.points + gen.points - 1];
    EXPECT_GT((tip.x - root.x) * side[gen.bundle[i]], 0.0f);
    if (::testing::Test::HasFailure()) break;
  }
}

StrandGroom straightStrands(std::size_t n, std::uint32_t points) {
  StrandGroom g;
  g.name = "straight";
  for (std::size_t i = 0; i < n; ++i) {
    const float x = 0.001f * static_cast<float>(i % 40), z = 0.001f * static_cast<float>(i / 40);
    g.pointCounts.push_back(points);
    for (std::uint32_t k = 0; k < points; ++k)
      g.points.push_back(glm::vec3(x, 0.05f * k / (points - 1), z + 0.01f * k / (points - 1)));
  }
  return g;
}

TEST(FitDegenerate, OneStrandIsASingleBundle) {
  const StrandGroom g = straightStrands(1, 9);
  const FitResult r = fitHairMesh(g);
  EXPECT_EQ(r.mesh.faces.size(), 1u);
  EXPECT_EQ(r.mesh.strandCount, 1);
  EXPECT_NO_THROW(validateHairMesh(r.mesh, "fitted"));
  ASSERT_FALSE(r.report.notes.empty());
  EXPECT_NE(r.report.notes[0].find("single bundle"), std::string::npos);
  EXPECT_LT(r.report.error.meanWidths, 1.0);  // its one generated strand lies on it
}

TEST(FitDegenerate, IdenticalStrandsAreASingleBundle) {
  StrandGroom g = straightStrands(1, 17);
  for (int i = 0; i < 99; ++i) test::append(g, straightStrands(1, 17));
  const FitResult r = fitHairMesh(g);
  EXPECT_EQ(r.mesh.faces.size(), 1u);
  EXPECT_EQ(r.mesh.strandCount, 100);
  EXPECT_NE(r.report.notes[0].find("roots coincide"), std::string::npos);
  EXPECT_LT(r.report.error.meanWidths, 1.0);
}

TEST(FitDegenerate, TwoPointStrandsFit) {
  const StrandGroom g = straightStrands(2000, 2);
  FitOptions o;
  o.bundles = 20;
  const FitResult r = fitHairMesh(g, o);
  EXPECT_NO_THROW(validateHairMesh(r.mesh, "fitted"));
  EXPECT_GE(r.mesh.faces.size(), 15u);
  // straight strands 1 mm apart: every one has a generated strand well within that
  EXPECT_LT(r.report.error.meanM, 5e-4);
  EXPECT_EQ(r.mesh.style.curlAmplitude, 0.0f);
}

TEST(FitDegenerate, BadInputIsOneClearError) {
  StrandGroom nan = straightStrands(10, 5);
  nan.points[7].y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(test::errorOf([&] { fitHairMesh(nan); }).find("point 7 is not finite"),
            std::string::npos);
  StrandGroom flat = straightStrands(3, 4);
  for (glm::vec3& p : flat.points) p = glm::vec3(0.1f);
  EXPECT_NE(test::errorOf([&] { fitHairMesh(flat); }).find("zero length"), std::string::npos);
  EXPECT_NE(test::errorOf([&] { fitHairMesh(StrandGroom{}); }).find("no strands"),
            std::string::npos);
  const StrandGroom ok = straightStrands(10, 5);
  FitOptions o;
  o.layers = 1;
  EXPECT_NE(test::errorOf([&] { fitHairMesh(ok, o); }).find("layers is 1"), std::string::npos);
  o = FitOptions();
  o.bundles = -2;
  EXPECT_NE(test::errorOf([&] { fitHairMesh(ok, o); }).find("bundles is -2"), std::string::npos);
}

// The fit paths under UBSan (these run in the sanitized suite, scripts/dev.sh): a groom
// centred on the origin puts cells left of and below the lattice's first (a negative cell
// coordinate in the lattice's key), and 16384 bundles asked of 61 strands shrink the lattice
// far below the roots' spacing (cell coordinates beyond the int range). Both fit. The first
// is 300 strands in 16 bundles (the k-means reads the cells around every border cell however
// many strands there are) and the error is measured over a sample of 50 strands: the paths
// run under the sanitizers in half the time of 1000 strands (23 s under ASan).
TEST(FitSanitized, GroomCentredOnTheOrigin) {
  StrandGroom g = straightStrands(300, 5);
  for (glm::vec3& p : g.points) p -= glm::vec3(0.02f, 0.0f, 0.05f);
  FitOptions o;
  o.bundles = 16;
  o.errorSample = 50;
  const FitResult r = fitHairMesh(g, o);
  EXPECT_GT(r.report.error.strands, 0u) << "the error was measured";
  EXPECT_NO_THROW(validateHairMesh(r.mesh, "fitted"));
  EXPECT_GT(r.mesh.faces.size(), 10u);
  EXPECT_EQ(r.mesh.strandCount, 300);
}

TEST(FitSanitized, MoreBundlesThanStrands) {
  const StrandGroom g = straightStrands(61, 5);
  FitOptions o;
  o.bundles = kFitMaxBundles;
  o.errorSample = 50;
  const FitResult r = fitHairMesh(g, o);
  EXPECT_NO_THROW(validateHairMesh(r.mesh, "fitted"));
  EXPECT_LE(r.mesh.faces.size(), 61u) << "no more bundles than strands";
  EXPECT_EQ(r.mesh.strandCount, 61);
}

TEST(FitCli, FitsAFileAndWritesTheReport) {
  const std::string dir = test::scratchDir();
  const StrandGroom g = test::strandsOf(test::patchMesh(PatchShape{}));
  CyHair h;
  for (std::uint32_t c : g.pointCounts) h.segments.push_back(c - 1);
  for (const glm::vec3& p : g.points) h.points.insert(h.points.end(), {p.x, p.y, p.z});
  h.defaultThickness = 7e-5f;
  writeCyHair(h, dir + "/patch.hair");
  const auto res = test::runCli("fit-mesh " + dir + "/patch.hair -o " + dir +
                                "/fit.hairmesh.json --bundles 64 --layers 5 --error-sample 500 "
                                "--report " +
                                dir + "/report.json");
  ASSERT_EQ(res.exitCode, 0) << res.output;
  const HairMesh m = loadHairMesh(dir + "/fit.hairmesh.json");  // validates
  EXPECT_EQ(m.strandCount, 20000);
  EXPECT_EQ(m.layerCount, 5);
  std::ifstream in(dir + "/report.json");
  const nlohmann::json rep = nlohmann::json::parse(in);
  EXPECT_EQ(rep["strands"]["in"], 20000);
  EXPECT_EQ(rep["strands"]["out"], 20000);
  EXPECT_EQ(rep["error"]["strands"], 500);
  EXPECT_GT(rep["error"]["mean_fibre_widths"].get<double>(), 0.0);
  EXPECT_EQ(rep["per_bundle"].size(), m.faces.size());
  EXPECT_GT(rep["size"]["mesh_file_bytes"].get<double>(), 0.0);
  EXPECT_LT(rep["size"]["mesh_over_strand_file_percent"].get<double>(), 10.0);
}

TEST(FitCli, BadInputIsOneErrorLineAndNoOutput) {
  const std::string dir = test::scratchDir();
  auto res = test::runCli("fit-mesh " + dir + "/missing.hair -o " + dir + "/out.json");
  EXPECT_EQ(res.exitCode, 1);
  EXPECT_NE(test::onlyErrorLine(res.output).find("missing.hair"), std::string::npos);
  // a cyHair file whose second point is NaN
  std::ofstream f(dir + "/nan.hair", std::ios::binary);
  auto u32 = [&](std::uint32_t v) { f.write(reinterpret_cast<const char*>(&v), 4); };
  auto f32 = [&](float v) { f.write(reinterpret_cast<const char*>(&v), 4); };
  f.write("HAIR", 4);
  u32(1);      // strands
  u32(2);      // points
  u32(2);      // flags: points only
  u32(1);      // default segments
  f32(1e-4f);  // thickness
  f32(0.0f);   // transparency
  for (int i = 0; i < 3; ++i) f32(1.0f);
  for (int i = 0; i < 88; ++i) f.put('\0');
  for (float v : {0.0f, 0.0f, 0.0f, 0.0f, std::numeric_limits<float>::quiet_NaN(), 0.0f}) f32(v);
  f.close();
  res = test::runCli("fit-mesh " + dir + "/nan.hair -o " + dir + "/out.json");
  EXPECT_EQ(res.exitCode, 1);
  EXPECT_FALSE(test::onlyErrorLine(res.output).empty());
  EXPECT_FALSE(std::filesystem::exists(dir + "/out.json"));
}

}  // namespace
}  // namespace clhair
