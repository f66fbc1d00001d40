// test_view_notes.cpp — the notes a scene gets before it renders (host/io/view_notes.h):
// a sparse groom of fibres far thinner than a pixel is named, with the key that makes it
// visible ("min_hit_diameter_px"), and that key does make it cover at least 1 % of a
// 640x480 frame; a dense groom gets no note; a scene without lights gets one line.
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

TEST(ViewNotes, ASparseThinGroomIsNamedWithTheKeyThatShowsIt) {
  const std::string dir = test::scratchDir();
  writeCap(dir + "/sparse.hair", 100);
  writeCap(dir + "/dense.hair", 20000);
  writeText(dir + "/s.json", sceneText("sparse.hair", "{}"));
  const Scene sparse = loadScene(dir + "/s.json");
  const std::vector<std::string> n = viewNotes(sparse, "s.json");
  ASSERT_EQ(n.size(), 1u);
  EXPECT_NE(n[0].find("\"min_hit_diameter_px\""), std::string::npos) << n[0];
  EXPECT_NE(n[0].find("grooms[0]"), std::string::npos) << n[0];
  // a dense groom of the same fibres covers its box: no note
  writeText(dir + "/d.json", sceneText("dense.hair", "{}"));
  EXPECT_EQ(countWith(viewNotes(loadScene(dir + "/d.json"), "d.json"), "min_hit"), 0u);
  // the key set: no note, and the hair covers at least 1 % of the frame (pixels more than
  // 2/255 away from the background)
  writeText(dir + "/k.json", sceneText("sparse.hair", "{\"min_hit_diameter_px\": 1}"));
  const Scene keyed = loadScene(dir + "/k.json");
  EXPECT_TRUE(viewNotes(keyed, "k.json").empty());
  Renderer r(test::sharedDevice());
  const Image img = r.render(keyed, RenderOptions{}).color;
  const Image bare = r.render(sparse, RenderOptions{}).color;
  auto visible = [&](const Image& im) {
    std::size_t v = 0;
    for (std::size_t i = 0; i < im.rgba.size(); i += 4) {
      float d = 0.0f;
      for (int c = 0; c < 3; ++c) d = std::max(d, std::fabs(im.rgba[i + c] - keyed.background[c]));
      v += d > 2.0f / 255.0f;
    }
    return static_cast<double>(v) / static_cast<double>(im.rgba.size() / 4);
  };
  const double withKey = visible(img), byDefault = visible(bare);
  std::printf("visible hair: %.3f %% of the frame by default, %.3f %% with the key\n",
              100.0 * byDefault, 100.0 * withKey);
  EXPECT_GE(withKey, 0.01);
  // the broken twin: a key out of its range is one error line
  writeText(dir + "/b.json", sceneText("sparse.hair", "{\"min_hit_diameter_px\": 5}"));
  const std::string e = test::errorOf([&] { loadScene(dir + "/b.json"); });
  EXPECT_NE(e.find("min_hit_diameter_px"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

TEST(ViewNotes, ASceneWithoutLightsGetsOneLine) {
  const std::string dir = test::scratchDir();
  writeCap(dir + "/dense.hair", 20000);
  writeText(dir + "/n.json", sceneText("dense.hair", "{}", false));
  const std::vector<std::string> n = viewNotes(loadScene(dir + "/n.json"), "n.json");
  ASSERT_EQ(n.size(), 1u);
  EXPECT_NE(n[0].find("no lights"), std::string::npos) << n[0];
  writeText(dir + "/l.json", sceneText("dense.hair", "{}"));
  EXPECT_EQ(countWith(viewNotes(loadScene(dir + "/l.json"), "l.json"), "no lights"), 0u);
}

}  // namespace
}  // namespace clhair
