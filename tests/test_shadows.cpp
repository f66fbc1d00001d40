// test_shadows.cpp — deep opacity maps: hair behind hair (seen from the light) is darker
// than hair in front, opaque objects receive hair shadows, and the LOD depth correction
// (Lipp §3.2.3) is inert when LOD removes nothing and never moves the image away from
// the full-detail one. Instances of one mesh each cast their own shadow.
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "clhair/renderer.h"
#include "groom/presets.h"
#include "test_util.h"

namespace clhair {
namespace {

// Two identical dense patches, one 3 cm behind the other along the light direction (+z),
// seen from the side (+x), so each covers its own half of the image.
Scene twoPatches(bool shadows) {
  HairMesh m = makeGroomPreset("tiny");
  m.strandCount = 3000;
  m.appearance.minHitDiameterPx = 1.0f;
  auto mesh = std::make_shared<const HairMesh>(m);
  Scene s;
  s.width = 120;
  s.height = 80;
  s.ambient = glm::vec3(0.0f);
  Light l;
  l.type = Light::Type::Directional;
  l.direction = glm::vec3(0.0f, 0.0f, 1.0f);  // light comes from +z
  l.intensity = 3.0f;
  l.shadows = shadows;
  s.lights.push_back(l);
  s.grooms.emplace_back("front", mesh, glm::mat4(1.0f));
  s.grooms.emplace_back("back", mesh, glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, -0.06f)));
  s.camera.position = glm::vec3(0.25f, 0.03f, -0.03f);
  s.camera.target = glm::vec3(0.0f, 0.03f, -0.03f);
  s.camera.fovYDegrees = 35.0f;
  return s;
}

// mean luminance of the left (z > -0.03, the front patch) and right halves' non-background pixels
std::pair<double, double> halves(const Frame& f, int width) {
  double sum[2] = {0, 0};
  int n[2] = {0, 0};
  for (std::size_t i = 0; i < f.depth.size(); ++i) {
    if (std::isinf(f.depth[i])) continue;
    int half = static_cast<int>(i % width) < width / 2 ? 0 : 1;
    sum[half] += f.color.rgba[4 * i] + f.color.rgba[4 * i + 1] + f.color.rgba[4 * i + 2];
    ++n[half];
  }
  EXPECT_GT(n[0], 50);
  EXPECT_GT(n[1], 50);
  return {sum[0] / std::max(n[0], 1), sum[1] / std::max(n[1], 1)};
}

TEST(Shadows, HairBehindHairIsDarker) {
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.filter = 0;
  Scene lit = twoPatches(false), shadowed = twoPatches(true);
  // the camera at +x looking at -x: image left is +z (the front patch, nearer the light)
  auto [frontLit, backLit] = halves(r.render(lit, o), lit.width);
  auto [frontSh, backSh] = halves(r.render(shadowed, o), shadowed.width);
  RecordProperty("front_lit", std::to_string(frontLit));
  RecordProperty("back_lit", std::to_string(backLit));
  RecordProperty("front_shadowed", std::to_string(frontSh));
  RecordProperty("back_shadowed", std::to_string(backSh));
  // the BSDF is view dependent, so compare each patch with itself unshadowed: the back
  // patch, in the front one's shadow, keeps a much smaller share of its light
  const double frontKept = frontSh / frontLit, backKept = backSh / backLit;
  RecordProperty("front_kept", std::to_string(frontKept));
  RecordProperty("back_kept", std::to_string(backKept));
  EXPECT_LT(backKept, 0.6 * frontKept) << "front keeps " << frontKept << ", back keeps " << backKept;
  EXPECT_LT(frontKept, 1.0) << "hair shadows itself too";
}

TEST(Shadows, InstancesOfOneMeshCastTheirOwnShadows) {
  // twoPatches draws one mesh twice; the same scene with a copy of the mesh per instance
  // (separate device resources) must give the same image: each instance adds its own
  // opacity to the deep opacity map, at its own place
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.filter = 0;
  Scene shared = twoPatches(true), copies = twoPatches(true);
  copies.grooms[1].mesh = std::make_shared<const HairMesh>(*copies.grooms[1].mesh);
  ASSERT_EQ(shared.grooms[0].mesh, shared.grooms[1].mesh);
  ASSERT_NE(copies.grooms[0].mesh, copies.grooms[1].mesh);
  const Frame a = r.render(copies, o), b = r.render(shared, o);
  ASSERT_EQ(a.color.rgba.size(), b.color.rgba.size());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a.color.rgba.size(); ++i) differing += a.color.rgba[i] != b.color.rgba[i];
  EXPECT_EQ(differing, 0u) << "a shared mesh's instances shadowed differently from separate copies";
}

TEST(Shadows, LightPassLodFollowsTheLightsViewNotTheCameras) {
  // The strands drawn into a deep opacity map are chosen by LOD in the light's view, so
  // the camera's lens and resolution change nothing there. (The hair-mesh path once ran
  // this LOD with the camera's view: its shadow maps drew a fraction of the strands the
  // light's view asks for, while a strand file of the same groom drew all of them.)
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.filter = 0;
  o.lod = 1;
  o.lodLambdaScale = 0.25f;  // small enough that LOD drops strands in the light's view
  auto drawn = [&](float fov, int camW, int camH) {
    Scene s = twoPatches(true);
    s.camera.fovYDegrees = fov;
    s.width = camW;
    s.height = camH;
    return r.render(s, o).stats.shadowStrandsDrawn;
  };
  const std::uint64_t wide = drawn(35.0f, 120, 80), narrow = drawn(8.0f, 120, 80), big = drawn(35.0f, 360, 240);
  RecordProperty("shadow_strands", std::to_string(wide));
  EXPECT_GT(wide, 0u);
  EXPECT_LT(wide, 6000u) << "LOD should drop strands in the light's view (2 patches x 3000)";
  EXPECT_EQ(narrow, wide) << "the camera's field of view changed the shadow pass";
  EXPECT_EQ(big, wide) << "the camera's resolution changed the shadow pass";
}

TEST(Shadows, MapsAreReusedWhileTheirInputsStayAndRebuiltWhenOneChanges) {
  // RenderOptions::reuseShadows keeps the deep opacity maps of the previous frame when
  // nothing they depend on changed: the second frame of a still scene skips the shadow
  // passes and equals a frame that rebuilt them; moving a light or a groom, or changing a
  // shadow setting, rebuilds them, so every frame equals a fresh renderer's.
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.filter = 0;
  auto hasShadowStage = [](const Frame& f) {
    for (const StageTime& t : f.timings)
      if (t.stage == "shadow") return true;
    return false;
  };
  Scene s = twoPatches(true);
  const Frame first = r.render(s, o);
  const Frame second = r.render(s, o);
  EXPECT_TRUE(hasShadowStage(first));
  EXPECT_FALSE(hasShadowStage(second)) << "a still scene rebuilt its shadow maps";
  RenderOptions rebuild = o;
  rebuild.reuseShadows = false;
  const Frame rebuilt = r.render(s, rebuild);
  EXPECT_TRUE(hasShadowStage(rebuilt));
  EXPECT_TRUE(second.color.rgba == rebuilt.color.rgba) << "reused maps differ from rebuilt ones";

  // each change against a fresh renderer that never saw the earlier scene
  auto freshEquals = [&](const Scene& changed, const char* what) {
    const Frame reused = r.render(changed, o);
    EXPECT_TRUE(hasShadowStage(reused)) << what << ": the shadow maps were not rebuilt";
    Renderer fresh(test::sharedDevice());
    EXPECT_TRUE(reused.color.rgba == fresh.render(changed, o).color.rgba) << what << ": stale shadows";
  };
  Scene moved = s;
  moved.lights[0].direction = glm::normalize(glm::vec3(0.3f, 0.2f, 1.0f));
  freshEquals(moved, "light moved");
  Scene groomMoved = moved;
  groomMoved.grooms[1].transform = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.01f, -0.06f));
  freshEquals(groomMoved, "groom moved");
  Scene denser = groomMoved;
  denser.shadows.density = 3.0f;
  freshEquals(denser, "shadow density changed");
}

TEST(Shadows, OpaqueObjectsReceiveHairShadows) {
  HairMesh m = makeGroomPreset("fur_sphere");
  m.strandCount = 80000;
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
  // the ball (center 0.15 above the ground) casts its shadow around x = -0.3: look down at it
  s.camera.position = glm::vec3(-0.3f, 0.5f, 0.01f);
  s.camera.target = glm::vec3(-0.3f, -0.15f, 0.0f);
  s.camera.fovYDegrees = 30.0f;
  Renderer r(test::sharedDevice());
  Frame lit = r.render(s);
  s.lights[0].shadows = true;
  Frame shadowed = r.render(s);
  // ground pixels around the image center lie in the ball's shadow
  double litSum = 0, shSum = 0;
  int n = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      std::size_t i = static_cast<std::size_t>(y) * s.width + x;
      if (std::isinf(lit.depth[i]) || lit.depth[i] < 0.6f) continue;  // ground only
      double dx = x - s.width / 2.0, dy = y - s.height / 2.0;
      if (dx * dx + dy * dy > 12.0 * 12.0) continue;  // the middle of the shadow
      litSum += lit.color.rgba[4 * i];
      shSum += shadowed.color.rgba[4 * i];
      ++n;
    }
  ASSERT_GT(n, 20);
  // the ball is a hollow shell of fur: its shadow is partial (measured ~0.75 of the light)
  EXPECT_LT(shSum, 0.85 * litSum) << "ground in the fur ball's shadow";
  RecordProperty("ground_shadow_ratio", std::to_string(shSum / litSum));
}

TEST(Shadows, LodCorrectionIsInertWithoutLodAndNeverHurts) {
  Scene s = loadScene(test::assetPath("scenes/default.json"));
  s.width = 200;
  s.height = 112;
  s.camera = framePreset(s, CameraPreset::Far, 35.0f, 10.0f, 35.0f);
  Renderer r(test::sharedDevice());
  auto mean = [&](int lod, int correction) {
    RenderOptions o;
    o.lod = lod;
    o.shadowLod = 0;
    o.shadowLodCorrection = correction;
    o.filter = 0;
    o.captureGBuffer = true;
    Frame f = r.render(s, o);
    double sum = 0;
    int n = 0;
    const std::size_t pixels = f.depth.size();
    for (std::size_t i = 0; i < pixels; ++i)
      if (f.gbuffer[i] != ~std::uint64_t(0)) {
        sum += f.color.rgba[4 * i] + f.color.rgba[4 * i + 1] + f.color.rgba[4 * i + 2];
        ++n;
      }
    return std::make_pair(sum / std::max(n, 1), f);
  };
  auto [fullOn, fOn] = mean(0, 1);
  auto [fullOff, fOff] = mean(0, 0);
  EXPECT_TRUE(fOn.color.rgba == fOff.color.rgba) << "without LOD the correction must change nothing";
  double lodOff = mean(1, 0).first, lodOn = mean(1, 1).first;
  RecordProperty("far_luminance_no_lod", std::to_string(fullOn));
  RecordProperty("far_luminance_lod_uncorrected", std::to_string(lodOff));
  RecordProperty("far_luminance_lod_corrected", std::to_string(lodOn));
  std::printf("[ shadows  ] far hair luminance: no LOD %.5f, LOD %.5f, LOD + correction %.5f\n", fullOn, lodOff, lodOn);
  EXPECT_LE(std::fabs(lodOn - fullOn), std::fabs(lodOff - fullOn) + 1e-6);
}

}  // namespace
}  // namespace clhair
