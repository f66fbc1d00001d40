// test_diffusion_field.cpp — light diffused through a strand file's groom
// (host/groom/diffusion_field.h) on a hand-made density grid:
//   DiffusionField.NoLightsNoLight        no shadowed light gives a zero field
//   DiffusionField.LightGoesRoundTheGroom  a box of hair lit from one side: fibres that absorb
//                                         little glow on the far side too, fibres that absorb
//                                         much do not, and the glow falls away from the light
//   DiffusionField.OppositeLightsGiveASymmetricField   the solve converges to the symmetric
//                                         field of a symmetric scene
//   DiffusionField.OpaqueVoxelsBlockTheLight  a wall of opaque voxels between the light and
//                                         the hair leaves it dark
#include <gtest/gtest.h>

#include <cmath>

#include "groom/diffusion_field.h"

namespace clhair {
namespace {

constexpr int kN = 20;           // voxels per side
constexpr float kVoxel = 0.01f;  // object units

// A cube of hair in voxels [4, 16) on every axis, optical depth `perVoxel` per voxel.
AoDensity box(float perVoxel) {
  AoDensity d;
  d.grid.lo = {{0.0f, 0.0f, 0.0f, kVoxel}};
  d.grid.dims = {{kN, kN, kN, 0}};
  d.density.assign(std::size_t(kN) * kN * kN, 0u);
  for (int z = 4; z < 16; ++z)
    for (int y = 4; y < 16; ++y)
      for (int x = 4; x < 16; ++x)
        d.density[(std::size_t(z) * kN + y) * kN + x] =
            static_cast<std::uint32_t>(perVoxel / kVoxel * 4096.0f);
  return d;
}

std::size_t at(int x, int y, int z) { return (std::size_t(z) * kN + y) * kN + x; }

DiffusionLight fromPlusX() {
  DiffusionLight l;
  l.at = glm::vec3(1.0f, 0.0f, 0.0f);
  l.radiance = glm::vec3(1.0f);
  return l;
}

TEST(DiffusionField, NoLightsNoLight) {
  const std::vector<glm::vec3> f = diffuseGroomLight(box(2.0f), glm::vec3(0.9f), {}, 1.0f);
  ASSERT_EQ(f.size(), std::size_t(kN) * kN * kN);
  for (const glm::vec3& v : f) EXPECT_EQ(v.x + v.y + v.z, 0.0f);
}

TEST(DiffusionField, LightGoesRoundTheGroom) {
  const std::vector<glm::vec3> f =
      diffuseGroomLight(box(0.5f), glm::vec3(0.99f, 0.6f, 0.2f), {fromPlusX()}, 1.0f);
  for (const glm::vec3& v : f)
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(v[c]) && v[c] >= 0.0f);
  // the slices of the box nearest (x = 15) and farthest (x = 4) from the light
  glm::vec3 nearSide(0.0f), farSide(0.0f);
  for (int z = 4; z < 16; ++z)
    for (int y = 4; y < 16; ++y) {
      nearSide += f[at(15, y, z)];
      farSide += f[at(4, y, z)];
    }
  EXPECT_GT(nearSide.x, 0.0f);
  // 6 optical depths of hair: the unscattered light is nearly gone (e^-6); red, which the fibres
  // hardly absorb, still reaches the far side, blue far less of it
  const float red = farSide.x / nearSide.x, blue = farSide.z / nearSide.z;
  EXPECT_GT(red, 0.2f) << "red far / near";
  EXPECT_LT(blue, 0.2f * red) << "blue far / near " << blue << ", red " << red;
  // the glow falls away from the light along the box's middle row
  for (int x = 5; x < 16; ++x) EXPECT_GT(f[at(x, 10, 10)].x, f[at(x - 1, 10, 10)].x) << "x " << x;
  // beside the box (outside the hair) a lookup finds its neighbours' value, not zero
  EXPECT_GT(f[at(16, 10, 10)].x, 0.5f * f[at(15, 10, 10)].x);
  EXPECT_EQ(f[at(0, 0, 0)].x, 0.0f) << "far from the hair";
}

TEST(DiffusionField, OppositeLightsGiveASymmetricField) {
  DiffusionLight a = fromPlusX(), b = fromPlusX();
  b.at = glm::vec3(-1.0f, 0.0f, 0.0f);
  const std::vector<glm::vec3> f = diffuseGroomLight(box(1.0f), glm::vec3(0.95f), {a, b}, 1.0f);
  for (int z = 4; z < 16; ++z)
    for (int y = 4; y < 16; ++y)
      for (int x = 4; x < 10; ++x) {
        const float l = f[at(x, y, z)].x, r = f[at(19 - x, y, z)].x;
        EXPECT_NEAR(l, r, 0.01f * std::max(l, r) + 1e-7f) << x << " " << y << " " << z;
      }
}

TEST(DiffusionField, OpaqueVoxelsBlockTheLight) {
  AoDensity d = box(1.0f);
  const auto solid = static_cast<std::uint32_t>(32.0f / kVoxel * 4096.0f);
  for (int z = 0; z < kN; ++z)
    for (int y = 0; y < kN; ++y) d.density[at(18, y, z)] = solid;  // a wall at x = 18
  const std::vector<glm::vec3> blocked = diffuseGroomLight(d, glm::vec3(0.9f), {fromPlusX()}, 1.0f);
  double sum = 0.0;
  for (const glm::vec3& v : blocked) sum += v.x;
  EXPECT_EQ(sum, 0.0);
  // and a point light inside the grid, in front of the wall, lights the hair
  DiffusionLight p;
  p.point = true;
  p.at = glm::vec3(0.17f, 0.1f, 0.1f);
  p.radiance = glm::vec3(0.01f);
  const std::vector<glm::vec3> lit = diffuseGroomLight(d, glm::vec3(0.9f), {p}, 1.0f);
  EXPECT_GT(lit[at(15, 10, 10)].x, 0.0f);
}

}  // namespace
}  // namespace clhair
