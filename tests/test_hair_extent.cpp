// test_hair_extent.cpp — the box the light maps frame (GroomGpu::hairMin/hairMax,
// HairMeshGpu::hairExtent): for a hair mesh at rest it holds every point the groom draws,
// lies within the conservative bounds, and is far tighter than they are for a styled groom;
// a deformed cage goes back to the bounds, and the box is kept in the cache folder.
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
  // every point of every strand at full detail (127,000 strands; the box was measured on a
  // sample of 20,000 and widened)
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
  EXPECT_GT(volume(lo, hi), 0.9f * volume(plo, phi));

  // a deformed cage: the bounds; at rest again: the box
  g.deform(std::make_shared<const std::vector<glm::vec3>>(mesh.positions));
  EXPECT_EQ(g.hairMin(), g.boundsMin());
  EXPECT_EQ(g.hairMax(), g.boundsMax());
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
