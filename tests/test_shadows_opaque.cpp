// test_shadows_opaque.cpp — hair shadows on opaque objects: the ground under a fur ball keeps
// the transmittance Beer-Lambert gives the hair's coverage at any tessellation and map size,
// the LOD depth correction (Lipp §3.2.3) is inert when LOD removes nothing and undoes part of
// LOD's darkening when it does, opaque shadow edges are percentage-closer filtered, and a lit
// sphere does not shadow itself.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "clhair/renderer.h"
#include "groom/presets.h"
#include "test_util.h"

namespace clhair {
namespace {

// The ground in the shadow of a fur ball against the transmittance Beer-Lambert gives the
// hair between it and the light (Yuksel & Keyser 2008; kernels/common/shadow.h: T =
// exp(-density O), O the strands' coverage along the ray, density 1 by default). O is
// computed here from the generated strands: each segment's projected length times the fibre
// width, summed in 2 mm cells of the plane facing the light, over the cell's area. Drawing a
// strand's width into every texel its conservative 1-pixel line touches counts a straight
// line between 1x (along an axis) and sqrt(2)x (diagonal) its area, so the ground should
// keep between exp(-sqrt(2) O) and exp(-O) of its light, within 0.03 for the 2 mm cells (the
// map's ~0.5 mm texels see O vary around the cell's mean; exp is convex, which moves the
// map's mean transmittance up).
struct GroundShadow {
  double ratio = 0.0;               // shadowed / unshadowed ground, around the middle of the shadow
  double lower = 0.0, upper = 0.0;  // Beer-Lambert: mean exp(-sqrt(2) O) and mean exp(-O)
};

GroundShadow groundUnderFurBall(int controlPoints, int mapResolution) {
  HairMesh m = makeGroomPreset("fur_sphere");
  m.strandCount = 80000;
  m.controlPoints = controlPoints;
  Scene s;
  s.width = 96;
  s.height = 96;
  s.ambient = glm::vec3(0.0f);
  Light l;
  l.type = Light::Type::Directional;
  l.direction = glm::normalize(glm::vec3(1.0f, 0.5f, 0.0f));  // low sun from +x
  l.intensity = 2.0f;
  s.lights.push_back(l);
  Plane ground;
  ground.offset = -0.15f;
  s.planes.push_back(ground);
  s.grooms.emplace_back("fur", std::make_shared<const HairMesh>(m));
  s.shadows.resolution = mapResolution;
  // the ball (center 0.15 above the ground) casts its shadow around x = -0.3: look down at it
  s.camera.position = glm::vec3(-0.3f, 0.5f, 0.01f);
  s.camera.target = glm::vec3(-0.3f, -0.15f, 0.0f);
  s.camera.fovYDegrees = 30.0f;
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.shadowLod = Toggle::Off;  // every strand into the map, as counted below
  const Frame lit = r.render(s, o);
  s.lights[0].shadows = true;
  const Frame shadowed = r.render(s, o);

  // O in 2 mm cells of the plane through the origin facing the light
  const glm::vec3 toLight = glm::normalize(l.direction);
  const glm::vec3 ea = glm::normalize(glm::cross(toLight, glm::vec3(0.0f, 0.0f, 1.0f)));
  const glm::vec3 eb = glm::cross(toLight, ea);
  const double cell = 0.002, half = 0.3;
  const int cells = static_cast<int>(2.0 * half / cell);
  std::vector<double> area(static_cast<std::size_t>(cells) * cells, 0.0);
  auto cellOf = [&](const glm::vec3& p) {
    const int i = static_cast<int>(std::floor((glm::dot(p, ea) + half) / cell));
    const int j = static_cast<int>(std::floor((glm::dot(p, eb) + half) / cell));
    return (i < 0 || j < 0 || i >= cells || j >= cells) ? -1 : j * cells + i;
  };
  const StrandSet set = r.generateStrands(m);
  std::size_t first = 0;
  for (std::uint32_t count : set.pointCounts) {
    for (std::uint32_t k = 0; k + 1 < count; ++k) {
      const float* p = &set.points[3 * (first + k)];
      const glm::vec3 a(p[0], p[1], p[2]), b(p[3], p[4], p[5]);
      const glm::vec3 d = b - a;
      const int c = cellOf(0.5f * (a + b));
      if (c >= 0)
        area[c] += std::hypot(glm::dot(d, ea), glm::dot(d, eb)) * m.appearance.strandWidth;
    }
    first += count;
  }

  // the ground point of each pixel: the camera ray through its centre meets y = -0.15
  const glm::vec3 fwd = glm::normalize(s.camera.target - s.camera.position);
  const glm::vec3 right = glm::normalize(glm::cross(fwd, s.camera.up)), up = glm::cross(right, fwd);
  const double f = 0.5 * s.height / std::tan(glm::radians(s.camera.fovYDegrees) * 0.5);
  double litSum = 0, shSum = 0;
  GroundShadow g;
  int n = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      std::size_t i = static_cast<std::size_t>(y) * s.width + x;
      if (std::isinf(lit.depth[i]) || lit.depth[i] < 0.6f) continue;  // ground only
      double dx = x - s.width / 2.0, dy = y - s.height / 2.0;
      if (dx * dx + dy * dy > 12.0 * 12.0) continue;  // the middle of the shadow
      const glm::vec3 ray =
          glm::normalize(fwd + right * static_cast<float>((x + 0.5 - 0.5 * s.width) / f) -
                         up * static_cast<float>((y + 0.5 - 0.5 * s.height) / f));
      const float t = (ground.offset - s.camera.position.y) / ray.y;
      const int c = cellOf(s.camera.position + t * ray);
      EXPECT_GE(c, 0);
      const double coverage = c >= 0 ? area[c] / (cell * cell) : 0.0;
      g.lower += std::exp(-std::sqrt(2.0) * coverage);
      g.upper += std::exp(-coverage);
      litSum += lit.color.rgba[4 * i];
      shSum += shadowed.color.rgba[4 * i];
      ++n;
    }
  EXPECT_GT(n, 20);
  g.ratio = shSum / std::max(litSum, 1e-30);
  g.lower /= std::max(n, 1);
  g.upper /= std::max(n, 1);
  std::printf(
      "[ shadows  ] %d control points, %d texels: the ground keeps %.4f of its light; "
      "Beer-Lambert %.4f .. %.4f\n",
      controlPoints, mapResolution, g.ratio, g.lower, g.upper);
  return g;
}

// The shadow is at least as dark as the hair's coverage makes it (it was absent once, and
// measured against the unshadowed ground only).
TEST(Shadows, OpaqueObjectsReceiveHairShadows) {
  const GroundShadow g = groundUnderFurBall(9, 512);  // the preset's points, the default map
  RecordProperty("ground_shadow_ratio", std::to_string(g.ratio));
  RecordProperty("beer_lambert_upper", std::to_string(g.upper));
  EXPECT_LT(g.upper, 0.9) << "the fur ball should be dense enough to tell a shadow";
  EXPECT_LE(g.ratio, g.upper + 0.03) << "the ground in the fur ball's shadow is too bright";
}

// The deep opacity map gets each strand's area per texel (its width times the length of its
// path through the texel), so the shadow does not depend on how finely the strand is
// tessellated or on the map's size. When it added the width to every texel each segment
// touched, the ground kept 0.59 / 0.49 / 0.35 / 0.18 of its light at 5 / 9 / 17 / 33 points
// and 0.34 / 0.60 with 256 / 1024 texels (PoCL), against 0.65 .. 0.74 from Beer-Lambert;
// then 0.737 / 0.737 / 0.736 at 5 / 9 / 17 points and 0.694 / 0.753 at 256 / 1024 texels, and
// now 0.749 / 0.749 / 0.748 and 0.748 / 0.753: the lower figures at 256 and 512 texels were
// the ground, lit 63 degrees off its normal, shadowing itself across the percentage-closer
// filter's reach until the opaque test compared the receiver's plane (shadow.h).
TEST(Shadows, GroundShadowFollowsBeerLambertAtAnyTessellationAndMapSize) {
  for (auto [points, texels] : {std::pair{5, 512}, {9, 512}, {17, 512}, {9, 256}, {9, 1024}}) {
    const GroundShadow g = groundUnderFurBall(points, texels);
    EXPECT_GE(g.ratio, g.lower - 0.03)
        << points << " control points, " << texels << " texels: too dark";
    EXPECT_LE(g.ratio, g.upper + 0.03)
        << points << " control points, " << texels << " texels: too bright";
  }
}

// Lipp §3.2.3: camera LOD leaves strands visible that full detail hides behind others, so
// they sit deeper in the deep opacity map and shade darker; the lookup moves -log(kept) of
// the first layer toward the light to undo it (kernels/shade.cl, kept = the share of the
// coverage LOD kept: the strands drawn times their widening, which stops at
// CLH_MAX_HIT_DIAMETER). A dense 1-pixel patch lit from behind the camera, at LOD low enough
// that the widening stops (20000 strands, about 1100 drawn: kept ~ 0.17): without LOD the
// correction changes no pixel; with LOD it must brighten the hair and remove at least a
// tenth of LOD's darkening (an inert correction removes none of it; PoCL: a fifth).
TEST(Shadows, LodCorrectionIsInertWithoutLodAndUndoesPartOfLodsDarkening) {
  HairMesh m = makeGroomPreset("tiny");
  m.strandCount = 20000;
  m.appearance.minHitDiameterPx = 1.0f;
  m.lod.strandsPerPixel = 0.0f;  // with LOD, the strands from L (Lipp Eq. 1), thinned by λ
  Scene s;
  s.width = 120;
  s.height = 80;
  s.ambient = glm::vec3(0.0f);
  Light l;
  l.type = Light::Type::Directional;
  l.direction = glm::normalize(glm::vec3(0.0f, 0.3f, 1.0f));  // from behind the camera
  l.intensity = 3.0f;
  l.shadows = true;
  s.lights.push_back(l);
  s.grooms.emplace_back("patch", std::make_shared<const HairMesh>(m), glm::mat4(1.0f));
  s.camera.position = glm::vec3(0.0f, 0.04f, 0.25f);
  s.camera.target = glm::vec3(0.0f, 0.03f, 0.0f);
  s.camera.fovYDegrees = 35.0f;
  Renderer r(test::sharedDevice());
  // mean r + g + b of the pixels with a centre hit
  auto render = [&](Toggle lod, Toggle correction) {
    RenderOptions o;
    o.lod = lod;
    o.lodLambdaScale = 0.03f;
    o.shadowLod = Toggle::Off;  // the maps hold every strand; only the camera's LOD differs
    o.shadowLodCorrection = correction;
    o.filter = Toggle::Off;
    o.captureGBuffer = true;
    Frame f = r.render(s, o);
    double sum = 0;
    int n = 0;
    for (std::size_t i = 0; i < f.depth.size(); ++i)
      if (f.gbuffer[i] != ~std::uint64_t(0)) {
        sum += f.color.rgba[4 * i] + f.color.rgba[4 * i + 1] + f.color.rgba[4 * i + 2];
        ++n;
      }
    EXPECT_GT(n, 500);
    return std::make_pair(sum / std::max(n, 1), f);
  };
  auto [full, fOn] = render(Toggle::Off, Toggle::On);
  auto [fullOff, fOff] = render(Toggle::Off, Toggle::Off);
  EXPECT_TRUE(fOn.color.rgba == fOff.color.rgba)
      << "without LOD the correction must change nothing";
  auto [lod, fLod] = render(Toggle::On, Toggle::Off);
  auto [corrected, fCorrected] = render(Toggle::On, Toggle::On);
  EXPECT_LT(fLod.stats.strandsDrawn, 20000u / 6)
      << "LOD should keep under a sixth: the widening stops at 3 px";
  RecordProperty("luminance_no_lod", std::to_string(full));
  RecordProperty("luminance_lod_uncorrected", std::to_string(lod));
  RecordProperty("luminance_lod_corrected", std::to_string(corrected));
  std::printf("[ shadows  ] hair luminance: no LOD %.5f, LOD %.5f, LOD + correction %.5f\n", full,
              lod, corrected);
  ASSERT_LT(lod, full) << "the scene should show LOD's darkening";
  EXPECT_GT(corrected, lod) << "the correction should brighten what LOD darkened";
  EXPECT_LE(std::fabs(corrected - full), 0.9 * std::fabs(lod - full))
      << "the correction removed under a tenth of the error";
}

// An opaque sphere's shadow on the ground, seen from above at about one map texel per
// pixel, with percentage-closer filtering (ShadowParams::pcf) and without it. Thin strands
// at the corners of a 1-unit box only frame the light's map; the row through the shadow's
// centre does not meet their shadows.
std::vector<float> groundRow(bool pcf) {
  StrandGroom g;
  g.name = "frame";
  for (float x : {-0.5f, 0.5f})
    for (float z : {-0.5f, 0.5f}) {
      g.pointCounts.push_back(2);
      g.points.push_back(glm::vec3(x, 0.0f, z));
      g.points.push_back(glm::vec3(x, 0.5f, z));
    }
  g.appearance.strandWidth = 1e-4f;
  Scene s;
  s.width = 96;
  s.height = 96;
  s.ambient = glm::vec3(0.0f);
  s.background = glm::vec3(0.0f);
  s.grooms.emplace_back("frame", std::make_shared<const StrandGroom>(std::move(g)));
  Plane ground;
  ground.color = glm::vec3(0.5f);
  s.planes.push_back(ground);
  Sphere ball;
  ball.center = glm::vec3(0.0f, 0.5f, 0.0f);
  ball.radius = 0.08f;
  s.spheres.push_back(ball);
  Light l;
  l.direction = glm::normalize(glm::vec3(0.6f, 1.0f, 0.0f));  // the shadow falls at x = -0.3
  l.intensity = 2.0f;
  l.shadows = true;
  s.lights.push_back(l);
  s.shadows.resolution = 256;  // 1.5 units across: 0.006 per texel
  s.shadows.pcf = pcf;
  s.camera.position = glm::vec3(-0.3f, 2.0f, 0.0f);  // 0.6 units across: 0.00625 per pixel
  s.camera.target = glm::vec3(-0.3f, 0.0f, 0.0f);
  s.camera.up = glm::vec3(0.0f, 0.0f, -1.0f);
  s.camera.fovYDegrees = 2.0f * glm::degrees(std::atan(0.3f / 2.0f));
  Renderer r(test::sharedDevice());
  const Frame f = r.render(s);
  std::vector<float> row(s.width);
  for (int x = 0; x < s.width; ++x) row[x] = f.color.pixel(x, s.height / 2)[1];
  return row;
}

// Pixels of a row, from the lit left end to the shadow's centre, strictly between 2 % and
// 98 % of the lit value (the shadow edge's ramp).
int rampPixels(const std::vector<float>& row, int centre) {
  int n = 0;
  for (int x = 0; x <= centre; ++x) n += row[x] > 0.02f * row[0] && row[x] < 0.98f * row[0];
  return n;
}

TEST(Shadows, OpaqueShadowEdgesArePercentageCloserFiltered) {
  const std::vector<float> hard = groundRow(false), soft = groundRow(true);
  const int centre = static_cast<int>(hard.size()) / 2;  // x = -0.3, the shadow's centre
  ASSERT_GT(hard[0], 0.05f) << "the left end of the row is lit";
  ASSERT_EQ(hard[centre], 0.0f) << "the shadow's centre is dark (no ambient light)";
  ASSERT_EQ(soft[centre], 0.0f);
  // the edge: a monotonic ramp over several pixels, wider than the bilinear lookup's
  for (int x = 1; x <= centre; ++x)
    EXPECT_LE(soft[x], soft[x - 1] + 1e-6f) << "pixel " << x << " brightens toward the shadow";
  const int hardRamp = rampPixels(hard, centre), softRamp = rampPixels(soft, centre);
  RecordProperty("ramp_pixels_bilinear", std::to_string(hardRamp));
  RecordProperty("ramp_pixels_pcf", std::to_string(softRamp));
  EXPECT_GE(softRamp, 3);
  EXPECT_GT(softRamp, hardRamp);
  // fully lit and fully shadowed pixels (no edge within 4 pixels) keep their value
  int unchanged = 0;
  for (int x = 4; x + 4 < centre; ++x) {
    bool flat = true;
    for (int d = -4; d <= 4; ++d) flat &= hard[x + d] == hard[x];
    if (!flat) continue;
    ++unchanged;
    EXPECT_NEAR(soft[x], hard[x], 1e-5f * hard[0]) << "pixel " << x;
  }
  for (int x = centre - 2; x <= centre + 2; ++x) EXPECT_EQ(soft[x], 0.0f) << "pixel " << x;
  EXPECT_GT(unchanged, 10);
}

// A lit sphere cannot shadow itself, so with its light's map every pixel of it must keep
// the light it gets without the map. The sphere is seen from between the light and its
// terminator, so its pixels span the angles to the light from 0 to 90 degrees; thin strands
// at the corners of a 1-unit box only frame the light's map (their shadows fall at |z| = 0.5,
// away from the sphere). Compared: the pixels lit at least 10 % of the brightest (the light
// within 84 degrees of the normal: receiver plane slopes are capped only within ~1 degree of
// grazing, kernels/common/shadow.h), within 1e-3 relative (the filter weights sum to one up to
// rounding). With the constant 2-texel bias alone, the surface past ~45 degrees from the light
// shadowed itself across the filter's 4 x 4 texels, in rings that followed the texel grid
// (the default scene's head sphere at 1280 x 720).
struct SelfShadow {
  int compared = 0, darker = 0;  // sphere pixels compared; those that lost light with the map
  double worst = 0.0;            // largest relative loss
};

SelfShadow sphereSelfShadow(bool pcf) {
  StrandGroom g;
  g.name = "frame";
  for (float x : {-0.5f, 0.5f})
    for (float z : {-0.5f, 0.5f}) {
      g.pointCounts.push_back(2);
      g.points.push_back(glm::vec3(x, -0.25f, z));
      g.points.push_back(glm::vec3(x, 0.25f, z));
    }
  g.appearance.strandWidth = 1e-4f;
  Scene s;
  s.width = 80;
  s.height = 72;
  s.ambient = glm::vec3(0.0f);
  s.background = glm::vec3(0.0f);
  s.grooms.emplace_back("frame", std::make_shared<const StrandGroom>(std::move(g)));
  Sphere ball;
  ball.radius = 0.1f;
  ball.color = glm::vec3(0.6f);
  s.spheres.push_back(ball);
  Light l;
  l.direction = glm::normalize(glm::vec3(0.6f, 1.0f, 0.0f));
  l.intensity = 2.0f;
  s.lights.push_back(l);
  s.shadows.pcf = pcf;
  s.camera.position = glm::vec3(0.25f, 0.2f, 0.5f);
  s.camera.target = glm::vec3(0.0f);
  s.camera.fovYDegrees = 24.0f;
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.captureGBuffer = true;
  const Frame open = r.render(s, o);
  s.lights[0].shadows = true;
  const Frame mapped = r.render(s, o);
  float brightest = 0.0f;
  for (std::size_t i = 0; i < open.depth.size(); ++i)
    if (std::isfinite(open.depth[i])) brightest = std::max(brightest, open.color.rgba[4 * i]);
  SelfShadow out;
  for (std::size_t i = 0; i < open.depth.size(); ++i) {
    const float lit = open.color.rgba[4 * i];
    if (!std::isfinite(open.depth[i]) || open.gbuffer[i] != ~std::uint64_t(0) ||
        mapped.gbuffer[i] != ~std::uint64_t(0) || !(lit >= 0.1f * brightest))
      continue;
    ++out.compared;
    const double loss = (lit - mapped.color.rgba[4 * i]) / static_cast<double>(lit);
    out.worst = std::max(out.worst, loss);
    out.darker += loss > 1e-3;
  }
  std::printf("[ shadows  ] sphere, pcf %s: %d of %d lit pixels darker with the map, worst %.4f\n",
              pcf ? "on" : "off", out.darker, out.compared, out.worst);
  return out;
}

TEST(Shadows, LitSphereDoesNotShadowItself) {
  for (bool pcf : {true, false}) {
    const SelfShadow d = sphereSelfShadow(pcf);
    RecordProperty(pcf ? "darker_pixels_pcf" : "darker_pixels_bilinear", d.darker);
    EXPECT_GT(d.compared, 500) << "the sphere should fill much of the frame";
    EXPECT_EQ(d.darker, 0) << "pcf " << pcf << ": the sphere shadows itself (worst loss " << d.worst
                           << " of the light)";
  }
}

}  // namespace
}  // namespace clhair
