// test_ao_field.cpp — the AO field of a strand file (host/groom/ao_field.h, kernels/ao.cl
// ao_field, kernels/common/ao_field.h): the splat keeps the fibres' extinction, a dense slab
// is black inside and about half open at the middle of a face, an opaque sphere under the
// slab takes light from the face it touches, and the shading of a strand file under
// ambient light follows it.
#include <cmath>
#include <memory>

#include <glm/geometric.hpp>

#include "clhair/renderer.h"
#include "groom/ao_field.h"
#include "groom/explicit_data.h"
#include "test_util.h"

namespace clhair {
namespace {

// 81 x 81 straight strands 0.25 mm apart, 2 cm long along +y, over a 2 x 2 cm square at
// y = 0: with fibres of 70 um, sigma_t = 1.6e7 / m^2 x 7e-5 m = 1120 / m, an optical depth
// of 11 per cm.
StrandGroom slab() {
  StrandGroom g;
  g.name = "slab";
  g.appearance.strandWidth = 7e-5f;
  for (int i = 0; i < 81; ++i)
    for (int j = 0; j < 81; ++j) {
      g.pointCounts.push_back(3);
      for (int k = 0; k < 3; ++k)
        g.points.push_back(glm::vec3(-0.01f + 0.00025f * i, 0.01f * k, -0.01f + 0.00025f * j));
    }
  return g;
}

std::size_t voxelAt(const AoDensity& d, glm::vec3 p) {
  const float v = d.grid.lo.s[3];
  const auto ix = static_cast<std::size_t>((p.x - d.grid.lo.s[0]) / v);
  const auto iy = static_cast<std::size_t>((p.y - d.grid.lo.s[1]) / v);
  const auto iz = static_cast<std::size_t>((p.z - d.grid.lo.s[2]) / v);
  return (iz * d.grid.dims.s[1] + iy) * d.grid.dims.s[0] + ix;
}

TEST(AoField, SlabIsBlackInsideHalfOpenOnAFaceAndASphereUnderItBlocks) {
  const ExplicitData d = prepareExplicit(slab());
  const AoDensity density = splatAoDensity(d, 7e-5f, 1.0f);
  ASSERT_FALSE(density.density.empty());
  // the splat keeps the extinction: sum of sigma_t x voxel volume = length x width
  const double voxel = density.grid.lo.s[3];
  double sum = 0.0;
  for (std::uint32_t v : density.density) sum += v / 4096.0 * voxel * voxel * voxel;
  EXPECT_NEAR(sum, 81.0 * 81.0 * 0.02 * 7e-5, 0.01 * 81.0 * 81.0 * 0.02 * 7e-5);

  auto& dev = *test::sharedDevice().impl();
  AoStage stage(dev);
  const std::vector<float> ao = stage.field(density.density, density.grid);
  ASSERT_EQ(ao.size(), density.density.size());
  for (float a : ao) {
    ASSERT_GE(a, 0.0f);
    ASSERT_LE(a, 1.0f);
  }
  const float centre = ao[voxelAt(density, {0.0f, 0.01f, 0.0f})];
  // the middle of the +x face: the voxel just outside the hair
  const float face = ao[voxelAt(density, {0.0105f + 0.5f * float(voxel), 0.01f, 0.0f})];
  RecordProperty("ao_corner", std::to_string(ao[0]));
  // the grid's corner, a voxel off the slab's corner, sees more than the face
  EXPECT_GT(ao[0], face);
  EXPECT_LT(centre, 0.02f) << "every direction crosses 0.5 cm of hair or more";
  EXPECT_GT(face, 0.35f) << "about the half of the directions that leave the slab";
  EXPECT_LT(face, 0.65f);
  RecordProperty("ao_centre", std::to_string(centre));
  RecordProperty("ao_face", std::to_string(face));

  // an opaque sphere under the slab, touching its bottom face: the bottom's open
  // directions point into it
  Scene scene;
  scene.spheres.push_back({glm::vec3(0.0f, -0.0205f, 0.0f), 0.02f, glm::vec3(0.5f)});
  const AoDensity blocked = withOccluders(density, scene, glm::mat4(1.0f));
  const std::vector<float> aoBlocked = stage.field(blocked.density, blocked.grid);
  const glm::vec3 bottom(0.0f, -0.3f * float(voxel), 0.0f), top(0.0f, 0.0203f, 0.0f);
  RecordProperty("ao_bottom", std::to_string(ao[voxelAt(density, bottom)]));
  RecordProperty("ao_bottom_on_sphere", std::to_string(aoBlocked[voxelAt(density, bottom)]));
  EXPECT_LT(aoBlocked[voxelAt(density, bottom)], 0.5f * ao[voxelAt(density, bottom)]);
  EXPECT_NEAR(aoBlocked[voxelAt(density, top)], ao[voxelAt(density, top)], 0.05f)
      << "the top face sees past the slab, away from the sphere";
}

// A strand file under ambient light only: with AO its hair is darker than with `ao off`
// (the field's inside is black), and without AO the field is not read at all.
TEST(AoField, AmbientLightOnAStrandFileFollowsItsField) {
  Scene s;
  s.width = 96;
  s.height = 96;
  s.background = glm::vec3(0.0f);
  s.ambient = glm::vec3(1.0f);
  s.grooms.push_back(GroomInstance("slab", std::make_shared<const StrandGroom>(slab())));
  s.camera.position = glm::vec3(0.05f, 0.03f, 0.06f);
  s.camera.target = glm::vec3(0.0f, 0.01f, 0.0f);
  s.camera.fovYDegrees = 40.0f;
  Renderer r(test::sharedDevice());
  RenderOptions on, off;
  off.ambientOcclusion = false;
  const Image a = r.render(s, on).color, b = r.render(s, off).color;
  double sa = 0.0, sb = 0.0, alpha = 0.0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      sa += a.pixel(x, y)[1];
      sb += b.pixel(x, y)[1];
      alpha += b.pixel(x, y)[3];
    }
  ASSERT_GT(alpha, 200.0) << "the slab covers part of the frame";
  RecordProperty("ambient_with_ao_over_without", std::to_string(sa / sb));
  EXPECT_LT(sa, 0.8 * sb);
  EXPECT_GT(sa, 0.1 * sb) << "the outer fibres stay lit";
}

}  // namespace
}  // namespace clhair
