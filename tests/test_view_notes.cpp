// test_view_notes.cpp — the notes a scene gets before it renders (host/io/view_notes.h):
// a sparse groom of fibres far thinner than a pixel is named where the render does not widen
// it, with the key that makes it visible ("min_hit_diameter_px"); a dense groom gets no
// note; a scene without lights gets one line. And the widening itself (io/faint_groom.h):
// a faint groom shows by default with the light of its true width.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <string>

#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "io/cyhair.h"
#include "io/view_notes.h"
#include "test_util.h"

namespace clhair {
namespace {

void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

// `strands` strands of 30 points, 0.3 m long, hanging from a 0.18 m head cap (metres).
void writeCap(const std::string& path, int strands) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  CyHair h;
  for (int s = 0; s < strands; ++s) {
    const float a = 6.2832f * u(rng), b = 1.2f * u(rng);
    const glm::vec3 n(std::sin(b) * std::cos(a), std::cos(b), std::sin(b) * std::sin(a));
    h.segments.push_back(29);
    for (int k = 0; k < 30; ++k) {
      const float t = static_cast<float>(k) / 29.0f;
      const glm::vec3 p = 0.09f * n + glm::vec3(0.04f * t * n.x, -0.3f * t * t, 0.04f * t * n.z);
      h.points.insert(h.points.end(), {p.x, p.y, p.z});
    }
  }
  h.info = "cap";
  writeCyHair(h, path);
}

std::string sceneText(const std::string& file, const std::string& appearance, bool lights = true) {
  return std::string("{\"resolution\": [640, 480], \"camera\": {\"preset\": \"close\"}, ") +
         (lights ? "\"lights\": [{\"type\": \"directional\", \"direction\": [0.3, 0.8, 0.5]}], "
                 : "") +
         "\"grooms\": [{\"strands_file\": \"" + file + "\", \"appearance\": " + appearance + "}]}";
}

std::size_t countWith(const std::vector<std::string>& notes, const std::string& what) {
  std::size_t n = 0;
  for (const std::string& s : notes) n += s.find(what) != std::string::npos;
  return n;
}

// The share of the frame shown as hair: pixels whose 8-bit sRGB level differs from the
// background's by more than 2 in some channel (what the written PNG shows).
double shownShare(const Image& im, const glm::vec3& background) {
  auto level = [](float c) {
    c = std::min(std::max(c, 0.0f), 1.0f);
    const float e = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
    return static_cast<int>(std::lround(255.0f * e));
  };
  std::size_t v = 0;
  for (std::size_t i = 0; i < im.rgba.size(); i += 4) {
    int d = 0;
    for (int c = 0; c < 3; ++c)
      d = std::max(d, std::abs(level(im.rgba[i + c]) - level(background[c])));
    v += d > 2;
  }
  return static_cast<double>(v) / static_cast<double>(im.rgba.size() / 4);
}

// The hair's light over the background: |pixel - background| summed over the channels.
double lightOver(const Image& im, const glm::vec3& background) {
  double sum = 0.0;
  for (std::size_t i = 0; i < im.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c) sum += std::fabs(im.rgba[i + c] - background[c]);
  return sum;
}

TEST(ViewNotes, ASparseThinGroomIsNamedWithTheKeyThatShowsIt) {
  const std::string dir = test::scratchDir();
  writeCap(dir + "/sparse.hair", 100);
  writeCap(dir + "/dense.hair", 20000);
  writeText(dir + "/s.json", sceneText("sparse.hair", "{}"));
  const Scene sparse = loadScene(dir + "/s.json");
  const std::vector<std::string> n = viewNotes(sparse, "s.json", false);
  ASSERT_EQ(n.size(), 1u);
  EXPECT_NE(n[0].find("\"min_hit_diameter_px\""), std::string::npos) << n[0];
  EXPECT_NE(n[0].find("grooms[0]"), std::string::npos) << n[0];
  // a dense groom of the same fibres covers its box: no note
  writeText(dir + "/d.json", sceneText("dense.hair", "{}"));
  EXPECT_EQ(countWith(viewNotes(loadScene(dir + "/d.json"), "d.json", false), "min_hit"), 0u);
  // a render that filters its hair widens the groom itself: no note
  EXPECT_TRUE(viewNotes(sparse, "s.json", true).empty());
  // the key set: no note, and the hair covers at least 1 % of the frame
  writeText(dir + "/k.json", sceneText("sparse.hair", "{\"min_hit_diameter_px\": 1}"));
  const Scene keyed = loadScene(dir + "/k.json");
  EXPECT_TRUE(viewNotes(keyed, "k.json", false).empty());
  Renderer r(test::sharedDevice());
  EXPECT_GE(shownShare(r.render(keyed, RenderOptions{}).color, keyed.background), 0.01);
  // the broken twin: a key out of its range is one error line
  writeText(dir + "/b.json", sceneText("sparse.hair", "{\"min_hit_diameter_px\": 5}"));
  const std::string e = test::errorOf([&] { loadScene(dir + "/b.json"); });
  EXPECT_NE(e.find("min_hit_diameter_px"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

// A faint groom (io/faint_groom.h) is drawn a pixel wide by default, with the light of its
// true width: it shows on at least 1 % of a 640x480 frame, and its light over the
// background stays that of the coverage raster's exact overlap areas (the truth), where the
// key's full-colour widening is many times brighter. A dense groom is drawn as before.
TEST(FaintGroom, DrawnAPixelWideWithTheLightOfItsTrueWidth) {
  const std::string dir = test::scratchDir();
  writeCap(dir + "/sparse.hair", 100);
  writeText(dir + "/s.json", sceneText("sparse.hair", "{}"));
  writeText(dir + "/k.json", sceneText("sparse.hair", "{\"min_hit_diameter_px\": 1}"));
  const Scene sparse = loadScene(dir + "/s.json"), keyed = loadScene(dir + "/k.json");
  const glm::vec3 bg = sparse.background;
  Renderer r(test::sharedDevice());
  RenderOptions asBefore, cover, lipp;
  asBefore.trueWidth = true;  // no widening: the true projected width only
  cover.raster = RasterMode::Coverage;
  lipp.filterMethod = FilterParams::Method::Lipp;
  const Image widened = r.render(sparse, RenderOptions{}).color;
  const Image before = r.render(sparse, asBefore).color;
  const Image exact = r.render(sparse, cover).color;
  const Image full = r.render(keyed, RenderOptions{}).color;
  const double shown = shownShare(widened, bg), shownBefore = shownShare(before, bg);
  const double light = lightOver(widened, bg), truth = lightOver(exact, bg);
  const double lightLipp = lightOver(r.render(sparse, lipp).color, bg);
  std::printf(
      "shown: %.3f %% of the frame (true width only %.3f %%, exact coverage %.3f %%, "
      "the key %.3f %%); light over the background %.4g, Lipp's filter %.4g, exact "
      "%.4g, the key %.4g\n",
      100.0 * shown, 100.0 * shownBefore, 100.0 * shownShare(exact, bg),
      100.0 * shownShare(full, bg), light, lightLipp, truth, lightOver(full, bg));
  EXPECT_GE(shown, 0.01);
  EXPECT_GT(shown, shownBefore);
  EXPECT_NEAR(light / truth, 1.0, 0.2);         // Huang's filter (the default)
  EXPECT_LE(lightLipp / truth, 1.2);            // Lipp's: never brighter than the coverage
  EXPECT_GT(lightOver(full, bg), 5.0 * truth);  // what the honest alpha avoids
  // a dense groom of the same fibres is not faint: drawn exactly as without the widening
  writeCap(dir + "/dense.hair", 20000);
  writeText(dir + "/d.json", sceneText("dense.hair", "{}"));
  const Scene dense = loadScene(dir + "/d.json");
  EXPECT_EQ(r.render(dense, RenderOptions{}).color.rgba, r.render(dense, asBefore).color.rgba);
}

// `clhair render` names a faint groom only where the render does not widen it.
TEST(FaintGroom, TheCliNotesItWhereItIsNotWidened) {
  const std::string dir = test::scratchDir();
  writeCap(dir + "/sparse.hair", 100);
  writeText(dir + "/s.json", sceneText("sparse.hair", "{}"));
  for (const auto& [flags, noted] :
       {std::pair<std::string, bool>{"", false}, {"--true-width", true}, {"--msaa 2", true}}) {
    SCOPED_TRACE(flags);
    const test::CommandResult r = test::runCli("render " + test::quote(dir + "/s.json") + " -o " +
                                               test::quote(dir + "/a.png") + " " + flags);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output.find("draws faint") != std::string::npos, noted) << r.output;
  }
}

TEST(ViewNotes, ASceneWithoutLightsGetsOneLine) {
  const std::string dir = test::scratchDir();
  writeCap(dir + "/dense.hair", 20000);
  writeText(dir + "/n.json", sceneText("dense.hair", "{}", false));
  const std::vector<std::string> n = viewNotes(loadScene(dir + "/n.json"), "n.json", false);
  ASSERT_EQ(n.size(), 1u);
  EXPECT_NE(n[0].find("no lights"), std::string::npos) << n[0];
  writeText(dir + "/l.json", sceneText("dense.hair", "{}"));
  EXPECT_EQ(countWith(viewNotes(loadScene(dir + "/l.json"), "l.json", false), "no lights"), 0u);
}

}  // namespace
}  // namespace clhair
