// test_composite.cpp — compositing and the reference mode: a groom that draws nothing
// leaves exactly the opaque scene, opaque hair hides the background completely, and the
// jittered reference converges as its sample count grows.
#include <cmath>

#include "clhair/renderer.h"
#include "groom/presets.h"
#include "test_util.h"

namespace clhair {
namespace {

Scene baseScene(std::int64_t strands, float minDiameter) {
  HairMesh mesh = makeGroomPreset("curly_medium");
  mesh.strandCount = strands;
  mesh.appearance.minHitDiameterPx = minDiameter;
  Scene s;
  s.width = 160;
  s.height = 90;
  s.background = glm::vec3(0.2f, 0.3f, 0.4f);
  Light l;
  l.direction = glm::normalize(glm::vec3(0.3f, 1.0f, 0.4f));
  l.intensity = 2.0f;
  s.lights.push_back(l);
  Sphere head;
  head.radius = 0.09f;
  s.spheres.push_back(head);
  s.grooms.emplace_back("curly", std::make_shared<const HairMesh>(std::move(mesh)));
  s.camera = framePreset(s, CameraPreset::Mid, 20.0f, 10.0f);
  return s;
}

TEST(Composite, EmptyGroomLeavesExactlyTheOpaqueScene) {
  Scene withGroom = baseScene(0, 0.0f);
  Scene without = withGroom;
  without.grooms.clear();
  Renderer r(test::sharedDevice());
  Frame a = r.render(withGroom), b = r.render(without);
  EXPECT_EQ(a.stats.strandsDrawn, 0u);
  EXPECT_TRUE(a.color.rgba == b.color.rgba);
  EXPECT_TRUE(a.depth == b.depth);
}

TEST(Composite, OpaqueHairHidesTheBackground) {
  // wide center hits make the hair fully opaque where it is: the pixel colour is then the
  // hair's whatever lies behind it, with and without the filter
  Scene s = baseScene(20000, 3.0f);
  s.camera = framePreset(s, CameraPreset::Close, 20.0f, 10.0f);
  Scene other = s;
  other.background = glm::vec3(1.0f, 0.0f, 1.0f);
  Renderer r(test::sharedDevice());
  for (int filter : {0, 1}) {
    RenderOptions o;
    o.filter = filter ? Toggle::On : Toggle::Off;
    o.captureGBuffer = true;
    Frame a = r.render(s, o), b = r.render(other, o);
    const std::size_t n = static_cast<std::size_t>(s.width) * s.height;
    std::size_t opaque = 0, hairOverBackground = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (a.gbuffer[i] == ~std::uint64_t(0)) continue;  // no center hit
      bool same = a.color.rgba[4 * i] == b.color.rgba[4 * i] &&
                  a.color.rgba[4 * i + 1] == b.color.rgba[4 * i + 1] &&
                  a.color.rgba[4 * i + 2] == b.color.rgba[4 * i + 2];
      opaque += same;
      // pixels where the backgrounds differ and the hair still shows its own colour
      hairOverBackground +=
          same && (a.color.rgba[4 * i] != 0.2f || a.color.rgba[4 * i + 2] != 0.4f);
    }
    std::size_t centers = 0;
    for (std::size_t i = 0; i < n; ++i) centers += a.gbuffer[i] != ~std::uint64_t(0);
    ASSERT_GT(centers, n / 20);
    // filter off: every center-hit pixel is opaque; filter on: all but the soft fringe
    if (filter == 0)
      EXPECT_EQ(opaque, centers);
    else
      EXPECT_GT(opaque, centers * 9 / 10);
    EXPECT_GT(hairOverBackground, centers / 2);
  }
}

TEST(Composite, HairOverABackgroundImage) {
  // a background image of the frame's size shows through exactly where nothing is drawn
  const std::string dir = test::scratchDir();
  Image bg;
  bg.width = 160;
  bg.height = 90;
  bg.rgba.resize(static_cast<std::size_t>(bg.width) * bg.height * 4);
  for (std::size_t i = 0; i < bg.rgba.size(); i += 4) {
    bg.rgba[i] = static_cast<float>((i / 4) % 160) / 159.0f;
    bg.rgba[i + 1] = static_cast<float>((i / 4) / 160) / 89.0f;
    bg.rgba[i + 2] = 0.5f;
    bg.rgba[i + 3] = 1.0f;
  }
  writeImage(bg, dir + "/bg.exr");
  Image stored = readImage(dir + "/bg.exr");  // half floats: compare against what was stored
  Scene s = baseScene(3000, 0.0f);
  s.spheres.clear();
  s.backgroundImage = dir + "/bg.exr";
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.captureGBuffer = true;
  Frame f = r.render(s, o);
  const std::size_t n = f.depth.size();
  std::size_t same = 0, hair = 0, empty = 0;
  for (std::size_t i = 0; i < n; ++i) {
    bool equal = true;
    // the stretch is the identity at equal sizes, up to float rounding of the texel position
    for (int c = 0; c < 3; ++c)
      equal = equal && std::fabs(f.color.rgba[4 * i + c] - stored.rgba[4 * i + c]) < 1e-5f;
    // pixels no strand touches (both layers empty) show the image exactly
    if (f.gbuffer[i] == ~std::uint64_t(0) && f.gbuffer[n + i] == ~std::uint64_t(0)) {
      ++empty;
      same += equal;
    } else {
      hair += !equal;
    }
  }
  EXPECT_GT(hair, 50u) << "hair covers part of the image";
  EXPECT_GT(empty, n / 2);
  EXPECT_EQ(same, empty) << "every pixel without hair shows the background image";
}

TEST(Reference, ConvergesAsSamplesGrow) {
  Scene s = baseScene(4000, 0.0f);
  s.width = 96;
  s.height = 54;
  Renderer r(test::sharedDevice());
  auto rmse = [](const Frame& a, const Frame& b) {
    double e = 0.0;
    for (std::size_t i = 0; i < a.color.rgba.size(); ++i) {
      double d = a.color.rgba[i] - b.color.rgba[i];
      e += d * d;
    }
    return std::sqrt(e / a.color.rgba.size());
  };
  const ReferenceMethod m = ReferenceMethod::Raster;  // the traced one: TracedReference.*
  Frame r2 = r.renderReference(s, 2, m), r4 = r.renderReference(s, 4, m);
  Frame r8 = r.renderReference(s, 8, m), r16 = r.renderReference(s, 16, m);
  double d24 = rmse(r2, r4), d816 = rmse(r8, r16);
  RecordProperty("rmse_2_vs_4", std::to_string(d24));
  RecordProperty("rmse_8_vs_16", std::to_string(d816));
  EXPECT_GT(d24, 0.0);
  EXPECT_LT(d816, 0.7 * d24) << "2 vs 4: " << d24 << ", 8 vs 16: " << d816;
}

}  // namespace
}  // namespace clhair
