// test_shadows.cpp — deep opacity maps: hair behind hair (seen from the light) is darker
// than hair in front; instances of one mesh each cast their own shadow; the lights' passes
// take their LOD from the light's view, capped by the camera's; maps are kept while their
// inputs stay. Shadows on opaque objects, the LOD depth correction and filtered edges:
// test_shadows_opaque.cpp.
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

// Two identical dense patches, one 3 cm behind the other along the light direction (+z),
// seen from the side (+x), so each covers its own half of the image.
Scene twoPatches(bool shadows) {
  HairMesh m = makeGroomPreset("tiny");
  m.lod.strandsPerPixel = 0.0f;  // with LOD, the strands from L (Lipp Eq. 1)
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
  s.grooms.emplace_back("back", mesh,
                        glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, -0.06f)));
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
  o.filter = Toggle::Off;
  // the map's attenuation alone: the light scattered through the front patch (dual
  // scattering, tests/test_dual.cpp) gives some of it back and is measured apart
  o.multipleScattering = false;
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
  EXPECT_LT(backKept, 0.6 * frontKept)
      << "front keeps " << frontKept << ", back keeps " << backKept;
  EXPECT_LT(frontKept, 1.0) << "hair shadows itself too";
}

TEST(Shadows, LightScatteredThroughTheFrontPatchReachesTheBackOne) {
  // dual scattering (hair_dual.h) gives the shadowed back patch part of what the front one
  // scattered forward: brighter than with the map's attenuation alone, and never brighter
  // than unshadowed
  Renderer r(test::sharedDevice());
  RenderOptions single, dual;
  single.filter = dual.filter = Toggle::Off;
  single.multipleScattering = false;
  const Scene lit = twoPatches(false), shadowed = twoPatches(true);
  const double backLit = halves(r.render(lit, single), lit.width).second;
  const double backSingle = halves(r.render(shadowed, single), shadowed.width).second;
  const double backDual = halves(r.render(shadowed, dual), shadowed.width).second;
  EXPECT_GT(backDual, backSingle * 1.01) << "single " << backSingle << ", dual " << backDual;
  EXPECT_LT(backDual, backLit) << "lit " << backLit << ", dual " << backDual;
}

TEST(Shadows, InstancesOfOneMeshCastTheirOwnShadows) {
  // twoPatches draws one mesh twice; the same scene with a copy of the mesh per instance
  // (separate device resources) must give the same image: each instance adds its own
  // opacity to the deep opacity map, at its own place
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.filter = Toggle::Off;
  Scene shared = twoPatches(true), copies = twoPatches(true);
  copies.grooms[1].mesh = std::make_shared<const HairMesh>(*copies.grooms[1].mesh);
  ASSERT_EQ(shared.grooms[0].mesh, shared.grooms[1].mesh);
  ASSERT_NE(copies.grooms[0].mesh, copies.grooms[1].mesh);
  const Frame a = r.render(copies, o), b = r.render(shared, o);
  ASSERT_EQ(a.color.rgba.size(), b.color.rgba.size());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a.color.rgba.size(); ++i)
    differing += a.color.rgba[i] != b.color.rgba[i];
  EXPECT_EQ(differing, 0u) << "a shared mesh's instances shadowed differently from separate copies";
}

TEST(Shadows, LightPassLodFollowsTheLightsViewNotTheCameras) {
  // Without the camera's cap (RenderOptions::shadowLodCamera 0) the strands drawn into a
  // deep opacity map are chosen by LOD in the light's view alone, so the camera's lens and
  // resolution change nothing there. (The hair-mesh path once ran this LOD with the
  // camera's view instead: its shadow maps drew a fraction of the strands the light's view
  // asks for, while a strand file of the same groom drew all of them.)
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.filter = Toggle::Off;
  o.lod = Toggle::On;
  o.shadowLodCamera = Toggle::Off;
  o.shadowResFromCamera = false;  // the maps at the scene's resolution, not the camera's
  o.lodLambdaScale = 0.25f;       // small enough that LOD drops strands in the light's view
  auto drawn = [&](float fov, int camW, int camH) {
    Scene s = twoPatches(true);
    s.camera.fovYDegrees = fov;
    s.width = camW;
    s.height = camH;
    return r.render(s, o).stats.shadowStrandsDrawn;
  };
  const std::uint64_t wide = drawn(35.0f, 120, 80), narrow = drawn(8.0f, 120, 80),
                      big = drawn(35.0f, 360, 240);
  RecordProperty("shadow_strands", std::to_string(wide));
  EXPECT_GT(wide, 0u);
  EXPECT_LT(wide, 6000u) << "LOD should drop strands in the light's view (2 patches x 3000)";
  EXPECT_EQ(narrow, wide) << "the camera's field of view changed the shadow pass";
  EXPECT_EQ(big, wide) << "the camera's resolution changed the shadow pass";
}

// The lights' passes draw no more strands per bundle than the camera's LOD (DESIGN.md,
// "Light-pass LOD from the camera"): a groom far from the camera draws at most the
// camera's strands into its map, fewer than its light's view alone asks for; close to the
// camera, which then needs every strand, the map draws every strand again.
TEST(Shadows, LightPassLodDrawsNoMoreThanTheCameraNeeds) {
  HairMesh m = makeGroomPreset("tiny");
  m.strandCount = 3000;
  m.lod.enabled = true;
  m.lod.lambda = 3.0f;
  m.lod.strandsPerPixel = 0.0f;  // the strands from L (Lipp Eq. 1): all of them close up
  Scene s;
  s.width = 128;
  s.height = 96;
  s.shadows.resolution = 128;
  s.shadows.lodScale = 1.0f;  // the lights' LOD as the camera's: the cap decides, not the scale
  Light l;
  l.direction = glm::normalize(glm::vec3(0.3f, 0.9f, 0.4f));
  l.shadows = true;
  s.lights.push_back(l);
  s.grooms.emplace_back("tiny", std::make_shared<const HairMesh>(m));
  Renderer r(test::sharedDevice());
  auto run = [&](CameraPreset p, Toggle cap) {
    Scene at = s;
    at.camera = framePreset(s, p, 30.0f, 15.0f);
    RenderOptions o;
    o.filter = Toggle::Off;
    o.shadowLodCamera = cap;
    return r.render(at, o).stats;
  };
  const FrameStats far = run(CameraPreset::Far, Toggle::Default),
                   farLight = run(CameraPreset::Far, Toggle::Off);
  const FrameStats close = run(CameraPreset::Close, Toggle::Default),
                   again = run(CameraPreset::Far, Toggle::Default);
  RecordProperty("far_camera_strands", std::to_string(far.strandsDrawn));
  RecordProperty("far_map_strands", std::to_string(far.shadowStrandsDrawn));
  RecordProperty("far_map_strands_light_view", std::to_string(farLight.shadowStrandsDrawn));
  ASSERT_GT(far.strandsDrawn, 0u);
  ASSERT_LT(far.strandsDrawn, 3000u) << "LOD should thin the far groom in the camera";
  EXPECT_GT(far.shadowStrandsDrawn, 0u);
  EXPECT_LE(far.shadowStrandsDrawn, far.strandsDrawn);
  EXPECT_GT(farLight.shadowStrandsDrawn, far.shadowStrandsDrawn)
      << "the light's view alone should ask for more strands";
  EXPECT_EQ(close.strandsDrawn, 3000u);
  EXPECT_EQ(close.shadowStrandsDrawn, 3000u) << "close up, the map draws every strand again";
  EXPECT_EQ(again.shadowStrandsDrawn, far.shadowStrandsDrawn) << "far again: rebuilt, capped";
}

// The traced reference (the quality table's ground truth, `clhair_bench --quality-lights
// maps`) shades through deep opacity maps built from the full groom at true width, whatever
// LOD the frames it judges use for theirs: a LOD frame draws fewer strands into its maps,
// the reference every strand, and its hair behind hair is darker (the maps are read).
TEST(Shadows, TracedReferenceMapsHoldTheFullGroomWhileLodFramesUseTheirLod) {
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.filter = Toggle::Off;
  o.lod = Toggle::On;
  Scene s = twoPatches(true);
  s.shadows.lodScale = 0.25f;  // LOD in the lights' passes drops strands (lod_scale)
  const Frame lod = r.render(s, o);
  const Frame ref = r.renderReference(s, 2, ReferenceMethod::Embree);
  const Frame lodAgain = r.render(s, o);  // the maps follow each frame's own LOD
  RecordProperty("shadow_strands_lod", std::to_string(lod.stats.shadowStrandsDrawn));
  RecordProperty("shadow_strands_reference", std::to_string(ref.stats.shadowStrandsDrawn));
  EXPECT_EQ(ref.stats.shadowStrandsDrawn, 6000u) << "the reference's maps: 2 patches x 3000";
  EXPECT_GT(lod.stats.shadowStrandsDrawn, 0u);
  EXPECT_LT(lod.stats.shadowStrandsDrawn, 6000u) << "the LOD frame's maps should be thinned";
  EXPECT_EQ(lodAgain.stats.shadowStrandsDrawn, lod.stats.shadowStrandsDrawn);
  const auto [front, back] = halves(ref, s.width);
  EXPECT_LT(back, 0.9 * front) << "the reference should show hair shadowing hair";
}

// "shadows": {"lod_scale"} thins the lights' passes only: fewer strands in the maps, the
// camera's strands unchanged, and hair behind hair about as much darker as with every
// strand in the maps (the LOD's widening keeps their opacity).
TEST(Shadows, LodScaleThinsOnlyTheLightsPasses) {
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.filter = Toggle::Off;
  o.lod = Toggle::On;
  auto run = [&](float lodScale) {
    Scene s = twoPatches(true);
    s.shadows.lodScale = lodScale;
    return r.render(s, o);
  };
  const Frame full = run(1.0f), thin = run(0.25f);
  RecordProperty("shadow_strands_full", std::to_string(full.stats.shadowStrandsDrawn));
  RecordProperty("shadow_strands_thin", std::to_string(thin.stats.shadowStrandsDrawn));
  EXPECT_LT(thin.stats.shadowStrandsDrawn, full.stats.shadowStrandsDrawn * 3 / 4);
  EXPECT_EQ(thin.stats.strandsDrawn, full.stats.strandsDrawn) << "the camera's pass changed";
  const auto [frontFull, backFull] = halves(full, 120);
  const auto [frontThin, backThin] = halves(thin, 120);
  ASSERT_LT(backFull, 0.9 * frontFull) << "the scene should show hair shadowing hair";
  EXPECT_NEAR(backThin / frontThin, backFull / frontFull, 0.1 * (backFull / frontFull));
}

TEST(Shadows, MapsAreReusedWhileTheirInputsStayAndRebuiltWhenOneChanges) {
  // RenderOptions::reuseShadows keeps the deep opacity maps of the previous frame when
  // nothing they depend on changed: the second frame of a still scene skips the shadow
  // passes and equals a frame that rebuilt them; moving a light or a groom, changing a
  // shadow setting or deforming a groom's cage rebuilds them, so every frame equals a fresh
  // renderer's.
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.filter = Toggle::Off;
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
    EXPECT_TRUE(reused.color.rgba == fresh.render(changed, o).color.rgba)
        << what << ": stale shadows";
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
  // a deformed cage (a frame of wind or cage animation) moves the strands without changing
  // the groom or its transform: the maps follow it
  auto lifted = std::make_shared<std::vector<glm::vec3>>(denser.grooms[0].mesh->positions);
  for (glm::vec3& p : *lifted) p += glm::vec3(0.0f, 0.006f, 0.004f);
  Scene deformed = denser;
  for (GroomInstance& g : deformed.grooms) g.deformed = lifted;
  freshEquals(deformed, "cage deformed");
  // the same cage evaluated again (another copy, as every sceneAtFrame makes) keeps them
  Scene again = denser;
  auto copy = std::make_shared<const std::vector<glm::vec3>>(*lifted);
  for (GroomInstance& g : again.grooms) g.deformed = copy;
  EXPECT_FALSE(hasShadowStage(r.render(again, o))) << "an equal cage rebuilt the shadow maps";
}

}  // namespace
}  // namespace clhair
