// test_file_look.cpp — a downloaded groom drawn as its author made it: the cyHair file's own
// colours, thicknesses and transparencies (arrays or header defaults) unless the scene's
// appearance gives its own, per key; the rendered colour under white light against the
// file's; "scale": "auto"; camera presets that frame a head mesh with its groom.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "groom/explicit_data.h"
#include "io/cyhair.h"
#include "test_util.h"

namespace clhair {
namespace {

void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

// A cyHair groom in centimetres: `strands` strands of 12 points hanging from a 9 cm disc.
CyHair centimetreGroom(int strands, bool arrays) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  CyHair h;
  for (int s = 0; s < strands; ++s) {
    h.segments.push_back(11);
    const float x = 9.0f * u(rng), z = 9.0f * u(rng);
    for (int k = 0; k < 12; ++k) {
      h.points.insert(h.points.end(), {x + 0.3f * k * u(rng) * 0.1f, -1.5f * k, z});
      if (arrays) {
        h.thickness.push_back(0.01f + 0.001f * k);
        h.transparency.push_back(0.25f);
        h.colors.insert(h.colors.end(), {0.7f, 0.5f, 0.2f});
      }
    }
  }
  h.info = "test";
  return h;
}

Scene sceneWith(const std::string& dir, const std::string& file, const std::string& appearance) {
  writeText(dir + "/s.json", "{\"grooms\": [{\"strands_file\": \"" + file +
                                 "\", \"scale\": 0.01, \"appearance\": " + appearance + "}]}");
  return loadScene(dir + "/s.json");
}

TEST(FileLook, FileOnlyDrawsTheFilesColourThicknessAndTransparency) {
  const std::string dir = test::scratchDir();
  writeCyHair(centimetreGroom(20, true), dir + "/a.hair");
  const Scene s = sceneWith(dir, "a.hair", "{}");
  const StrandGroom& g = *s.grooms[0].strands;
  const ExplicitData d = prepareExplicit(g);
  ASSERT_TRUE(d.fileColor && d.fileThickness && d.fileOpacity);
  const std::uint32_t src = d.sourceStrand[0];
  const std::size_t i = std::size_t(src) * 12 + 3;  // point 3 of that strand in the file
  const glm::vec4 look = d.fileLook[d.strandOffsets[0] + 3];
  EXPECT_FLOAT_EQ(look.x, 0.7f);
  EXPECT_FLOAT_EQ(look.w, g.thickness[i] * 0.75f) << "thickness times 1 - transparency";
}

TEST(FileLook, SceneOnlyDrawsTheScenesLook) {
  const std::string dir = test::scratchDir();
  writeCyHair(centimetreGroom(20, false), dir + "/b.hair");  // no arrays, cyHair's defaults
  const Scene s =
      sceneWith(dir, "b.hair",
                R"({"root_color": [0.1, 0.2, 0.3], "strand_width": 1e-4, "transparency": 0.5})");
  const StrandGroom& g = *s.grooms[0].strands;
  EXPECT_TRUE(g.colors.empty() && g.thickness.empty() && g.transparency.empty());
  const ExplicitData d = prepareExplicit(g);
  EXPECT_TRUE(d.fileLook.empty());
  EXPECT_FLOAT_EQ(g.appearance.strandWidth, 1e-4f);
  EXPECT_FLOAT_EQ(g.appearance.transparency, 0.5f);
  EXPECT_FALSE(g.appearance.useMelanin);
}

TEST(FileLook, BothGivenTheSceneWinsPerKey) {
  const std::string dir = test::scratchDir();
  writeCyHair(centimetreGroom(20, true), dir + "/c.hair");
  // every key: nothing of the file's
  const Scene all =
      sceneWith(dir, "c.hair",
                R"({"root_color": [0.1, 0.2, 0.3], "strand_width": 1e-4, "transparency": 0.5})");
  EXPECT_TRUE(prepareExplicit(*all.grooms[0].strands).fileLook.empty());
  // only the width: the file's colour and transparency stay, its thickness goes
  const Scene width = sceneWith(dir, "c.hair", R"({"strand_width": 1e-4})");
  const ExplicitData d = prepareExplicit(*width.grooms[0].strands);
  EXPECT_TRUE(d.fileColor);
  EXPECT_FALSE(d.fileThickness);
  EXPECT_TRUE(d.fileOpacity);
  EXPECT_FLOAT_EQ(d.fileLook[0].w, -0.75f) << "the groom's width times the file's opacity";
  // only a colour: the file's thickness and transparency stay
  const Scene colour = sceneWith(dir, "c.hair", R"({"eumelanin": [0.3, 0.3]})");
  const ExplicitData dc = prepareExplicit(*colour.grooms[0].strands);
  EXPECT_FALSE(dc.fileColor);
  EXPECT_TRUE(dc.fileThickness && dc.fileOpacity);
  // only a transparency: the file's colour and thickness, the scene's opacity
  const Scene transparent = sceneWith(dir, "c.hair", R"({"transparency": 0.5})");
  const ExplicitData dt = prepareExplicit(*transparent.grooms[0].strands);
  EXPECT_TRUE(dt.fileColor && dt.fileThickness && !dt.fileOpacity);
  const std::uint32_t src = dt.sourceStrand[0];
  EXPECT_FLOAT_EQ(dt.fileLook[dt.strandOffsets[0]].w,
                  transparent.grooms[0].strands->thickness[std::size_t(src) * 12] * 0.5f);
}

TEST(FileLook, HeaderDefaultsStandForMissingArrays) {
  const std::string dir = test::scratchDir();
  CyHair h = centimetreGroom(10, false);
  h.defaultThickness = 0.008f;
  h.defaultTransparency = 0.2f;
  h.defaultColor[0] = 0.3f;
  h.defaultColor[1] = 0.2f;
  h.defaultColor[2] = 0.1f;
  writeCyHair(h, dir + "/d.hair");
  const Scene s = sceneWith(dir, "d.hair", "{}");
  const StrandGroom& g = *s.grooms[0].strands;
  ASSERT_EQ(g.thickness.size(), g.points.size());
  EXPECT_FLOAT_EQ(g.thickness[5], 0.008f);
  EXPECT_FLOAT_EQ(g.transparency[5], 0.2f);
  EXPECT_FLOAT_EQ(g.colors[5].y, 0.2f);
  // cyHair's own initial defaults (thickness 1, transparency 0, white) mean "not set"
  writeCyHair(centimetreGroom(10, false), dir + "/e.hair");
  const Scene e = sceneWith(dir, "e.hair", "{}");
  EXPECT_TRUE(e.grooms[0].strands->thickness.empty() && e.grooms[0].strands->colors.empty());
}

// Under white uniform light (ambient 1, no lights) the hair shows the file's colours: the
// image's mean hair colour (colour over coverage, the coverage measured by the same groom
// drawn white) within 2 % of the mean of the file's point colours.
TEST(FileLook, MeanHairColourUnderWhiteLightIsTheFilesMeanColour) {
  const std::string dir = test::scratchDir();
  const glm::vec3 palette[3] = {{0.75f, 0.55f, 0.25f}, {0.35f, 0.2f, 0.1f}, {0.6f, 0.6f, 0.55f}};
  CyHair coloured = centimetreGroom(600, false), white = coloured;
  glm::dvec3 fileMean(0.0);
  std::mt19937 rng(3);  // each point's colour drawn from the palette, wherever it lies
  for (std::size_t s = 0; s < coloured.segments.size(); ++s)
    for (int k = 0; k < 12; ++k) {
      const glm::vec3 c = palette[rng() % 3];
      coloured.colors.insert(coloured.colors.end(), {c.x, c.y, c.z});
      white.colors.insert(white.colors.end(), {1.0f, 1.0f, 1.0f});
      fileMean += glm::dvec3(c);
    }
  fileMean /= static_cast<double>(coloured.points.size() / 3);
  writeCyHair(coloured, dir + "/coloured.hair");
  writeCyHair(white, dir + "/white.hair");
  Renderer r(test::sharedDevice());
  auto render = [&](const std::string& file) {
    writeText(dir + "/w.json",
              "{\"resolution\": [160, 120], \"background\": [0, 0, 0], \"ambient\": [1, 1, 1],"
              " \"camera\": {\"preset\": \"close\"}, \"grooms\": [{\"strands_file\": \"" +
                  file + "\", \"scale\": 0.01, \"appearance\": {\"strand_width\": 4e-4}}]}");
    return r.render(loadScene(dir + "/w.json"), RenderOptions{}).color;
  };
  const Image c = render("coloured.hair"), w = render("white.hair");
  glm::dvec3 sumC(0.0), sumW(0.0);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x)
      for (int ch = 0; ch < 3; ++ch) {
        sumC[ch] += c.pixel(x, y)[ch];
        sumW[ch] += w.pixel(x, y)[ch];
      }
  ASSERT_GT(sumW.x, 100.0) << "the white groom covers some pixels";
  for (int ch = 0; ch < 3; ++ch) {
    const double mean = sumC[ch] / sumW[ch];
    EXPECT_NEAR(mean, fileMean[ch], 0.02 * fileMean[ch]) << "channel " << ch;
    std::printf("channel %d: image %.4f, file %.4f (%+.2f %%)\n", ch, mean, fileMean[ch],
                100.0 * (mean / fileMean[ch] - 1.0));
  }
  // and the white file is drawn white: its coverage-weighted colour is 1 where it is opaque
  EXPECT_NEAR(sumW.x / sumW.y, 1.0, 0.01);
}

TEST(ScaleAuto, ScalesTheRootsToAHeadAndSaysTheFactor) {
  const std::string dir = test::scratchDir();
  writeCyHair(centimetreGroom(50, false), dir + "/cm.hair");
  CyHair h = centimetreGroom(50, false);
  writeText(dir + "/head.obj", "v -5 0 -5\nv 5 0 -5\nv 0 0 5\nf 1 2 3\n");
  writeText(dir + "/auto.json",
            R"({"meshes": [{"file": "head.obj", "scale": "auto"}],
                "grooms": [{"strands_file": "cm.hair", "scale": "auto"}]})");
  const Scene s = loadScene(dir + "/auto.json");
  const float factor = s.grooms[0].transform[0][0];
  EXPECT_GT(factor, 0.0f);
  // the roots span 0.18 m after scaling
  glm::vec3 rlo(1e30f), rhi(-1e30f);
  for (std::size_t st = 0; st < h.segments.size(); ++st) {
    const glm::vec3 p(s.grooms[0].transform * glm::vec4(h.points[st * 36], h.points[st * 36 + 1],
                                                        h.points[st * 36 + 2], 1));
    rlo = glm::min(rlo, p);
    rhi = glm::max(rhi, p);
  }
  const glm::vec3 ext = rhi - rlo;
  EXPECT_NEAR(std::max(ext.x, std::max(ext.y, ext.z)), 0.18f, 1e-4f);
  EXPECT_FLOAT_EQ(s.meshes[0].transform[0][0], factor) << "the mesh takes the groom's factor";
  ASSERT_EQ(s.notes.size(), 1u);
  EXPECT_NE(s.notes[0].find("\"auto\" scales"), std::string::npos) << s.notes[0];
  // a mesh cannot guess alone
  writeText(dir + "/alone.json",
            R"({"meshes": [{"file": "head.obj", "scale": "auto"}],
                "grooms": [{"strands_file": "cm.hair", "scale": 0.01}]})");
  EXPECT_THROW(loadScene(dir + "/alone.json"), Error);
}

TEST(ScaleAuto, TheUnitsWarningSuggestsIt) {
  const std::string dir = test::scratchDir();
  writeCyHair(centimetreGroom(50, false), dir + "/cm.hair");
  writeText(dir + "/cm.json",
            R"({"resolution": [96, 64], "camera": {"preset": "close"},
                "grooms": [{"strands_file": "cm.hair"}]})");
  const Scene s = loadScene(dir + "/cm.json");
  const std::vector<std::string> w = viewWarnings(s, "cm.json");
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("\"auto\""), std::string::npos) << w[0];
}

// A groom of four files in one space (a ponytail's back, front, side and tail, the tail's
// roots in a small patch): "auto" takes one factor from all their roots together, so it draws
// as with the number that puts those roots at 0.18 m (hair masks' IoU at least 0.99), where a
// factor per file would scale the tail several times larger; one note line gives the factor.
TEST(ScaleAuto, AGroomOfSeveralFilesSharesOneFactor) {
  const std::string dir = test::scratchDir();
  const char* parts[] = {"back", "front", "side", "tail"};
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (int i = 0; i < 4; ++i) {
    CyHair h = centimetreGroom(40, false);
    for (std::size_t p = 0; p < h.points.size(); p += 3) {
      // back, front and side: discs around the head; the tail: 1.5 cm patch below the back
      const float sx = i == 3 ? 0.08f : 1.0f;
      h.points[p] = h.points[p] * sx + (i == 2 ? 6.0f : 0.0f);
      h.points[p + 2] = h.points[p + 2] * sx + (i == 0 ? -6.0f : i == 1 ? 6.0f : 0.0f);
      if (i == 3) {
        h.points[p + 1] -= 4.0f;
        h.points[p + 2] -= 8.0f;
      }
    }
    for (std::size_t s = 0; s < h.segments.size(); ++s) {
      const glm::vec3 r(h.points[s * 36], h.points[s * 36 + 1], h.points[s * 36 + 2]);
      lo = glm::min(lo, r);
      hi = glm::max(hi, r);
    }
    writeCyHair(h, dir + "/" + parts[i] + ".hair");
  }
  const glm::vec3 ext = hi - lo;
  const float factor = 0.18f / std::max(ext.x, std::max(ext.y, ext.z));
  auto scene = [&](const std::string& scale) {
    std::string grooms;
    for (const char* p : parts)
      grooms += std::string(grooms.empty() ? "" : ", ") + "{\"strands_file\": \"" + p +
                ".hair\", \"scale\": " + scale + "}";
    writeText(dir + "/p.json",
              "{\"resolution\": [160, 120], \"camera\": {\"preset\": \"mid\"}, "
              "\"grooms\": [" +
                  grooms + "]}");
    return loadScene(dir + "/p.json");
  };
  const Scene a = scene("\"auto\""), n = scene(std::to_string(factor));
  EXPECT_NEAR(a.grooms[3].transform[0][0], factor, 1e-4f * factor) << "the tail's factor";
  ASSERT_EQ(a.notes.size(), 1u);
  EXPECT_NE(a.notes[0].find("4 files"), std::string::npos) << a.notes[0];
  char f[32];
  std::snprintf(f, sizeof(f), "%g", static_cast<double>(a.grooms[0].transform[0][0]));
  EXPECT_NE(a.notes[0].find(f), std::string::npos) << a.notes[0];
  Renderer r(test::sharedDevice());
  const Image ia = r.render(a, RenderOptions{}).color, in = r.render(n, RenderOptions{}).color;
  std::size_t both = 0, either = 0;
  for (std::size_t i = 3; i < ia.rgba.size(); i += 4) {
    const bool ma = ia.rgba[i] > 0.05f, mn = in.rgba[i] > 0.05f;
    both += ma && mn;
    either += ma || mn;
  }
  ASSERT_GT(either, 200u) << "the groom covers some pixels";
  EXPECT_GE(static_cast<double>(both) / static_cast<double>(either), 0.99);
  // a groom that names its number keeps it; the others still share the factor
  writeText(dir + "/m.json",
            "{\"grooms\": [{\"strands_file\": \"back.hair\", \"scale\": \"auto\"}, "
            "{\"strands_file\": \"tail.hair\", \"scale\": 0.5}]}");
  const Scene m = loadScene(dir + "/m.json");
  EXPECT_FLOAT_EQ(m.grooms[1].transform[0][0], 0.5f);
  // the broken twin: a misspelt "auto" is one error line naming the entry
  writeText(dir + "/b.json",
            "{\"grooms\": [{\"strands_file\": \"back.hair\", \"scale\": \"auto\"}, "
            "{\"strands_file\": \"tail.hair\", \"scale\": \"Auto\"}]}");
  const std::string e = test::errorOf([&] { loadScene(dir + "/b.json"); });
  EXPECT_NE(e.find("grooms[1]"), std::string::npos) << e;
  EXPECT_NE(e.find("\"auto\""), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

// A small groom on a large head: the close preset frames both, so no mesh vertex falls off
// the image.
TEST(CameraPresets, FrameTheMeshesWithTheGrooms) {
  const std::string dir = test::scratchDir();
  writeCyHair(centimetreGroom(30, false), dir + "/g.hair");
  writeText(dir + "/head.obj",
            "v -30 -40 -30\nv 30 -40 -30\nv 30 20 30\nv -30 20 30\nf 1 2 3\nf 1 3 4\n");
  writeText(dir + "/h.json",
            R"({"resolution": [160, 120], "camera": {"preset": "close", "azimuth": 30},
                "meshes": [{"file": "head.obj", "scale": 0.01}],
                "grooms": [{"strands_file": "g.hair", "scale": 0.01}]})");
  const Scene s = loadScene(dir + "/h.json");
  const Camera& c = s.camera;
  const glm::vec3 f = glm::normalize(c.target - c.position);
  const glm::vec3 right = glm::normalize(glm::cross(f, c.up)), up = glm::cross(right, f);
  const float t = std::tan(glm::radians(c.fovYDegrees) * 0.5f), aspect = 160.0f / 120.0f;
  for (const glm::vec3& p : s.meshes[0].mesh->positions) {
    const glm::vec3 w(s.meshes[0].transform * glm::vec4(p, 1.0f));
    const glm::vec3 d = w - c.position;
    const float z = glm::dot(d, f);
    ASSERT_GT(z, 0.0f);
    EXPECT_LE(std::fabs(glm::dot(d, up) / z), t * 1.001f);
    EXPECT_LE(std::fabs(glm::dot(d, right) / z), t * aspect * 1.001f);
  }
}

}  // namespace
}  // namespace clhair
