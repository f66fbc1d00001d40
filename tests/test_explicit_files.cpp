// test_explicit_files.cpp — explicit strand grooms through files: scene files that name
// strand files (placement, scale, up axis), and the command line on strand files — malformed
// cyHair, USC-HairSalon and TressFX files refused with one line, trailing bytes warned
// about once. How they look (framing, units, file colours, thread counts):
// test_explicit_look.cpp. The kernel, round trips, LOD and device bytes: test_explicit.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clhair/renderer.h"
#include "clhair/strand_groom.h"
#include "float_frames.h"
#include "groom/presets.h"
#include "io/cyhair.h"
#include "io/tressfx.h"
#include "synthetic_groom.h"
#include "test_util.h"

namespace clhair {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::countOf;
using test::writeBytes;

// ---- scene files ----------------------------------------------------------------------------

struct Bytes {
  std::string data;
  Bytes& u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) data += static_cast<char>(v >> (8 * i) & 0xFF);
    return *this;
  }
  Bytes& u16(std::uint16_t v) {
    for (int i = 0; i < 2; ++i) data += static_cast<char>(v >> (8 * i) & 0xFF);
    return *this;
  }
  Bytes& f32(float v) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, 4);
    return u32(bits);
  }
};

// A cyHair header (flags 2: points only, or 3 with a segments array).
Bytes cyHeader(std::uint32_t strands, std::uint32_t points, std::uint32_t flags,
               std::uint32_t defaultSegments) {
  Bytes b;
  b.data = "HAIR";
  b.u32(strands)
      .u32(points)
      .u32(flags)
      .u32(defaultSegments)
      .f32(1.0f)
      .f32(0.0f)
      .f32(1.0f)
      .f32(1.0f)
      .f32(1.0f);
  b.data.append(88, '\0');
  return b;
}

// Three strands of four points each, every coordinate `v` or a small offset from it.
std::string validCyHair(float nanAt = -1.0f) {
  Bytes b = cyHeader(3, 12, 2, 3);
  for (int i = 0; i < 36; ++i)
    b.f32(i == static_cast<int>(nanAt) ? std::nanf("") : 0.01f * static_cast<float>(i % 7));
  return b.data;
}

json sceneWithStrands(const std::string& file) {
  return json{{"resolution", {48, 32}},
              {"camera", {{"position", {0.0, 0.03, 0.3}}, {"target", {0.0, 0.02, 0.0}}}},
              {"grooms", {{{"strands_file", file}}}}};
}

TEST(ExplicitScene, StrandFilesLoadWithTheirPlacement) {
  const std::string dir = test::scratchDir();
  writeBytes(dir + "/three.hair", validCyHair());
  // USC-HairSalon: 2 strands, the second of 1 point (skipped)
  Bytes usc;
  usc.u32(2).u32(3);
  for (int i = 0; i < 9; ++i) usc.f32(0.1f * static_cast<float>(i));
  usc.u32(1).f32(0.0f).f32(0.0f).f32(0.0f);
  writeBytes(dir + "/two.data", usc.data);
  json j = sceneWithStrands("three.hair");
  j["grooms"].push_back({{"strands_file", "two.data"},
                         {"up", "z"},
                         {"scale", 2.0},
                         {"transform", {{"translate", {1.0, 0.0, 0.0}}}},
                         {"appearance", {{"strand_width", 1e-4}, {"min_hit_diameter_px", 1.0}}},
                         {"lod", {{"enabled", true}, {"lambda", 2.0}}},
                         {"filter", {{"promote", false}, {"method", "lipp"}}}});
  j["filter"] = {{"radius", 3}, {"s_perp", 0.2}};
  writeBytes(dir + "/scene.json", j.dump());
  Scene s = loadScene(dir + "/scene.json");
  EXPECT_EQ(s.filter.radius, 3);
  EXPECT_FLOAT_EQ(s.filter.sPerp, 0.2f);
  EXPECT_TRUE(s.filter.promote);
  EXPECT_FALSE(s.grooms[0].hasFilter);
  ASSERT_TRUE(s.grooms[1].hasFilter);
  EXPECT_FALSE(s.grooms[1].filter.promote);
  EXPECT_EQ(s.grooms[1].filter.radius, 3);  // the groom's filter starts from the scene's
  EXPECT_EQ(s.filter.method, FilterParams::Method::Auto);  // "auto" unless a method is named
  EXPECT_EQ(s.grooms[1].filter.method, FilterParams::Method::Lipp);
  ASSERT_EQ(s.grooms.size(), 2u);
  ASSERT_TRUE(s.grooms[0].strands && !s.grooms[0].mesh);
  EXPECT_EQ(s.grooms[0].strands->pointCounts, std::vector<std::uint32_t>({4, 4, 4}));
  EXPECT_EQ(s.grooms[0].name, "three");
  const StrandGroom& usc2 = *s.grooms[1].strands;
  EXPECT_EQ(usc2.pointCounts, std::vector<std::uint32_t>({3}));
  EXPECT_FLOAT_EQ(usc2.appearance.strandWidth, 1e-4f);
  EXPECT_TRUE(usc2.lod.enabled);
  EXPECT_FLOAT_EQ(usc2.lod.lambda, 2.0f);
  // z up, scale 2, then the translation: file point (x, y, z) lands at (2x + 1, 2z, -2y)
  const glm::vec4 w = s.grooms[1].transform * glm::vec4(0.3f, 0.4f, 0.5f, 1.0f);
  EXPECT_NEAR(w.x, 1.6f, 1e-6f);
  EXPECT_NEAR(w.y, 1.0f, 1e-6f);
  EXPECT_NEAR(w.z, -0.8f, 1e-6f);
  // x up: the file's +x becomes +y, its +y becomes -x, a rotation (determinant 1)
  j["grooms"][1]["up"] = "x";
  writeBytes(dir + "/scene_x.json", j.dump());
  const glm::mat4 mx = loadScene(dir + "/scene_x.json").grooms[1].transform;
  const glm::vec4 wx =
      mx * glm::vec4(0.3f, 0.4f, 0.5f, 1.0f);  // -> (2 * -0.4 + 1, 2 * 0.3, 2 * 0.5)
  EXPECT_NEAR(wx.x, 0.2f, 1e-6f);
  EXPECT_NEAR(wx.y, 0.6f, 1e-6f);
  EXPECT_NEAR(wx.z, 1.0f, 1e-6f);
  EXPECT_NEAR(glm::determinant(glm::mat3(mx)), 8.0f, 1e-5f);  // scale 2 cubed, no mirror
  // a limit below the file's arrays refuses it before reading them
  try {
    loadScene(dir + "/scene.json", 100);
    ADD_FAILURE() << "a 100-byte limit was accepted";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("grooms[0].strands_file"), std::string::npos) << msg;
    EXPECT_NE(msg.find("limit"), std::string::npos) << msg;
  }
}

// ---- the CLI refuses malformed strand files ------------------------------------------------

// Writes `bytes` as `name` and a scene naming it (or the given scene), renders, and expects
// exit 1, one "clhair: error:" line holding every fragment, and no image.
void expectRefused(const std::string& dir, const std::string& name, const std::string& bytes,
                   json scene, const std::vector<std::string>& fragments) {
  SCOPED_TRACE(name);
  if (!bytes.empty()) writeBytes(dir + "/" + name, bytes);
  writeBytes(dir + "/scene.json", scene.dump());
  const std::string out = dir + "/out.png";
  test::CommandResult r =
      test::runCli("render " + test::quote(dir + "/scene.json") + " -o " + test::quote(out));
  SCOPED_TRACE("output was:\n" + r.output);
  EXPECT_EQ(r.exitCode, 1);
  const std::string line = test::onlyErrorLine(r.output);
  for (const std::string& f : fragments)
    EXPECT_NE(line.find(f), std::string::npos) << "missing \"" << f << "\": " << line;
  const std::size_t end = r.output.find('\n', r.output.find("clhair: error:"));
  if (end != std::string::npos) {
    EXPECT_EQ(r.output.find_first_not_of(" \n\r\t", end), std::string::npos)
        << "more than one line";
  }
  EXPECT_FALSE(fs::exists(out)) << "an image was written although the render failed";
}

TEST(ExplicitCli, MalformedStrandFilesAreRefusedWithOneLine) {
  const std::string dir = test::scratchDir();
  const std::vector<std::string> where = {"scene.json", "grooms[0].strands_file"};
  auto with = [&](std::vector<std::string> extra) {
    extra.insert(extra.begin(), where.begin(), where.end());
    return extra;
  };
  const std::string valid = validCyHair();
  expectRefused(dir, "truncated.hair", valid.substr(0, 128 + 50),
                sceneWithStrands("truncated.hair"), with({"truncated.hair", "truncated"}));
  {
    Bytes b = cyHeader(3, 12, 3, 0);  // segments 3 + 3 + 4 = 10 + 3 points = 13, header 12
    b.u16(3).u16(3).u16(4);
    for (int i = 0; i < 36; ++i) b.f32(0.01f * static_cast<float>(i));
    expectRefused(dir, "counts.hair", b.data, sceneWithStrands("counts.hair"),
                  with({"counts.hair", "12 points", "adds up to 13"}));
  }
  expectRefused(dir, "nan.hair", validCyHair(17.0f), sceneWithStrands("nan.hair"),
                with({"nan.hair", "point 5", "finite"}));
  expectRefused(dir, "empty.hair", cyHeader(0, 0, 2, 0).data, sceneWithStrands("empty.hair"),
                with({"empty.hair", "0 strands"}));
  expectRefused(dir, "absurd.hair",
                cyHeader(0xFFFFFFFFu, 0xFFFFFFFFu, 2, 0).data + std::string(64, '\0'),
                sceneWithStrands("absurd.hair"), with({"absurd.hair", "4294967295"}));
  {
    Bytes b = cyHeader(3, 3, 2, 0);  // three single-point strands: nothing to draw
    for (int i = 0; i < 9; ++i) b.f32(0.0f);
    expectRefused(dir, "points.hair", b.data, sceneWithStrands("points.hair"),
                  with({"points.hair", "no strand has 2 or more points"}));
  }
  {
    Bytes b;  // USC-HairSalon: 2 strands announced, the file ends inside the first
    b.u32(2).u32(5).f32(0.0f).f32(1.0f);
    expectRefused(dir, "short.data", b.data, sceneWithStrands("short.data"), with({"short.data"}));
  }
  expectRefused(dir, "groom.txt", valid, sceneWithStrands("groom.txt"),
                with({"groom.txt", ".hair", ".data"}));
  {
    json s = sceneWithStrands("missing.hair");
    expectRefused(dir, "", "", s, with({"missing.hair", "does not exist"}));
  }
  writeBytes(dir + "/ok.hair", valid);
  {
    json s = sceneWithStrands("ok.hair");
    s["grooms"][0]["file"] = test::assetPath("grooms/tiny.hairmesh.json");
    expectRefused(dir, "", "", s, {"scene.json", "grooms[0]", "exactly one"});
  }
  {
    json s = sceneWithStrands("ok.hair");
    s["grooms"][0]["up"] = "w";
    expectRefused(dir, "", "", s, {"scene.json", "grooms[0].up", "\"w\"", "\"x\", \"y\" or \"z\""});
  }
  {
    json s = sceneWithStrands("ok.hair");
    s["grooms"][0]["strands"] = 100;  // a hair-mesh override means nothing here
    expectRefused(dir, "", "", s, {"scene.json", "grooms[0]", "strands"});
  }
}

// A TressFX 4.0 file of `strands` strands of 4 vertices near the origin (every coordinate
// from 0 to 0.03), the value at float index `nanAt` of the positions replaced by NaN.
std::string validTressFx(std::uint32_t strands = 3, int nanAt = -1) {
  Bytes b;
  b.f32(4.0f).u32(strands).u32(4).u32(160);
  for (int i = 0; i < 4 + 32; ++i) b.u32(0);
  for (std::uint32_t i = 0; i < strands * 4 * 4; ++i)
    b.f32(static_cast<int>(i) == nanAt ? std::nanf("")
          : i % 4 == 3                 ? 1.0f
                                       : 0.005f * static_cast<float>(i % 7));
  return b.data;
}

TEST(ExplicitCli, MalformedTressFxFilesAreRefusedWithOneLine) {
  const std::string dir = test::scratchDir();
  auto with = [](std::vector<std::string> extra) {
    extra.insert(extra.begin(), {"scene.json", "grooms[0].strands_file"});
    return extra;
  };
  const std::string valid = validTressFx();
  expectRefused(dir, "header.tfx", valid.substr(0, 100), sceneWithStrands("header.tfx"),
                with({"header.tfx", "is 100 bytes", "160-byte header"}));
  expectRefused(dir, "data.tfx", valid.substr(0, valid.size() - 5), sceneWithStrands("data.tfx"),
                with({"data.tfx", "truncated", "vertex positions"}));
  expectRefused(dir, "nan.tfx", validTressFx(3, 21), sceneWithStrands("nan.tfx"),
                with({"nan.tfx", "strand 1 vertex 1 y is nan", "finite"}));
  std::string huge = valid;
  huge.replace(4, 4, Bytes().u32(0xFFFFFFFFu).data);
  expectRefused(dir, "huge.tfx", huge, sceneWithStrands("huge.tfx"),
                with({"huge.tfx", "truncated", "4294967295 strands"}));
  std::string version = valid;
  version.replace(0, 4, Bytes().f32(2.5f).data);
  expectRefused(dir, "version.tfx", version, sceneWithStrands("version.tfx"),
                with({"version.tfx", "version field is 2.5", "3.x or 4.x"}));
  expectRefused(dir, "text.tfx", "numStrands 3\nis sorted 1\n", sceneWithStrands("text.tfx"),
                with({"text.tfx", "text layout is not supported"}));
}

// Bytes after the strand data: every format renders, with one warning line naming the file
// and the byte count.
TEST(ExplicitCli, TrailingBytesWarnOnceInEveryFormat) {
  const std::string dir = test::scratchDir();
  Bytes usc;
  usc.u32(1).u32(3);
  for (int i = 0; i < 9; ++i) usc.f32(0.01f * static_cast<float>(i));
  const struct {
    std::string name, bytes;
  } cases[] = {{"extra.hair", validCyHair() + "abcde"},
               {"extra.data", usc.data + "abcde"},
               {"extra.tfx", validTressFx() + "abcde"}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    writeBytes(dir + "/" + c.name, c.bytes);
    writeBytes(dir + "/scene.json", sceneWithStrands(c.name).dump());
    const std::string out = dir + "/out_" + c.name + ".png";
    test::CommandResult r =
        test::runCli("render " + test::quote(dir + "/scene.json") + " -o " + test::quote(out));
    SCOPED_TRACE("output was:\n" + r.output);
    EXPECT_EQ(r.exitCode, 0);
    EXPECT_TRUE(fs::exists(out));
    ASSERT_EQ(countOf(r.output, "clhair: warning:"), 1u);
    const std::size_t begin = r.output.find("clhair: warning:");
    const std::string line = r.output.substr(begin, r.output.find('\n', begin) - begin);
    EXPECT_NE(line.find(c.name), std::string::npos) << line;
    EXPECT_NE(line.find("5 bytes"), std::string::npos) << line;
  }
}

}  // namespace
}  // namespace clhair
