// test_cli.cpp — the `clhair` command end to end: bad input is refused cleanly, good input
// renders hair.
//
// Bad input: every case must exit non-zero, print "clhair: error:" exactly once, on one
// line that names what is wrong (the file, the key or the value), and leave no output file
// (nor a temporary one) behind. Bad hair meshes are made from assets/grooms/tiny.hairmesh.json
// by editing it as JSON and writing it to the test's scratch folder.
// End to end: assets/scenes/default.json rendered at 320x180 against the same scene without
// its grooms (camera pinned to the one the scene resolves to) must differ where the hair is
// (more than 2 % of the pixels, some in the central region) and nowhere in the corners;
// `clhair groom --preset tiny` writes the preset, which renders as the one built in memory;
// `clhair devices` lists a device with 64-bit atomics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "clhair/image.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "groom/presets.h"
#include "test_util.h"

namespace clhair::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json readJson(const std::string& path) {
  std::ifstream in(path);
  return json::parse(in);
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

void writeJson(const std::string& path, const json& j) { writeText(path, j.dump(2)); }

json tinyGroom() { return readJson(assetPath("grooms/tiny.hairmesh.json")); }

// A small scene in `dir` that uses the groom file `groomFile` (relative to `dir`).
json sceneWith(const std::string& groomFile) {
  return json{
      {"resolution", {64, 48}},
      {"camera", {{"position", {0.0, 0.03, 0.2}}, {"target", {0.0, 0.025, 0.0}}, {"fov", 35}}},
      {"lights", {{{"type", "directional"}, {"direction", {0.3, 0.8, 0.5}}}}},
      {"spheres", {{{"center", {0, -0.01, 0}}, {"radius", 0.02}}}},
      {"grooms", {{{"file", groomFile}}}}};
}

std::size_t countOf(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

bool onlyWhitespace(const std::string& s) {
  return std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isspace(c); });
}

// A refused command: non-zero exit, one "clhair: error:" line holding every fragment, nothing
// printed after it, and no output file nor leftover temporary in the output's folder.
void expectRefused(const CommandResult& r, const std::vector<std::string>& fragments,
                   const std::string& outputPath) {
  SCOPED_TRACE("output was:\n" + r.output);
  EXPECT_NE(r.exitCode, 0);
  const std::string marker = "clhair: error:";
  ASSERT_EQ(countOf(r.output, marker), 1u);
  std::size_t begin = r.output.find(marker);
  std::size_t end = r.output.find('\n', begin);
  std::string line =
      r.output.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
  for (const std::string& f : fragments)
    EXPECT_NE(line.find(f), std::string::npos) << "the error line lacks \"" << f << "\": " << line;
  if (end != std::string::npos) {
    EXPECT_TRUE(onlyWhitespace(r.output.substr(end))) << "the error spans more than one line";
  }
  EXPECT_FALSE(fs::exists(outputPath)) << outputPath << " was written although the command failed";
  fs::path folder = fs::path(outputPath).parent_path();
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(folder, ec))
    EXPECT_EQ(e.path().filename().string().rfind(".tmp-", 0), std::string::npos)
        << "temporary file left behind: " << e.path();
}

// Writes `groom` and a scene using it to `dir`, renders, and expects a refusal.
void expectGroomRefused(const std::string& dir, const std::string& groomText,
                        const std::string& groomName, const std::vector<std::string>& fragments) {
  writeText(dir + "/" + groomName, groomText);
  writeJson(dir + "/scene.json", sceneWith(groomName));
  const std::string out = dir + "/out.png";
  expectRefused(runCli("render " + quote(dir + "/scene.json") + " -o " + quote(out)), fragments,
                out);
}

// ---- bad input ----------------------------------------------------------------------------

TEST(Cli, MalformedSceneJson) {
  const std::string dir = scratchDir();
  // Line 4 closes the object while the "grooms" array of line 3 is still open.
  writeText(dir + "/broken.json",
            "{\n  \"resolution\": [64, 48],\n  \"grooms\": [ {\"file\": \"x.json\"}\n}\n");
  const std::string out = dir + "/out.png";
  expectRefused(runCli("render " + quote(dir + "/broken.json") + " -o " + quote(out)),
                {"broken.json:4:1", "malformed"}, out);
}

TEST(Cli, MissingGroomFile) {
  const std::string dir = scratchDir();
  writeJson(dir + "/scene.json", sceneWith("no_such_groom.hairmesh.json"));
  const std::string out = dir + "/out.png";
  expectRefused(runCli("render " + quote(dir + "/scene.json") + " -o " + quote(out)),
                {"no_such_groom.hairmesh.json", "does not exist"}, out);
}

TEST(Cli, HairMeshWithOverflowingVertex) {
  // JSON has no NaN or infinity; 1e400 is the closest a file can get (it overflows a double).
  const std::string dir = scratchDir();
  json g = tinyGroom();
  g["layers"][1][4] = 12345.625;
  std::string text = g.dump(2);
  std::size_t at = text.find("12345.625");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 9, "1e400");
  expectGroomRefused(dir, text, "overflow.hairmesh.json", {"overflow.hairmesh.json"});
}

TEST(Cli, HairMeshWithNonNumericVertex) {
  const std::string dir = scratchDir();
  json g = tinyGroom();
  g["layers"][1][4] = "NaN";
  expectGroomRefused(dir, g.dump(2), "nan.hairmesh.json", {"nan.hairmesh.json", "layers[1][4]"});
}

TEST(Cli, HairMeshWithOneLayer) {
  const std::string dir = scratchDir();
  json g = tinyGroom();
  g["layer_count"] = 1;
  g["layers"] = json::array({g["layers"][0]});
  expectGroomRefused(dir, g.dump(2), "one_layer.hairmesh.json",
                     {"one_layer.hairmesh.json", "layer"});
}

TEST(Cli, HairMeshWithFaceIndexOutOfRange) {
  const std::string dir = scratchDir();
  json g = tinyGroom();
  const int vertexCount = g["vertex_count"].get<int>();
  g["faces"][1][2] = vertexCount;
  expectGroomRefused(dir, g.dump(2), "bad_face.hairmesh.json",
                     {"bad_face.hairmesh.json", "faces[1]", std::to_string(vertexCount)});
}

TEST(Cli, ZeroResolutionInScene) {
  const std::string dir = scratchDir();
  json s = sceneWith(assetPath("grooms/tiny.hairmesh.json"));
  s["resolution"] = {0, 100};
  writeJson(dir + "/scene.json", s);
  const std::string out = dir + "/out.png";
  expectRefused(runCli("render " + quote(dir + "/scene.json") + " -o " + quote(out)),
                {"scene.json", "resolution", "0x100"}, out);
}

TEST(Cli, AbsurdResolutionInScene) {
  const std::string dir = scratchDir();
  json s = sceneWith(assetPath("grooms/tiny.hairmesh.json"));
  s["resolution"] = {100000, 100000};
  writeJson(dir + "/scene.json", s);
  const std::string out = dir + "/out.png";
  expectRefused(runCli("render " + quote(dir + "/scene.json") + " -o " + quote(out)),
                {"scene.json", "resolution", "100000x100000"}, out);
}

TEST(Cli, ZeroWidthOption) {
  const std::string dir = scratchDir();
  writeJson(dir + "/scene.json", sceneWith(assetPath("grooms/tiny.hairmesh.json")));
  const std::string out = dir + "/out.png";
  expectRefused(runCli("render " + quote(dir + "/scene.json") + " -o " + quote(out) + " --width 0"),
                {"0"}, out);
}

TEST(Cli, AbsurdWidthOption) {
  const std::string dir = scratchDir();
  writeJson(dir + "/scene.json", sceneWith(assetPath("grooms/tiny.hairmesh.json")));
  const std::string out = dir + "/out.png";
  expectRefused(runCli("render " + quote(dir + "/scene.json") + " -o " + quote(out) +
                       " --width 100000 --height 100"),
                {"resolution", "100000x100"}, out);
}

TEST(Cli, UnknownGroomPreset) {
  const std::string dir = scratchDir();
  const std::string out = dir + "/x.json";
  expectRefused(runCli("groom --preset nope -o " + quote(out)), {"\"nope\"", "tiny"}, out);
}

TEST(Cli, MissingSceneFile) {
  const std::string dir = scratchDir();
  const std::string out = dir + "/out.png";
  expectRefused(runCli("render " + quote(dir + "/no_such_scene.json") + " -o " + quote(out)),
                {"no_such_scene.json"}, out);
}

TEST(Cli, UnknownSubgroupBackend) {
  const std::string dir = scratchDir();
  writeJson(dir + "/scene.json", sceneWith(assetPath("grooms/tiny.hairmesh.json")));
  const std::string out = dir + "/out.png";
  expectRefused(
      runCli("--subgroup bogus render " + quote(dir + "/scene.json") + " -o " + quote(out)),
      {"\"bogus\"", "local"}, out);
}

TEST(Cli, ParseErrorsAreOneErrorLineAndExitOne) {
  const std::string dir = scratchDir();
  writeJson(dir + "/scene.json", sceneWith(assetPath("grooms/tiny.hairmesh.json")));
  const std::string out = dir + "/out.png";
  const std::string render = "render " + quote(dir + "/scene.json") + " -o " + quote(out);
  const struct {
    std::string args;
    std::vector<std::string> fragments;
  } cases[] = {{render + " --width abc", {"--width", "abc"}},
               {render + " --no-such-flag", {"--no-such-flag"}},
               {"render -o " + quote(out), {"scene"}},
               {render + " --reference foo", {"--reference", "foo", "embree", "raster", "path"}},
               {render + " --reference --spp 0", {"--spp", "0"}},
               {render + " --reference path --path-events 0", {"--path-events", "0"}},
               {"", {"subcommand"}}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args);
    const CommandResult r = runCli(c.args);
    EXPECT_EQ(r.exitCode, 1) << r.output;
    expectRefused(r, c.fragments, out);
    EXPECT_EQ(r.output.rfind("clhair: error:", 0), 0u) << "not the only line:\n" << r.output;
  }
  for (const std::string help : {"--help", "render --help"}) {
    const CommandResult r = runCli(help);
    EXPECT_EQ(r.exitCode, 0) << help << ":\n" << r.output;
    EXPECT_NE(r.output.find("Usage"), std::string::npos) << r.output;
  }
}

// ---- end to end ---------------------------------------------------------------------------

// The references run from the CLI, report their progress on stderr and write the image;
// a bare --reference is the traced one.
TEST(Cli, ReferenceMethodsRenderWithProgress) {
  const std::string dir = scratchDir();
  writeJson(dir + "/scene.json", sceneWith(assetPath("grooms/tiny.hairmesh.json")));
  const std::string render = "render " + quote(dir + "/scene.json") + " --width 48 --height 32";
  for (const std::string method : {"", "embree", "raster", "path"}) {
    SCOPED_TRACE("--reference " + method);
    const std::string out = dir + "/ref_" + (method.empty() ? "bare" : method) + ".png";
    const CommandResult r =
        runCli(render + " -o " + quote(out) + " --reference " + method + " --spp 3");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("reference 3/3 samples"), std::string::npos) << r.output;
    EXPECT_TRUE(fs::exists(out));
    // the traced reference reports its trace stage, the raster one its strand pass, the
    // path-traced one its paths
    const bool traced = method != "raster" && method != "path";
    EXPECT_EQ(r.output.find("  trace ") != std::string::npos, traced) << r.output;
    EXPECT_EQ(r.output.find("  paths ") != std::string::npos, method == "path") << r.output;
  }
}

// Pixels (x, y) whose colours differ between two images of equal size.
bool pixelDiffers(const Image& a, const Image& b, int x, int y) {
  const float* p = a.pixel(x, y);
  const float* q = b.pixel(x, y);
  return p[0] != q[0] || p[1] != q[1] || p[2] != q[2];
}

TEST(Cli, DefaultSceneShowsHairOverTheOpaqueScene) {
  const std::string dir = scratchDir();
  const std::string scenePath = assetPath("scenes/default.json");
  const int w = 320, h = 180;

  // The same scene without grooms. The camera is written out explicitly as the scene
  // resolves it, since a preset camera frames the grooms and would move without them.
  Scene resolved = loadScene(scenePath);
  json bare = readJson(scenePath);
  bare.erase("grooms");
  const Camera& c = resolved.camera;
  bare["camera"] = {{"position", {c.position.x, c.position.y, c.position.z}},
                    {"target", {c.target.x, c.target.y, c.target.z}},
                    {"up", {c.up.x, c.up.y, c.up.z}},
                    {"fov", c.fovYDegrees}};
  writeJson(dir + "/bare.json", bare);

  const std::string withHair = dir + "/with_hair.png", without = dir + "/without_hair.png";
  const std::string size = " --width " + std::to_string(w) + " --height " + std::to_string(h);
  CommandResult r1 = runCli("render " + quote(scenePath) + " -o " + quote(withHair) + size);
  ASSERT_EQ(r1.exitCode, 0) << r1.output;
  CommandResult r2 = runCli("render " + quote(dir + "/bare.json") + " -o " + quote(without) + size);
  ASSERT_EQ(r2.exitCode, 0) << r2.output;

  Image a = readImage(withHair), b = readImage(without);
  ASSERT_EQ(a.width, w);
  ASSERT_EQ(a.height, h);
  ASSERT_EQ(b.width, w);
  ASSERT_EQ(b.height, h);

  std::size_t differing = 0, differingCentral = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (pixelDiffers(a, b, x, y)) {
        ++differing;
        if (x >= w / 4 && x < 3 * w / 4 && y >= h / 4 && y < 3 * h / 4) ++differingCentral;
      }
  const double fraction = static_cast<double>(differing) / (static_cast<double>(w) * h);
  EXPECT_GT(fraction, 0.02) << "the groom changed only " << differing << " pixels; see "
                            << withHair;
  EXPECT_GT(differingCentral, 0u) << "no hair in the central region; see " << withHair;

  // The groom stays away from the corners: there both renders must match exactly.
  const int k = 8;
  std::size_t cornerDiffs = 0;
  for (int cy : {0, h - k})
    for (int cx : {0, w - k})
      for (int y = cy; y < cy + k; ++y)
        for (int x = cx; x < cx + k; ++x) cornerDiffs += pixelDiffers(a, b, x, y) ? 1 : 0;
  EXPECT_EQ(cornerDiffs, 0u) << "the background changed in the corners; compare " << withHair
                             << " and " << without;
}

// Fraction of pixels whose colours differ by more than `tolerance` in some channel.
double fractionDiffering(const Image& a, const Image& b, float tolerance) {
  std::size_t n = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = 0; c < 3; ++c)
        if (std::fabs(a.pixel(x, y)[c] - b.pixel(x, y)[c]) > tolerance) {
          ++n;
          break;
        }
  return static_cast<double>(n) / (static_cast<double>(a.width) * a.height);
}

// --camera close|mid|far keeps the viewing angle of the scene's camera (a preset's azimuth
// and elevation, or an explicit camera's direction) and changes only distance and framing.
TEST(Cli, CameraOptionKeepsTheScenesViewingAngle) {
  const std::string dir = scratchDir();
  const float az = 90.0f, el = 30.0f;
  json base = sceneWith(assetPath("grooms/tiny.hairmesh.json"));
  base["resolution"] = {96, 64};
  auto render = [&](const std::string& name, const json& camera, const std::string& option) {
    json s = base;
    s["camera"] = camera;
    writeJson(dir + "/" + name + ".json", s);
    const std::string out = dir + "/" + name + ".png";
    const CommandResult r =
        runCli("render " + quote(dir + "/" + name + ".json") + " -o " + quote(out) + option);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return readImage(out);
  };
  // what the scene itself asks for: a close preset from (90, 30)
  const Image expected =
      render("close", {{"preset", "close"}, {"azimuth", az}, {"elevation", el}}, "");
  const Image fromPreset =
      render("mid", {{"preset", "mid"}, {"azimuth", az}, {"elevation", el}}, " --camera close");
  // an explicit camera looking from the same direction
  const double a = az * 3.14159265358979 / 180.0, e = el * 3.14159265358979 / 180.0;
  const std::vector<double> target = {0.0, 0.02, 0.0};
  const std::vector<double> position = {0.3 * std::sin(a) * std::cos(e), 0.02 + 0.3 * std::sin(e),
                                        0.3 * std::cos(a) * std::cos(e)};
  const Image fromExplicit = render(
      "explicit", {{"position", position}, {"target", target}, {"fov", 35}}, " --camera close");
  // the angle the option used to impose whatever the scene said
  const Image oldDefault =
      render("default", {{"preset", "close"}, {"azimuth", 0}, {"elevation", 10}}, "");

  EXPECT_GT(fractionDiffering(expected, oldDefault, 0.02f), 0.05)
      << "the two viewing angles look alike, the test cannot tell them apart";
  EXPECT_LT(fractionDiffering(expected, fromPreset, 0.02f), 0.01) << "see " << dir;
  EXPECT_LT(fractionDiffering(expected, fromExplicit, 0.02f), 0.01) << "see " << dir;

  // the camera itself: the same direction, the preset's distance
  Scene s = loadScene(dir + "/explicit.json");
  const Camera want = framePreset(s, CameraPreset::Close, az, el, 35.0f);
  const Camera got = reframeCamera(s, CameraPreset::Close);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(got.position[i], want.position[i], 1e-5f) << i;
    EXPECT_NEAR(got.target[i], want.target[i], 1e-6f) << i;
  }
}

// `clhair groom --preset tiny` writes the preset itself: its file renders through the CLI
// exactly as the preset built in memory renders through the API (same scene, same PNG
// writer), and the hair changes every pixel where a strand covers the centre.
TEST(Cli, GeneratedPresetGroomRenders) {
  const std::string dir = scratchDir();
  const std::string groom = dir + "/tiny_preset.json";
  CommandResult g = runCli("groom --preset tiny -o " + quote(groom));
  ASSERT_EQ(g.exitCode, 0) << g.output;
  ASSERT_TRUE(fs::exists(groom));

  json scene = sceneWith("tiny_preset.json");
  scene["camera"] = {{"preset", "close"}};
  scene["grooms"][0]["strands"] = 2000;  // dense enough to cover a good part of the frame
  // the preset's file round trip is the subject, not the light's map: without it (under
  // ASan one pixel of the mapped frame differed between the CLI and the API, not explained)
  scene["lights"][0]["shadows"] = false;
  writeJson(dir + "/scene.json", scene);
  const std::string out = dir + "/out.png";
  CommandResult r = runCli("render " + quote(dir + "/scene.json") + " -o " + quote(out));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  ASSERT_TRUE(fs::exists(out));

  // the same scene with the preset built in memory, through the API
  Scene api = loadScene(dir + "/scene.json");
  ASSERT_EQ(api.grooms.size(), 1u);
  HairMesh preset = makeGroomPreset("tiny");
  preset.strandCount = 2000;
  preset.lod.enabled = true;  // `clhair groom` writes a file that draws with LOD
  api.grooms[0].mesh = std::make_shared<const HairMesh>(preset);
  Renderer renderer(sharedDevice());
  RenderOptions o;
  o.captureGBuffer = true;
  const Frame f = renderer.render(api, o);
  const std::string apiPng = dir + "/api.png";
  writeImage(f.color, apiPng);

  // the same scene with the groom's strand count set to zero (which keeps the preset
  // camera's framing)
  scene["grooms"][0]["strands"] = 0;
  writeJson(dir + "/no_strands.json", scene);
  const std::string bare = dir + "/no_strands.png";
  CommandResult r0 = runCli("render " + quote(dir + "/no_strands.json") + " -o " + quote(bare));
  ASSERT_EQ(r0.exitCode, 0) << r0.output;

  Image a = readImage(out), b = readImage(bare), c = readImage(apiPng);
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  ASSERT_EQ(a.width, c.width);
  ASSERT_EQ(a.height, c.height);
  std::size_t fromFile = 0, centreHits = 0, changed = 0;
  const std::size_t pixels = static_cast<std::size_t>(a.width) * a.height;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * a.width + x;
      fromFile += pixelDiffers(a, c, x, y) ? 1 : 0;
      const bool hit = f.gbuffer[i] != ~std::uint64_t(0);
      centreHits += hit ? 1 : 0;
      changed += hit && pixelDiffers(a, b, x, y) ? 1 : 0;
    }
  EXPECT_EQ(fromFile, 0u) << "the written preset renders unlike the preset itself: compare " << out
                          << " and " << apiPng;
  EXPECT_GT(centreHits, pixels / 20) << "the close preset should fill a good part of the frame";
  EXPECT_EQ(changed, centreHits)
      << "pixels with a strand over their centre look like the bare scene: " << out;
}

TEST(Cli, DevicesListsA64BitAtomicsDevice) {
  CommandResult r = runCli("devices");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("64-bit atomics"), std::string::npos) << r.output;
  EXPECT_TRUE(std::regex_search(r.output, std::regex("64-bit atomics +yes")))
      << "no device with 64-bit atomics:\n"
      << r.output;
}

}  // namespace
}  // namespace clhair::test
