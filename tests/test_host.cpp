// test_host.cpp — the host's own contracts: instances of one groom keep their own LOD
// state (strand totals), reference mode does not leak into later frames, and stage inputs
// are checked before launch with messages that name the argument.
#include <cstring>
#include <string>

#include "cl/buffers.h"
#include "clhair/renderer.h"
#include "groom/presets.h"
#include "stages/filter_stage.h"
#include "synthetic_groom.h"
#include "test_util.h"

namespace clhair {
namespace {

Scene furScene() {
  HairMesh mesh = makeGroomPreset("fur_sphere");
  mesh.strandCount = 20000;
  mesh.lod.enabled = true;
  Scene s;
  s.width = 200;
  s.height = 150;
  Light l;
  l.direction = glm::normalize(glm::vec3(0.3f, 1.0f, 0.6f));
  s.lights.push_back(l);
  s.grooms.push_back({"fur", std::make_shared<const HairMesh>(std::move(mesh)), glm::mat4(1.0f)});
  s.camera = framePreset(s, CameraPreset::Mid, 30.0f, 15.0f);
  return s;
}

// A second instance of the scene's groom, a quarter of the size and off to the side: LOD
// keeps fewer of its strands.
GroomInstance smallCopy(const GroomInstance& g) {
  GroomInstance c = g;
  c.name += " (small)";
  for (int k = 0; k < 3; ++k) c.transform[k] *= 0.25f;
  c.transform[3] += glm::vec4(0.3f, 0.0f, 0.0f, 0.0f);
  return c;
}

void expectOwnCounts(Scene s) {
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.lod = Toggle::On;
  const GroomInstance big = s.grooms[0], small = smallCopy(big);
  const std::uint64_t nBig = r.render(s, o).stats.strandsDrawn;
  s.grooms = {small};
  const std::uint64_t nSmall = r.render(s, o).stats.strandsDrawn;
  ASSERT_GT(nSmall, 0u);
  ASSERT_LT(nSmall, nBig) << "the small instance should lose strands to LOD";
  s.grooms = {big, small};
  EXPECT_EQ(r.render(s, o).stats.strandsDrawn, nBig + nSmall);
  s.grooms = {small, big};
  EXPECT_EQ(r.render(s, o).stats.strandsDrawn, nBig + nSmall);
  s.grooms = {big, small, small};
  EXPECT_EQ(r.render(s, o).stats.strandsDrawn, nBig + 2 * nSmall);
}

TEST(Host, TwoInstancesOfOneHairMeshCountTheirOwnStrands) { expectOwnCounts(furScene()); }

TEST(Host, TwoInstancesOfOneStrandFileCountTheirOwnStrands) {
  Scene s = furScene();
  StrandGroom g = test::syntheticGroom(6000);
  g.lod.enabled = true;
  s.grooms[0].mesh.reset();
  s.grooms[0].strands = std::make_shared<const StrandGroom>(std::move(g));
  s.camera = framePreset(s, CameraPreset::Mid, 30.0f, 15.0f);
  expectOwnCounts(s);
}

// Reference passes ignore the minimum hit diameter; the next ordinary frame draws with it
// again, exactly as a fresh renderer does.
TEST(Host, ReferenceModeDoesNotLeakIntoLaterFrames) {
  Scene s = furScene();
  HairMesh m = *s.grooms[0].mesh;
  m.appearance.minHitDiameterPx = 1.5f;
  s.grooms[0].mesh = std::make_shared<const HairMesh>(std::move(m));
  Renderer fresh(test::sharedDevice());
  const Frame expected = fresh.render(s);
  Renderer r(test::sharedDevice());
  const Frame reference = r.renderReference(s, 1, ReferenceMethod::Raster);
  const Frame after = r.render(s);
  ASSERT_EQ(after.color.rgba.size(), expected.color.rgba.size());
  EXPECT_EQ(0, std::memcmp(after.color.rgba.data(), expected.color.rgba.data(),
                           after.color.rgba.size() * 4));
  // and the reference did draw thinner strands: fewer hair pixels
  auto hairPixels = [](const Frame& f) {
    std::size_t n = 0;
    for (float d : f.depth) n += d < 1e30f;
    return n;
  };
  EXPECT_LT(hairPixels(reference), hairPixels(expected));
}

// A stage launched with a buffer smaller than its target needs fails before the launch,
// naming the stage, kernel, argument and both sizes.
TEST(Host, StageInputsAreCheckedBeforeLaunch) {
  Device::Impl& d = *test::sharedDevice().impl();
  constexpr int W = 16, H = 8;
  gpu::ClhViewGpu view{};
  view.width = W;
  view.height = H;
  gpu::ClhGroomGpu groom{};
  cl::Buffer bv = makeBuffer<gpu::ClhViewGpu>(d, "view", 1, &view);
  cl::Buffer bg = makeBuffer<gpu::ClhGroomGpu>(d, "groom", 1, &groom);
  cl::Buffer gbufferOneLayer = makeBuffer<cl_ulong>(d, "G-buffer", W * H);  // the filter reads two
  cl::Buffer hair = makeBuffer<cl_float4>(d, "hair", W * H),
             out = makeBuffer<cl_float4>(d, "out", W * H);
  FilterStage stage(d);
  FilterParams f;
  try {
    stage.enqueue(f, {{&bv, W, H}, &bg, &gbufferOneLayer, &hair, &out}, nullptr);
    FAIL() << "a one-layer G-buffer was accepted";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("filter: kernel filter_reconstruct argument 3 (G-buffer)"), std::string::npos)
        << m;
    EXPECT_NE(m.find(std::to_string(W * H * 8) + " bytes"), std::string::npos) << m;
    EXPECT_NE(m.find("needs " + std::to_string(2 * W * H * 8)), std::string::npos) << m;
  }
  f.radius = 9;
  cl::Buffer gbuffer = makeBuffer<cl_ulong>(d, "G-buffer", 2 * W * H);
  EXPECT_THROW(stage.enqueue(f, {{&bv, W, H}, &bg, &gbuffer, &hair, &out}, nullptr), Error);
}

}  // namespace
}  // namespace clhair
