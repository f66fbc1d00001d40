// test_refusals.cpp — input clhair used to accept silently, limits it did not state, and error
// paths that printed more than one line (issue 27). Each test here failed on the code before:
//
// - refused: an empty --frames value, a degenerate groom matrix, a hair mesh without a
//   required key, a negative --strands, unknown output extensions (before any work), an unknown
//   subcommand (named), cage coordinates beyond the bound of layer vertices;
// - warned: a groom that draws no strand, with the reason;
// - limits: the strands per bundle checked when the hair mesh is read (file and bundle named),
//   HDR output written as RGB, a 254-byte output name written, an image header that declares
//   far more than its file holds refused before its pixels are allocated;
// - one line: device selection, a kernel build failure, damaged images as background and
//   environment; details behind --verbose or in the log file the line names.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "clhair/animation.h"
#include "clhair/hair_mesh.h"
#include "clhair/image.h"
#include "clhair/scene.h"
#include "fault_fs.h"
#include "io/cyhair.h"
#include "test_util.h"

namespace clhair::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json readJson(const std::string& path) {
  std::ifstream in(path);
  return json::parse(in);
}

json tinyGroom() { return readJson(assetPath("grooms/tiny.hairmesh.json")); }

json sceneWith(const json& groomEntry) {
  return json{
      {"resolution", {40, 30}},
      {"camera", {{"position", {0.0, 0.03, 0.2}}, {"target", {0.0, 0.025, 0.0}}, {"fov", 35}}},
      {"lights", {{{"type", "directional"}, {"direction", {0.3, 0.8, 0.5}}}}},
      {"grooms", {groomEntry}}};
}

std::size_t lines(const std::string& text) {
  std::size_t n = 0;
  for (char c : text) n += c == '\n';
  return n + (!text.empty() && text.back() != '\n');
}

// A refused command: exit code 1, one line that is the error line and holds every fragment,
// and `output` (if given) not written.
void expectRefused(const CommandResult& r, const std::vector<std::string>& fragments,
                   const std::string& output = {}) {
  SCOPED_TRACE("output was:\n" + r.output);
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_EQ(lines(r.output), 1u);
  const std::string line = onlyErrorLine(r.output);
  for (const std::string& f : fragments)
    EXPECT_NE(line.find(f), std::string::npos) << "the line lacks \"" << f << "\"";
  if (!output.empty()) {
    EXPECT_FALSE(fs::exists(output)) << output << " was written";
  }
}

// ---- silent acceptance -------------------------------------------------------------------

TEST(Refusals, EmptyFramesValue) {
  const std::string dir = scratchDir();
  writeBytes(dir + "/scene.json",
             sceneWith({{"file", assetPath("grooms/tiny.hairmesh.json")}}).dump());
  // `--frames "$SLURM_ARRAY_TASK_ID"` with the variable unset: every task rendered frame 1
  const CommandResult r = runCli("render " + quote(dir + "/scene.json") + " --frames '' -q -o " +
                                 quote(dir + "/f.####.png"));
  expectRefused(r, {"--frames", "empty"});
  EXPECT_TRUE(listFolder(dir).size() == 1u) << "something was written";
}

TEST(Refusals, DegenerateGroomMatrix) {
  const std::string dir = scratchDir();
  const std::vector<std::vector<double>> degenerate = {
      std::vector<double>(16, 0.0),                       // zeros
      {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1},   // flattens z
      {1, 2, 3, 0, 2, 4, 6, 0, 0, 0, 1, 0, 0, 0, 0, 1}};  // two equal rows
  for (const auto& m : degenerate) {
    json s = sceneWith(
        {{"file", assetPath("grooms/tiny.hairmesh.json")}, {"transform", {{"matrix", m}}}});
    writeBytes(dir + "/scene.json", s.dump());
    const std::string e = errorOf([&] { loadScene(dir + "/scene.json"); });
    EXPECT_NE(e.find("grooms[0].transform.matrix"), std::string::npos) << e;
    EXPECT_NE(e.find("degenerate"), std::string::npos) << e;
  }
  // a small but regular matrix (scale 1e-3) stays valid
  json s = sceneWith(
      {{"file", assetPath("grooms/tiny.hairmesh.json")},
       {"transform", {{"matrix", {1e-3, 0, 0, 0, 0, 1e-3, 0, 0, 0, 0, 1e-3, 0, 0, 0, 0, 1}}}}});
  writeBytes(dir + "/scene.json", s.dump());
  EXPECT_EQ(errorOf([&] { loadScene(dir + "/scene.json"); }), "");
}

// A strand file in absurd units framed by a camera preset draws nothing; the render says why.
TEST(Refusals, GroomThatDrawsNothingIsExplained) {
  const std::string dir = scratchDir();
  CyHair h;
  for (int s = 0; s < 4; ++s) {
    h.segments.push_back(7);
    for (int k = 0; k < 8; ++k) h.points.insert(h.points.end(), {1e-30f * (s + 1), 1e-30f * k, 0});
  }
  h.defaultThickness = 1e-32f;
  writeCyHair(h, dir + "/tiny30.hair");
  json s = sceneWith({{"strands_file", "tiny30.hair"}});
  s["camera"] = {{"preset", "mid"}};
  writeBytes(dir + "/scene.json", s.dump());
  const CommandResult r =
      runCli("render " + quote(dir + "/scene.json") + " -q -o " + quote(dir + "/out.png"));
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("clhair: warning:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("grooms[0] (\"tiny30\") draws none of its 4 strands"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("too small"), std::string::npos) << r.output;
}

TEST(Refusals, HairMeshWithoutARequiredKey) {
  const std::string dir = scratchDir();
  for (const std::string key :
       {"format", "version", "layer_count", "vertex_count", "faces", "uv", "layers"}) {
    SCOPED_TRACE(key);
    json g = tinyGroom();
    g.erase(key);
    writeBytes(dir + "/g.json", g.dump());
    const std::string e = errorOf([&] { loadHairMesh(dir + "/g.json"); });
    EXPECT_NE(e.find("g.json: " + key + ": is missing"), std::string::npos) << e;
  }
}

TEST(Refusals, NegativeStrandCount) {
  const std::string dir = scratchDir();
  expectRefused(runCli("groom --preset tiny --strands -5 -o " + quote(dir + "/g.json")),
                {"--strands", "-5"}, dir + "/g.json");
}

// Refused before any work: the scene file is not even read, nor the images compared.
TEST(Refusals, UnknownOutputExtensionsBeforeAnyWork) {
  const std::string dir = scratchDir();
  expectRefused(runCli("render " + quote(dir + "/no_scene.json") + " -o " + quote(dir + "/x.xyz")),
                {"x.xyz", "\".xyz\""});
  expectRefused(runCli("render " + quote(dir + "/no_scene.json") + " --frames 1-2 -o " +
                       quote(dir + "/x.####.xyz")),
                {"x.####.xyz", "\".xyz\""});
  expectRefused(runCli("compare " + quote(dir + "/a.png") + " " + quote(dir + "/b.png") +
                       " --error-map " + quote(dir + "/map.xyz")),
                {"map.xyz", "\".xyz\""});
  expectRefused(runCli("export-strands " + quote(assetPath("grooms/tiny.hairmesh.json")) + " -o " +
                       quote(dir + "/x.xyz")),
                {"x.xyz", "\".xyz\"", ".hair", ".tfx"}, dir + "/x.xyz");
  // a missing folder: refused once the scene is read (its views name the outputs), unrendered
  writeBytes(dir + "/scene.json",
             sceneWith({{"file", assetPath("grooms/tiny.hairmesh.json")}}).dump());
  expectRefused(
      runCli("render " + quote(dir + "/scene.json") + " -o " + quote(dir + "/no_folder/x.png")),
      {"no_folder", "no such file or directory"});
}

TEST(Refusals, UnknownSubcommandIsNamed) {
  const std::string dir = scratchDir();
  expectRefused(runCli("rendr scene.json -o " + quote(dir + "/x.png")),
                {"unknown subcommand \"rendr\"", "render"});
  expectRefused(runCli("--device 0:0 rendr"), {"\"rendr\""});
}

TEST(Refusals, CageAndLayerCoordinatesBeyondTheBound) {
  const std::string dir = scratchDir();
  CageAnimation c;
  c.frames = 1;
  c.vertices = 3;
  c.positions = {glm::vec3(0.0f), glm::vec3(1e30f, 0.0f, 0.0f), glm::vec3(0.0f)};
  saveCageAnimation(c, dir + "/far.cage");
  std::string e = errorOf([&] { loadCageAnimation(dir + "/far.cage", 1 << 20); });
  EXPECT_NE(e.find("frame 0, vertex 1"), std::string::npos) << e;
  EXPECT_NE(e.find("1e+30"), std::string::npos) << e;
  c.positions[1] = glm::vec3(-kMaxCoordinate, kMaxCoordinate, 0.0f);  // at the bound: fine
  saveCageAnimation(c, dir + "/edge.cage");
  EXPECT_EQ(errorOf([&] { loadCageAnimation(dir + "/edge.cage", 1 << 20); }), "");
  json g = tinyGroom();
  g["layers"][1][4] = 2e6;
  writeBytes(dir + "/g.json", g.dump());
  e = errorOf([&] { loadHairMesh(dir + "/g.json"); });
  EXPECT_NE(e.find("layer 1 vertex 1"), std::string::npos) << e;
  EXPECT_NE(e.find("1e6"), std::string::npos) << e;
}

// ---- limits ---------------------------------------------------------------------------------

TEST(Limits, BundleStrandsCheckedWhenTheFileIsRead) {
  const std::string dir = scratchDir();
  json g = tinyGroom();
  g["strands"] = 5000000;
  writeBytes(dir + "/five_million.json", g.dump());
  const std::string e = errorOf([&] { loadHairMesh(dir + "/five_million.json"); });
  EXPECT_NE(e.find("five_million.json: strands is 5000000: bundle "), std::string::npos) << e;
  EXPECT_NE(e.find("at most 65536"), std::string::npos) << e;
  // the count the message offers fits
  std::smatch m;
  ASSERT_TRUE(std::regex_search(e, m, std::regex("ask for at most ([0-9]+) strands"))) << e;
  g["strands"] = std::stoll(m[1].str());
  writeBytes(dir + "/fits.json", g.dump());
  const HairMesh fits = loadHairMesh(dir + "/fits.json");
  std::uint32_t most = 0;
  for (std::uint32_t c : bundleStrandCounts(fits)) most = std::max(most, c);
  EXPECT_LE(most, kMaxBundleStrands);
  EXPECT_GT(most, kMaxBundleStrands - 8u) << "the offered count is not the largest that fits";
  // the scene's per-instance override is checked the same way, naming the entry
  writeBytes(
      dir + "/scene.json",
      sceneWith({{"file", assetPath("grooms/tiny.hairmesh.json")}, {"strands", 5000000}}).dump());
  const std::string o = errorOf([&] { loadScene(dir + "/scene.json"); });
  EXPECT_NE(o.find("grooms[0]"), std::string::npos) << o;
  EXPECT_NE(o.find("at most 65536"), std::string::npos) << o;
}

Image gradient(int w, int h) {
  Image img;
  img.width = w;
  img.height = h;
  img.rgba.resize(static_cast<std::size_t>(w) * h * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = img.pixel(x, y);
      p[0] = 0.1f + x * 0.01f;
      p[1] = 0.5f + y * 0.02f;
      p[2] = 2.0f;
      p[3] = 0.5f;
    }
  return img;
}

TEST(Limits, HdrIsWrittenAsRgb) {
  const std::string dir = scratchDir();
  const Image img = gradient(12, 7);
  writeImage(img, dir + "/x.hdr");
  const Image back = readImage(dir + "/x.hdr");
  ASSERT_EQ(back.width, 12);
  ASSERT_EQ(back.height, 7);
  for (std::size_t i = 0; i < img.rgba.size(); ++i) {
    if (i % 4 == 3) {
      EXPECT_EQ(back.rgba[i], 1.0f) << "an RGB file reads back opaque";
      continue;
    }
    // RGBE: 8-bit mantissas under the pixel's largest channel's exponent, one step of it
    const std::size_t p = i / 4 * 4;
    const float largest = std::max({img.rgba[p], img.rgba[p + 1], img.rgba[p + 2]});
    EXPECT_NEAR(back.rgba[i], img.rgba[i], largest / 64.0f) << i;
  }
  // the command too, before the render's output is thrown away
  writeBytes(dir + "/scene.json",
             sceneWith({{"file", assetPath("grooms/tiny.hairmesh.json")}}).dump());
  const CommandResult r =
      runCli("render " + quote(dir + "/scene.json") + " -q -o " + quote(dir + "/frame.hdr"));
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(readImage(dir + "/frame.hdr").width, 40);
}

TEST(Limits, LongestFileNamesAreWritten) {
  const std::string dir = scratchDir();
  for (const std::size_t length : {254u, 255u}) {
    const std::string name = std::string(length - 4, 'n') + ".png";
    writeImage(gradient(5, 4), dir + "/" + name);
    EXPECT_EQ(readImage(dir + "/" + name).width, 5);
    EXPECT_TRUE(temporariesIn(dir).empty());
  }
}

long maxResidentKiB() {
  struct rusage u {};
  ::getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

std::string pngChunk(const std::string& type, const std::string& data);

// A header that declares far more pixels than the file holds is refused before the pixels are
// allocated: the peak memory of this process grows by less than 64 MiB (the 16384^2 image
// would need 4 GiB as float RGBA).
TEST(Limits, ImageHeaderBeyondItsFileRefusedBeforeAllocating) {
  const std::string dir = scratchDir();
  // a 16384 x 16384 RGBA PNG header with one row of data (made by writing a one-row image and
  // patching its height, CRC included)
  Image row;
  row.width = 16384;
  row.height = 1;
  row.rgba.assign(16384 * 4, 0.5f);
  writeImage(row, dir + "/row.png");
  std::string png = readBytes(dir + "/row.png");
  ASSERT_EQ(png.substr(12, 4), "IHDR");
  png[20] = 0;
  png[21] = 0;
  png[22] = 0x40;  // height 16384
  png[23] = 0;
  png.replace(8, 25, pngChunk("IHDR", png.substr(16, 13)));
  writeBytes(dir + "/huge.png", png);
  // a BMP header of 16384 x 16384 x 24 bits with no pixel data
  std::string bmp = "BM";
  auto u32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) bmp += static_cast<char>(v >> (8 * i) & 0xFF);
  };
  auto u16 = [&](std::uint16_t v) {
    for (int i = 0; i < 2; ++i) bmp += static_cast<char>(v >> (8 * i) & 0xFF);
  };
  u32(54 + 16384u * 16384u * 3u);
  u32(0);
  u32(54);
  u32(40);
  u32(16384);
  u32(16384);
  u16(1);
  u16(24);
  u32(0);
  u32(16384u * 16384u * 3u);
  u32(2835);
  u32(2835);
  u32(0);
  u32(0);
  bmp += std::string(4096, '\x7f');
  writeBytes(dir + "/huge.bmp", bmp);

  const long before = maxResidentKiB();
  const std::string e1 = errorOf([&] { readImage(dir + "/huge.png"); });
  EXPECT_NE(e1.find("huge.png"), std::string::npos) << e1;
  EXPECT_NE(e1.find("16384x16384"), std::string::npos) << e1;
  const std::string e2 = errorOf([&] { readImage(dir + "/huge.bmp"); });
  EXPECT_NE(e2.find("huge.bmp"), std::string::npos) << e2;
  EXPECT_NE(e2.find("16384x16384"), std::string::npos) << e2;
  EXPECT_LT(maxResidentKiB() - before, 64 * 1024) << "KiB of peak memory grew";
}

// CRC-32 (PNG's polynomial) framing of one chunk.
std::string pngChunk(const std::string& type, const std::string& data) {
  std::uint32_t table[256];
  for (std::uint32_t n = 0; n < 256; ++n) {
    std::uint32_t c = n;
    for (int k = 0; k < 8; ++k) c = c & 1 ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    table[n] = c;
  }
  std::uint32_t crc = 0xFFFFFFFFu;
  for (unsigned char b : type + data) crc = table[(crc ^ b) & 0xFF] ^ (crc >> 8);
  crc ^= 0xFFFFFFFFu;
  std::string out;
  for (std::uint32_t v : {static_cast<std::uint32_t>(data.size())})
    for (int i = 3; i >= 0; --i) out += static_cast<char>(v >> (8 * i) & 0xFF);
  out += type + data;
  for (int i = 3; i >= 0; --i) out += static_cast<char>(crc >> (8 * i) & 0xFF);
  return out;
}

// ---- one line ----------------------------------------------------------------------------

// The log file a line names ("details in PATH"), read; "" when the line names none.
std::string detailsOf(const std::string& line) {
  std::smatch m;
  if (!std::regex_search(line, m, std::regex("details in ([^ )]+)"))) return {};
  const std::string text = readBytes(m[1].str());
  fs::remove(m[1].str());
  return text;
}

TEST(OneLine, DeviceSelection) {
  const std::string dir = scratchDir();
  const std::string devices = runCli("devices").output;
  const std::string firstName =
      devices.substr(devices.find("  ") + 2, devices.find('\n') - devices.find("  ") - 2);
  for (const std::string sel : {"9:9", "0:9", "no-such-device-name", "-1:0"}) {
    SCOPED_TRACE(sel);
    const CommandResult r =
        runCli("--device " + quote(sel) + " render " + quote(assetPath("scenes/default.json")) +
               " -o " + quote(dir + "/x.png"));
    expectRefused(r, {"\"" + sel + "\"", "clhair devices"}, dir + "/x.png");
    const std::string details = detailsOf(onlyErrorLine(r.output));
    EXPECT_NE(details.find(firstName), std::string::npos)
        << "the log the line names lists the devices:\n"
        << details;
  }
  // --verbose: the list follows the line instead
  const CommandResult w =
      runCli("--verbose --device 9:9 render " + quote(assetPath("scenes/default.json")) + " -o " +
             quote(dir + "/x.png"));
  EXPECT_EQ(w.exitCode, 1);
  EXPECT_EQ(w.output.rfind("clhair: error:", 0), 0u) << w.output;
  EXPECT_NE(w.output.find(firstName), std::string::npos) << w.output;
}

TEST(OneLine, KernelBuildFailure) {
  const std::string dir = scratchDir();
  fs::create_directories(dir + "/tree");
  fs::copy(sourceDir() + "/kernels", dir + "/tree/kernels", fs::copy_options::recursive);
  {
    std::ofstream shade(dir + "/tree/kernels/shade.cl", std::ios::app);
    shade << "\nthis is not OpenCL C;\n";
  }
  writeBytes(dir + "/scene.json",
             sceneWith({{"file", assetPath("grooms/tiny.hairmesh.json")}}).dump());
  const CommandResult r =
      runCommand("env CLHAIR_CACHE_DIR=" + quote(dir + "/cache") + " " + quote(cliPath()) +
                 " --kernel-dir " + quote(dir + "/tree") + " render " + quote(dir + "/scene.json") +
                 " -q -o " + quote(dir + "/x.png"));
  expectRefused(r, {"shade.cl", "CL_BUILD_PROGRAM_FAILURE", "details in"}, dir + "/x.png");
  const std::string details = detailsOf(onlyErrorLine(r.output));
  EXPECT_NE(details.find("--- build log ---"), std::string::npos) << details;
  EXPECT_NE(details.find("shade.cl"), std::string::npos) << details;
}

TEST(OneLine, DamagedImagesAsBackgroundAndEnvironment) {
  const std::string dir = scratchDir();
  Image env = gradient(64, 32);
  for (const std::string ext : {".png", ".exr"}) {
    writeImage(env, dir + "/good" + ext);
    std::string bytes = readBytes(dir + "/good" + ext);
    for (std::size_t i = bytes.size() / 2; i < bytes.size() / 2 + 64 && i < bytes.size(); ++i)
      bytes[i] = 'Z';
    writeBytes(dir + "/bad" + ext, bytes);
    for (const std::string slot : {"background", "environment"}) {
      SCOPED_TRACE(slot + " " + ext);
      json s = sceneWith({{"file", assetPath("grooms/tiny.hairmesh.json")}});
      if (slot == "background")
        s["background_image"] = "bad" + ext;
      else
        s["environment"] = {{"file", "bad" + ext}};
      writeBytes(dir + "/scene.json", s.dump());
      expectRefused(
          runCli("render " + quote(dir + "/scene.json") + " -q -o " + quote(dir + "/x.png")),
          {"bad" + ext}, dir + "/x.png");
    }
  }
}

}  // namespace
}  // namespace clhair::test
