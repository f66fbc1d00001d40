// test_raster.cpp — properties of the visibility layers: the conservative layer contains
// every sample hit, each MSAA sample layer equals a 1-sample render shifted to that
// sample's position, the nearer of two grooms wins whatever their order, and frames stay
// bit-identical with LOD and MSAA.
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>

#include "clhair/renderer.h"
#include "groom/presets.h"
#include "test_util.h"

namespace clhair {
namespace {

constexpr std::uint64_t kEmpty = ~std::uint64_t(0);

Scene groomScene(const std::string& preset, std::int64_t strands, int w, int h, CameraPreset cam) {
  HairMesh mesh = makeGroomPreset(preset);
  mesh.strandCount = strands;
  Scene s;
  s.width = w;
  s.height = h;
  Light l;
  l.direction = glm::normalize(glm::vec3(0.2f, 1.0f, 0.5f));
  s.lights.push_back(l);
  s.grooms.push_back({preset, std::make_shared<const HairMesh>(std::move(mesh)), glm::mat4(1.0f)});
  s.camera = framePreset(s, cam, 25.0f, 10.0f);
  return s;
}

TEST(Raster, ConservativeContainsEveryCenterHit) {
  for (float minDiameter : {0.0f, 0.6f, 1.0f}) {
    Scene s = groomScene("curly_medium", 4000, 203, 117, CameraPreset::Mid);  // odd sizes
    HairMesh m = *s.grooms[0].mesh;
    m.appearance.minHitDiameterPx = minDiameter;
    s.grooms[0].mesh = std::make_shared<const HairMesh>(m);
    Renderer r(test::sharedDevice());
    RenderOptions o;
    o.captureGBuffer = true;
    o.filterMethod = FilterParams::Method::Lipp;  // Lipp's filter: the raster's centre and
                                                  // conservative layers as drawn
    Frame f = r.render(s, o);
    ASSERT_EQ(f.gbufferLayers, 2);
    const std::size_t n = static_cast<std::size_t>(s.width) * s.height;
    std::size_t center = 0, cons = 0;
    for (std::size_t i = 0; i < n; ++i) {
      bool c = f.gbuffer[i] != kEmpty, k = f.gbuffer[n + i] != kEmpty;
      center += c;
      cons += k;
      ASSERT_TRUE(!c || k) << "pixel " << i % s.width << "," << i / s.width
                           << " has a center hit but no conservative hit";
    }
    EXPECT_GT(center, 0u);
    EXPECT_GE(cons, center);
    if (minDiameter == 0.0f) {
      EXPECT_GT(cons, 2 * center) << "sub-pixel strands miss most centers";
    }
  }
}

TEST(Raster, EachMsaaLayerEqualsAShiftedSingleSampleRender) {
  // the sample positions of kernels/strands.cl (Direct3D standard patterns)
  const float pos4[4][2] = {{0.375f, 0.125f}, {0.875f, 0.375f}, {0.125f, 0.625f}, {0.625f, 0.875f}};
  Scene s = groomScene("curly_medium", 3000, 160, 96, CameraPreset::Close);
  HairMesh m = *s.grooms[0].mesh;
  m.appearance.minHitDiameterPx = 0.7f;  // enough hits to compare
  s.grooms[0].mesh = std::make_shared<const HairMesh>(m);
  Renderer r(test::sharedDevice());
  RenderOptions o4;
  o4.msaa = 4;
  o4.captureGBuffer = true;
  Frame f4 = r.render(s, o4);
  ASSERT_EQ(f4.gbufferLayers, 5);
  const std::size_t n = static_cast<std::size_t>(s.width) * s.height;
  for (int k = 0; k < 4; ++k) {
    RenderOptions o1;
    o1.captureGBuffer = true;
    o1.filterMethod = FilterParams::Method::Lipp;  // Huang's (the default) would add linked pixels
                                                   // to the centre layer
    // moving the image plane by (0.5 - offset) puts this pixel's center where the sample was
    o1.jitterX = 0.5f - pos4[k][0];
    o1.jitterY = 0.5f - pos4[k][1];
    Frame f1 = r.render(s, o1);
    std::size_t hits = 0, differ = 0;
    for (std::size_t i = 0; i < n; ++i) {
      hits += f4.gbuffer[k * n + i] != kEmpty;
      differ += f4.gbuffer[k * n + i] != f1.gbuffer[i];
    }
    EXPECT_GT(hits, n / 50) << "sample " << k;
    // identical up to float rounding of points exactly on a hit boundary
    EXPECT_LE(differ, hits / 1000 + 2)
        << "sample " << k << ": " << differ << " of " << hits << " differ";
  }
}

TEST(Raster, NearerGroomWinsWhateverTheOrder) {
  HairMesh a = makeGroomPreset("tiny");
  a.strandCount = 300;
  a.appearance.minHitDiameterPx = 1.0f;
  a.appearance.useMelanin = false;  // colour mode: red strands here, blue ones below
  a.appearance.rootColor = a.appearance.tipColor = glm::vec3(1.0f, 0.0f, 0.0f);
  HairMesh b = a;
  b.appearance.rootColor = b.appearance.tipColor = glm::vec3(0.0f, 0.0f, 1.0f);
  auto ma = std::make_shared<const HairMesh>(a), mb = std::make_shared<const HairMesh>(b);
  Scene s;
  s.width = 96;
  s.height = 96;
  s.ambient = glm::vec3(1.0f);
  s.background = glm::vec3(0.0f);
  // b is the same patch moved 2 cm away from the camera and slightly sideways: they overlap
  glm::mat4 behind = glm::translate(glm::mat4(1.0f), glm::vec3(0.004f, 0.0f, -0.02f));
  s.camera.position = glm::vec3(0.0f, 0.03f, 0.15f);
  s.camera.target = glm::vec3(0.0f, 0.025f, 0.0f);
  s.camera.fovYDegrees = 30.0f;
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.filter = Toggle::Off;  // opaque 1-sample hair: the visibility test itself, without blending
  s.grooms = {{"a", ma, glm::mat4(1.0f)}, {"b", mb, behind}};
  Frame ab = r.render(s, o);
  s.grooms = {{"b", mb, behind}, {"a", ma, glm::mat4(1.0f)}};
  Frame ba = r.render(s, o);
  std::size_t red = 0, blue = 0, differ = 0;
  for (std::size_t i = 0; i < ab.color.rgba.size(); i += 4) {
    red += ab.color.rgba[i] > 2.0f * ab.color.rgba[i + 2] + 1e-4f;
    blue += ab.color.rgba[i + 2] > 2.0f * ab.color.rgba[i] + 1e-4f;
    differ += std::memcmp(&ab.color.rgba[i], &ba.color.rgba[i], 3 * sizeof(float)) != 0;
  }
  EXPECT_GT(red, 200u);
  EXPECT_GT(blue, 20u) << "the far groom shows where the near one does not cover it";
  EXPECT_EQ(differ, 0u);
  // and the depth handed on is the nearer one
  EXPECT_TRUE(std::memcmp(ab.depth.data(), ba.depth.data(), ab.depth.size() * sizeof(float)) == 0);
}

TEST(Raster, DeterministicWithLodAndMsaa) {
  Scene s = groomScene("long_wavy", 20000, 240, 135, CameraPreset::Mid);
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.lod = Toggle::On;
  o.msaa = 4;
  o.captureGBuffer = true;
  Frame f1 = r.render(s, o);
  Frame f2 = r.render(s, o);
  EXPECT_LT(f1.stats.strandsDrawn, 20000u);
  EXPECT_TRUE(f1.gbuffer == f2.gbuffer);
  EXPECT_TRUE(f1.color.rgba == f2.color.rgba);
  for (DispatchMode m : {DispatchMode::OverLaunch, DispatchMode::Persistent}) {
    o.dispatch = m;
    Frame f3 = r.render(s, o);
    EXPECT_TRUE(f1.gbuffer == f3.gbuffer) << dispatchModeName(m);
    EXPECT_EQ(f3.stats.strandsDrawn, f1.stats.strandsDrawn);
  }
}

// The counters against what they count, each from elsewhere: the segments from the strands
// the export kernel generates (LOD off, the whole groom in front of the camera), the
// atomics from the G-buffer (every word that is not empty was put there by one at least),
// and the writes (candidates that passed the scene depth test) from their independence of
// the order the strands run in: the persistent grid runs them in another order.
TEST(Raster, StatisticsCountWritesAndAtomics) {
  Scene s = groomScene("curly_medium", 5000, 160, 90, CameraPreset::Mid);
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.rasterStats = true;
  o.lod = Toggle::Off;
  o.captureGBuffer = true;
  const Frame f = r.render(s, o);
  ASSERT_EQ(f.stats.strandsDrawn, 5000u);

  const StrandSet set = r.generateStrands(*s.grooms[0].mesh);
  ASSERT_EQ(set.pointCounts.size(), 5000u);
  std::uint64_t segments = 0;
  for (std::uint32_t c : set.pointCounts) segments += c - 1;
  EXPECT_EQ(f.stats.segmentsDrawn, segments);

  std::uint64_t words = 0;
  for (std::uint64_t w : f.gbuffer) words += w != kEmpty;
  ASSERT_GT(words, 0u);
  EXPECT_GE(f.stats.atomicsIssued, words)
      << "a word in the G-buffer without an atomic that wrote it";
  EXPECT_LE(f.stats.atomicsIssued, f.stats.pixelWrites);
  EXPECT_GT(f.stats.pixelWrites, words) << "dense hair visits most covered pixels more than once";

  RenderOptions other = o;
  other.dispatch = DispatchMode::Persistent;
  const Frame g = r.render(s, other);
  EXPECT_TRUE(g.gbuffer == f.gbuffer);
  EXPECT_EQ(g.stats.pixelWrites, f.stats.pixelWrites)
      << "the writes must not depend on the order of the strands";
  EXPECT_EQ(g.stats.segmentsDrawn, f.stats.segmentsDrawn);
  EXPECT_GE(g.stats.atomicsIssued, words);

  // the load skip (on by default, DESIGN.md "Atomics") spares some of the repeat visits
  EXPECT_GT(f.stats.atomicsSkipped, 0u);
}

}  // namespace
}  // namespace clhair
