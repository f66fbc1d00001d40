// test_hair_extent.cpp — the box the light maps frame (GroomGpu::hairMin/hairMax,
// HairMeshGpu::hairExtent): for a hair mesh at rest it is the extent of every point the groom
// draws, within the conservative bounds and far tighter than they are for a styled groom; a
// deformed cage goes back to the bounds, and the box is kept in the cache folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>

#include "clhair/hair_mesh.h"
#include "groom_stages.h"
#include "test_util.h"

namespace clhair::test {
namespace {

float volume(glm::vec3 lo, glm::vec3 hi) {
  const glm::vec3 d = glm::max(hi - lo, glm::vec3(0.0f));
  return d.x * d.y * d.z;
}

TEST(HairExtent, HoldsEveryDrawnPointWithinTheBoundsAndFarTighter) {
  const HairMesh mesh = loadHairMesh(assetPath("grooms/long_wavy.hairmesh.json"));
  GroomStagesOnDevice st;
  HairMeshGpu g(std::make_shared<const HairMesh>(mesh), st.stages, true);
  const glm::vec3 lo = g.hairMin(), hi = g.hairMax();
  for (int a = 0; a < 3; ++a) {
    EXPECT_GE(lo[a], g.boundsMin()[a]) << "axis " << a;
    EXPECT_LE(hi[a], g.boundsMax()[a]) << "axis " << a;
  }
  // every point of every strand at full detail (127,000 strands, all of them measured)
  const StrandSet all = g.exportStrands(1.0f);
  ASSERT_GT(all.pointCounts.size(), 20000u);
  glm::vec3 plo(1e30f), phi(-1e30f);
  for (std::size_t i = 0; i + 2 < all.points.size(); i += 3) {
    const glm::vec3 p(all.points[i], all.points[i + 1], all.points[i + 2]);
    plo = glm::min(plo, p);
    phi = glm::max(phi, p);
  }
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(lo[a], plo[a]) << "axis " << a;
    EXPECT_GE(hi[a], phi[a]) << "axis " << a;
  }
  const float ratio = volume(lo, hi) / volume(g.boundsMin(), g.boundsMax());
  RecordProperty("box_over_bounds_volume", std::to_string(ratio));
  EXPECT_LT(ratio, 0.3f) << "the bounds add every styling offset's reach on every side";
  EXPECT_EQ(lo, plo) << "every strand measured: the box is the points' own";
  EXPECT_EQ(hi, phi);

  // a deformed cage: the bounds; a cage equal to the rest pose and the rest pose: the box
  std::vector<glm::vec3> moved = mesh.positions;
  for (glm::vec3& p : moved) p.x += 0.01f;
  g.deform(std::make_shared<const std::vector<glm::vec3>>(moved));
  EXPECT_EQ(g.hairMin(), g.boundsMin());
  EXPECT_EQ(g.hairMax(), g.boundsMax());
  g.deform(std::make_shared<const std::vector<glm::vec3>>(mesh.positions));
  EXPECT_EQ(g.hairMin(), lo);
  EXPECT_EQ(g.hairMax(), hi);
  g.deform(nullptr);
  EXPECT_EQ(g.hairMin(), lo);
  EXPECT_EQ(g.hairMax(), hi);
}

// Kept with the AO bake: the same mesh reads its box back from the cache folder, another
// mesh has an entry of its own, and a damaged entry is measured again.
TEST(HairExtent, IsKeptInTheCacheFolder) {
  const std::string dir = scratchDir() + "/cache";
  Device dev = openWithCache(dir, false);
  GroomStagesOnDevice st(*dev.impl());
  GroomStages& stages = st.stages;
  HairMesh mesh = loadHairMesh(assetPath("grooms/tiny.hairmesh.json"));
  mesh.strandCount = 2000;
  const auto measured = HairMeshGpu::hairExtent(mesh, stages);
  ASSERT_LE(measured.first.x, measured.second.x);
  std::vector<std::filesystem::path> stored;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.path().extension() == ".extent") stored.push_back(e.path());
  ASSERT_EQ(stored.size(), 1u);
  EXPECT_EQ(HairMeshGpu::hairExtent(mesh, stages), measured);
  // another mesh is another entry
  HairMesh other = mesh;
  other.strandCount = 1000;
  HairMeshGpu::hairExtent(other, stages);
  std::size_t n = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    n += e.path().extension() == ".extent" ? 1u : 0u;
  EXPECT_EQ(n, 2u);
  // a damaged entry (cut short) is measured again
  std::filesystem::resize_file(stored[0], 3);
  EXPECT_EQ(HairMeshGpu::hairExtent(mesh, stages), measured);
}

}  // namespace
}  // namespace clhair::test
