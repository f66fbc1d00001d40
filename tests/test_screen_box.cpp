// test_screen_box.cpp — each groom's passes bounded to its screen box (stages/view_math.h,
// screenBox; kernels/link.cl, "Screen boxes"): the G-buffer clear, hair linking, Huang's
// filter and its compositing run over the box of the groom's projected bounds, each pass
// grown by the margin it reads, and the frame must be the whole-frame passes' frame bit for
// bit. Two instances of the tiny hair mesh far apart in a small image (each box a small part
// of it), with and without the anisotropic filter, rendered bounded, whole-frame and bounded
// again by one renderer (the clears carry the last groom's box from frame to frame); the
// same with the grooms cut by the image's left and right borders (their boxes clipped); and
// the boxes' premise checked directly: every word of every G-buffer layer a groom leaves
// (the linking layers included, with and without LOD widening) lies inside its box.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "clhair/hair_mesh.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "groom/groom_data.h"
#include "stages/view_math.h"
#include "test_util.h"

namespace clhair {
namespace {

constexpr std::uint64_t kEmpty = ~std::uint64_t(0);  // CLH_GBUF_EMPTY

// Two tiny grooms `apart` metres apart along x, the camera looking at x = `look`.
Scene twoGrooms(float apart, float look) {
  Scene s;
  s.width = 128;
  s.height = 64;
  s.camera.position = glm::vec3(look, 0.03f, 0.45f);
  s.camera.target = glm::vec3(look, 0.025f, 0.0f);
  Light l;
  l.direction = glm::normalize(glm::vec3(0.3f, 1.0f, 0.6f));
  s.lights.push_back(l);
  auto tiny =
      std::make_shared<const HairMesh>(loadHairMesh(test::assetPath("grooms/tiny.hairmesh.json")));
  for (int k = 0; k < 2; ++k) {
    GroomInstance g("tiny " + std::to_string(k), tiny);
    g.transform =
        glm::translate(glm::mat4(1.0f), glm::vec3((k == 0 ? -0.5f : 0.5f) * apart, 0.0f, 0.0f));
    s.grooms.push_back(g);
  }
  s.filter.method = FilterParams::Method::Huang;
  return s;
}

// The screen box of instance k as the frame computes it, before clipping (a margin of
// kScreenBoxMargin) when `clip` is false.
PixelRect boxOf(const Scene& s, std::size_t k, bool clip = true) {
  gpu::ClhViewGpu view = makeView(s.camera, s.width, s.height);
  const GroomData d = prepareGroom(*s.grooms[k].mesh);
  const int pad = clip ? 0 : 1000;  // a wider image around the same camera
  view.width += 2 * pad;
  view.height += 2 * pad;
  view.cx += pad;
  view.cy += pad;
  const PixelRect b =
      screenBox(d.boundsMin, d.boundsMax, worldToView(s.camera) * s.grooms[k].transform, view,
                kScreenBoxMargin);
  return {b.x0 - pad, b.y0 - pad, b.x1 - pad, b.y1 - pad};
}

// Renders `s` bounded, whole-frame and bounded again with one renderer; expects three
// equal frames, with linking at work in them.
void expectBoundedEqualsWhole(const Scene& s, RenderOptions o) {
  Renderer r(test::sharedDevice());
  o.screenBoxes = true;
  const Frame bounded = r.render(s, o);
  o.screenBoxes = false;
  const Frame whole = r.render(s, o);
  o.screenBoxes = true;
  const Frame again = r.render(s, o);
  EXPECT_GT(whole.stats.linkedPixels, 0u) << "no linking to compare";
  for (const GroomDrawStats& g : whole.stats.grooms) EXPECT_GT(g.strands, 0u) << g.name;
  EXPECT_EQ(bounded.stats.linkSelecting, whole.stats.linkSelecting);
  EXPECT_EQ(bounded.stats.linkedPixels, whole.stats.linkedPixels);
  EXPECT_EQ(bounded.stats.linkStrands, whole.stats.linkStrands);
  // every float equal: the same arithmetic on the same words
  EXPECT_TRUE(bounded.color.rgba == whole.color.rgba) << "the bounded frame differs";
  EXPECT_TRUE(bounded.depth == whole.depth) << "the bounded frame's depth differs";
  EXPECT_TRUE(again.color.rgba == whole.color.rgba) << "the second bounded frame differs";
  EXPECT_TRUE(again.depth == whole.depth);
}

}  // namespace

TEST(LinkScreenBox, BoundedPassesGiveTheWholeFramePassesImage) {
  const Scene s = twoGrooms(0.16f, 0.0f);
  // each box a small part of the image, the two apart: the bounded passes skip most of it
  const PixelRect a = boxOf(s, 0), b = boxOf(s, 1);
  ASSERT_FALSE(a.empty());
  ASSERT_FALSE(b.empty());
  EXPECT_LT(a.pixels() + b.pixels(), std::size_t(s.width) * s.height / 2);
  EXPECT_LE(a.x1, b.x0) << "the boxes overlap";
  EXPECT_TRUE(PixelRect(a).clipped(s.width, s.height) == a) << "a box is clipped";
  for (const bool aniso : {true, false}) {
    SCOPED_TRACE(aniso ? "with the anisotropic filter" : "alpha fix only");
    Scene t = s;
    t.filter.aniso = aniso;
    RenderOptions o;
    o.filter = Toggle::On;
    o.lod = Toggle::Off;
    expectBoundedEqualsWhole(t, o);
  }
}

TEST(LinkScreenBox, GroomsCutByTheImageBorderAreFilteredAsOnTheWholeFrame) {
  // the camera between two grooms that each reach past a side of the image
  const Scene s = twoGrooms(0.55f, 0.0f);
  const PixelRect a = boxOf(s, 0, false), b = boxOf(s, 1, false);
  ASSERT_LT(a.x0, 0) << "the left groom's box does not reach past the border";
  ASSERT_GT(a.x1, 0);
  ASSERT_GT(b.x1, s.width) << "the right groom's box does not reach past the border";
  ASSERT_LT(b.x0, s.width);
  // hair in the border columns, not only the box's margin
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.filter = Toggle::On;
  o.lod = Toggle::Off;
  o.captureGBuffer = true;  // the last groom's layers: the right one
  const Frame f = r.render(s, o);
  const std::size_t plane = std::size_t(s.width) * s.height;
  int border = 0;
  for (int y = 0; y < s.height; ++y)
    border += f.gbuffer[CLH_LAYER_ID * plane + std::size_t(y) * s.width + s.width - 1] != kEmpty;
  EXPECT_GT(border, 0) << "the right groom leaves no hair in the last column";
  o.captureGBuffer = false;
  expectBoundedEqualsWhole(s, o);
}

TEST(LinkScreenBox, EveryLayerAGroomWritesLiesInItsBox) {
  Scene s = twoGrooms(0.16f, 0.0f);
  s.grooms.pop_back();
  // closer: the hair covers more pixels; a curly style reaches far from the cage
  s.camera.position = glm::vec3(0.0f, 0.03f, 0.3f);
  HairMesh m = *s.grooms[0].mesh;
  m.style.curlAmplitude = 0.006f;
  m.style.curlFrequency = 6.0f;
  m.lod.enabled = true;
  m.lod.lambda = 0.02f;  // with LOD: widened strands, up to the widest hit diameter
  s.grooms[0] = GroomInstance("curly tiny", std::make_shared<const HairMesh>(m));
  const PixelRect box = boxOf(s, 0);
  ASSERT_FALSE(box.empty());
  const PixelRect hull = boxOf(s, 0).grown(-kScreenBoxMargin);
  EXPECT_TRUE(!hull.empty() && hull.x0 > 0 && hull.y0 > 0 && hull.x1 < s.width &&
              hull.y1 < s.height)
      << "the groom is not inside the image: the test needs the unclipped box";
  for (const int lod : {0, 1}) {
    SCOPED_TRACE(lod ? "LOD" : "no LOD");
    Renderer r(test::sharedDevice());
    RenderOptions o;
    o.filter = Toggle::On;
    o.lod = lod ? Toggle::On : Toggle::Off;
    o.captureGBuffer = true;
    const Frame f = r.render(s, o);
    ASSERT_EQ(f.gbufferLayers, int(CLH_LAYER_LINKED) + 1);
    EXPECT_GT(f.stats.linkedPixels, 0u);
    const std::size_t plane = std::size_t(s.width) * s.height;
    std::size_t words = 0, outside = 0;
    PixelRect seen{s.width, s.height, 0, 0};
    for (int l = 0; l < f.gbufferLayers; ++l)
      for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
          if (f.gbuffer[l * plane + std::size_t(y) * s.width + x] == kEmpty) continue;
          ++words;
          outside += !(x >= box.x0 && x < box.x1 && y >= box.y0 && y < box.y1);
          seen = seen.united({x, y, x + 1, y + 1});
        }
    EXPECT_GT(words, 100u);
    EXPECT_EQ(outside, 0u) << "words outside the box [" << box.x0 << ", " << box.x1 << ") x ["
                           << box.y0 << ", " << box.y1 << "); the hair spans [" << seen.x0 << ", "
                           << seen.x1 << ") x [" << seen.y0 << ", " << seen.y1 << ")";
  }
}

}  // namespace clhair
