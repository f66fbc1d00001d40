// test_children.cpp — children grown from guides on the device (kernels/common/children.h)
// against the CPU rules of host/groom/children.h: follow hairs and interpolated children
// point for point, the interpolation on a synthetic scalp of three guides, LOD keeping the
// guides first, and the coverage of children against the same children drawn from a file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include <glm/geometric.hpp>

#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "groom/children.h"
#include "groom/explicit_data.h"
#include "synthetic_groom.h"
#include "test_util.h"

namespace clhair {
namespace {

float groomSize(const ExplicitData& d) { return glm::length(d.boundsMax - d.boundsMin); }

// Every drawn strand of the export at full detail against the CPU rules: strand i of the
// export is drawn strand i (guide i % G, child i / G). Returns the worst distance.
float worstDistance(Renderer& r, const StrandGroom& g) {
  const ExplicitData d = prepareExplicit(g);
  const StrandSet e = r.generateStrands(g, 1.0f);
  const std::size_t G = d.totalStrands;
  EXPECT_EQ(e.pointCounts.size(), G * (g.children.count + 1));
  if (e.pointCounts.size() != G * (g.children.count + 1)) return 1e30f;
  float worst = 0.0f;
  std::size_t at = 0;
  for (std::size_t i = 0; i < e.pointCounts.size(); ++i) {
    const auto guide = static_cast<std::uint32_t>(i % G), child = static_cast<std::uint32_t>(i / G);
    const std::uint32_t n = d.strandOffsets[guide + 1] - d.strandOffsets[guide];
    EXPECT_EQ(e.pointCounts[i], n) << "strand " << i;
    std::vector<glm::vec3> ref;
    if (child == 0)
      for (std::uint32_t k = 0; k < n; ++k) ref.emplace_back(d.points[d.strandOffsets[guide] + k]);
    else
      ref = childPoints(d, d.kids, d.neighbours, guide, child);
    for (std::uint32_t k = 0; k < std::min(n, e.pointCounts[i]); ++k) {
      const glm::vec3 p(e.points[3 * (at + k)], e.points[3 * (at + k) + 1],
                        e.points[3 * (at + k) + 2]);
      worst = std::max(worst, glm::length(p - ref[k]));
    }
    at += e.pointCounts[i];
  }
  return worst;
}

TEST(Children, FollowHairsMatchTheCpuRules) {
  StrandGroom g = test::syntheticGroom(150);  // 3 chunks; 2 to 300 points per strand
  g.children.count = 5;
  g.children.radius = 0.004f;
  g.children.tipSpread = 2.0f;
  g.children.clump = 0.3f;
  Renderer r(test::sharedDevice());
  const float size = groomSize(prepareExplicit(g));
  const float worst = worstDistance(r, g);
  EXPECT_LE(worst, 1e-4f * size) << "groom size " << size;
  // the children really leave their guides (the rule is not the identity)
  const ExplicitData d = prepareExplicit(g);
  const std::vector<glm::vec3> c = childPoints(d, d.kids, d.neighbours, 7, 3);
  EXPECT_GT(glm::length(c[0] - glm::vec3(d.points[d.strandOffsets[7]])), 1e-4f);
}

TEST(Children, FollowClumpAndSpreadFollowTressFxAndBlender) {
  StrandGroom g = test::syntheticGroom(3);
  g.children.count = 2;
  g.children.radius = 0.01f;
  g.children.tipSpread = 2.0f;
  const ExplicitData d = prepareExplicit(g);
  std::uint32_t s = 0;  // the strand of 4 points
  while (s < 3 && d.strandOffsets[s + 1] - d.strandOffsets[s] != 4) ++s;
  ASSERT_LT(s, 3u);
  const std::uint32_t first = d.strandOffsets[s], n = d.strandOffsets[s + 1] - first;
  const std::vector<glm::vec3> c = childPoints(d, d.kids, d.neighbours, s, 1);
  const glm::vec3 o = c[0] - glm::vec3(d.points[first]);
  for (std::uint32_t k = 0; k < n; ++k)  // TressFX: offset times 1 + s k / n
    EXPECT_NEAR(glm::length(c[k] - glm::vec3(d.points[first + k]) - o * (1.0f + 2.0f * k / 4.0f)),
                0.0f, 1e-6f);
  // the offset lies across the root direction, within the square of half side R
  const glm::vec3 root = glm::normalize(glm::vec3(d.points[first + 1] - d.points[first]));
  EXPECT_NEAR(glm::dot(o, root), 0.0f, 1e-6f);
  EXPECT_LE(glm::length(o), 0.01f * std::sqrt(2.0f) + 1e-6f);
  // clump 1 brings the tip back onto the guide
  g.children.clump = 1.0f;
  const ExplicitData dc = prepareExplicit(g);
  const std::vector<glm::vec3> cc = childPoints(dc, dc.kids, dc.neighbours, s, 1);
  EXPECT_NEAR(glm::length(cc[n - 1] - glm::vec3(dc.points[first + n - 1])), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(cc[0] - c[0]), 0.0f, 1e-6f);
}

TEST(Children, InterpolatedChildrenMatchTheCpuRules) {
  StrandGroom g = test::syntheticGroom(150);
  g.children.mode = ChildrenParams::Mode::Interpolated;
  g.children.count = 4;
  g.children.radius = 0.0f;  // half the guide spacing
  Renderer r(test::sharedDevice());
  const ExplicitData d = prepareExplicit(g);
  EXPECT_GT(d.kids.radius, 0.0f);
  const float size = groomSize(d);
  EXPECT_LE(worstDistance(r, g), 1e-4f * size);
}

// Three guides on a flat scalp, roots at the corners of an equilateral triangle, each its
// own shape and point count.
StrandGroom threeGuides() {
  StrandGroom g;
  g.name = "three";
  const std::uint32_t counts[3] = {9, 5, 17};
  for (int i = 0; i < 3; ++i) {
    const float a = 2.0944f * static_cast<float>(i);
    // away from the origin: a root's coordinates plus the tiny offsets below stay the root
    const glm::vec3 root =
        glm::vec3(0.05f, 0.02f, 0.03f) + glm::vec3(0.01f * std::cos(a), 0.0f, 0.01f * std::sin(a));
    g.pointCounts.push_back(counts[i]);
    for (std::uint32_t k = 0; k < counts[i]; ++k) {
      const float t = static_cast<float>(k) / static_cast<float>(counts[i] - 1);
      g.points.push_back(root + glm::vec3(0.02f * t * (i - 1.0f), -0.1f * t,
                                          0.01f * (std::sin(6.0f * t + static_cast<float>(i)) -
                                                   std::sin(static_cast<float>(i)))));
    }
  }
  return g;
}

TEST(Children, InterpolatedChildOnAGuideRootFollowsThatGuide) {
  StrandGroom g = threeGuides();
  g.children.mode = ChildrenParams::Mode::Interpolated;
  g.children.count = 3;
  g.children.radius = 1e-30f;  // the roots land on the guides' roots
  Renderer r(test::sharedDevice());
  const StrandSet e = r.generateStrands(g, 1.0f);
  const ExplicitData d = prepareExplicit(g);
  ASSERT_EQ(e.pointCounts.size(), 12u);
  std::size_t at = 0;
  for (std::size_t i = 0; i < e.pointCounts.size(); ++i) {
    const std::size_t guide = i % 3;
    const std::uint32_t first = d.strandOffsets[guide];
    ASSERT_EQ(e.pointCounts[i], d.strandOffsets[guide + 1] - first);
    for (std::uint32_t k = 0; k < e.pointCounts[i]; ++k)
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(e.points[3 * (at + k) + c], d.points[first + k][c])
            << "strand " << i << " point " << k;
    at += e.pointCounts[i];
  }
}

TEST(Children, InterpolatedChildAtTheCentroidFollowsTheAverage) {
  const StrandGroom g = threeGuides();
  const ExplicitData d = prepareExplicit(g);
  std::vector<glm::vec3> roots;
  for (std::uint32_t s = 0; s < 3; ++s) roots.emplace_back(d.points[d.strandOffsets[s]]);
  const glm::vec3 centroid = (roots[0] + roots[1] + roots[2]) / 3.0f;
  const ChildBlend b = childBlend(centroid, roots);
  ASSERT_EQ(b.count, 3);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(b.weight[i], 1.0f / 3.0f, 1e-5f);
  // at a guide's root the blend is that guide alone
  for (std::uint32_t s = 0; s < 3; ++s) {
    const ChildBlend on = childBlend(roots[s], roots);
    ASSERT_EQ(on.count, 1);
    EXPECT_EQ(on.index[0], s);
    EXPECT_EQ(on.weight[0], 1.0f);
  }
  // near the centroid the blend is close to the average (continuous), and it leans toward
  // the nearer guide
  const ChildBlend near = childBlend(centroid + 0.1f * (roots[0] - centroid), roots);
  float w0 = 0.0f;
  for (int i = 0; i < near.count; ++i)
    if (near.index[i] == 0) w0 = near.weight[i];
  EXPECT_GT(w0, 1.0f / 3.0f);
  EXPECT_LT(w0, 0.5f);
}

TEST(Children, LodKeepsTheGuidesFirstAndWidensTheRest) {
  StrandGroom g = test::syntheticGroom(150);
  g.children.count = 5;
  g.children.radius = 0.004f;
  Renderer r(test::sharedDevice());
  const StrandSet full = r.generateStrands(g, 1.0f);
  const StrandSet far = r.generateStrands(g, 0.25f);
  EXPECT_EQ(full.pointCounts.size(), 900u);
  EXPECT_LT(far.pointCounts.size(), 400u);
  // every guide is still drawn: a chunk's slots hold its guides before any child
  std::set<std::uint32_t> guides;
  for (std::size_t i = 0; i < far.uv.size() / 2; ++i) guides.insert(far.sourceStrand[i]);
  EXPECT_EQ(guides.size(), 150u);
  EXPECT_GT(far.pointCounts.size(), 150u) << "children beyond the guides at L = 0.25";
}

// The hair mask of a groom of guides and children against the same strands exported and
// drawn as a strand file, at close and far (LOD on: fewer children, widened).
TEST(Children, CoverageMatchesTheSameStrandsFromAFile) {
  StrandGroom g = test::syntheticGroom(300);  // 5100 strands: a closed mask at far
  g.children.count = 16;
  g.children.radius = 0.003f;
  g.children.tipSpread = 2.0f;
  g.lod.enabled = true;
  g.appearance.strandWidth = 2e-4f;
  Renderer r(test::sharedDevice());
  StrandSet e = r.generateStrands(g, 1.0f);
  StrandGroom file;
  file.name = "exported";
  file.pointCounts = e.pointCounts;
  for (std::size_t i = 0; i < e.points.size(); i += 3)
    file.points.emplace_back(e.points[i], e.points[i + 1], e.points[i + 2]);
  file.appearance = g.appearance;
  file.lod = g.lod;
  auto mask = [&](const StrandGroom& groom, CameraPreset preset) {
    Scene s;
    // far: 1080 rows as in the benchmark's 1920x1080, the groom 54 pixels high
    s.width = preset == CameraPreset::Far ? 1080 : 160;
    s.height = preset == CameraPreset::Far ? 1080 : 120;
    s.grooms.emplace_back("g", std::make_shared<const StrandGroom>(file));
    s.camera = framePreset(s, preset);  // one camera for both
    s.grooms[0].strands = std::make_shared<const StrandGroom>(groom);
    const Frame f = r.render(s, RenderOptions{});
    std::vector<bool> m(f.depth.size());
    for (std::size_t i = 0; i < m.size(); ++i) m[i] = std::isfinite(f.depth[i]);
    return m;
  };
  auto iou = [](const std::vector<bool>& a, const std::vector<bool>& b, std::size_t* hair) {
    std::size_t inter = 0, uni = 0;
    *hair = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      inter += a[i] && b[i];
      uni += a[i] || b[i];
      *hair += a[i];
    }
    return uni ? static_cast<double>(inter) / static_cast<double>(uni) : 0.0;
  };
  std::size_t hair = 0;
  // close, LOD on
  const double close = iou(mask(g, CameraPreset::Close), mask(file, CameraPreset::Close), &hair);
  EXPECT_GT(hair, 500u);
  EXPECT_GE(close, 0.9) << "close";
  // far: LOD draws a random share of each chunk, widened; two draws of the same file with
  // other chunk shuffles (another seed) already differ at the edges of the mask, so the
  // children are held to that floor (measured 0.874 against 0.873), and to 0.9 without LOD
  StrandGroom reseeded = file;
  reseeded.seed = 7;
  const double floor = iou(mask(file, CameraPreset::Far), mask(reseeded, CameraPreset::Far), &hair);
  const double far = iou(mask(g, CameraPreset::Far), mask(file, CameraPreset::Far), &hair);
  EXPECT_GT(hair, 300u);
  EXPECT_GE(far, floor - 0.02) << "far, LOD on; the file against itself reseeded: " << floor;
  StrandGroom gAll = g, fileAll = file;
  gAll.lod.enabled = fileAll.lod.enabled = false;
  const double farAll = iou(mask(gAll, CameraPreset::Far), mask(fileAll, CameraPreset::Far), &hair);
  EXPECT_GE(farAll, 0.9) << "far, LOD off";
  std::printf(
      "hair mask IoU: close %.3f, far %.3f (the file against itself reseeded %.3f), "
      "far without LOD %.3f\n",
      close, far, floor, farAll);
  // without its children the groom covers clearly less (the test can fail)
  StrandGroom bare = g;
  bare.children.count = 0;
  const std::vector<bool> a = mask(bare, CameraPreset::Close), b = mask(file, CameraPreset::Close);
  std::size_t inter = 0, uni = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    inter += a[i] && b[i];
    uni += a[i] || b[i];
  }
  EXPECT_LT(static_cast<double>(inter) / static_cast<double>(uni), 0.9);
}

}  // namespace
}  // namespace clhair
