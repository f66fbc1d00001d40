// test_explicit_look.cpp — how strand files look through the command line: preset framing
// that ignores an outlier vertex, grooms in the wrong units warned about, file colours and
// thicknesses drawn unless the scene gives its own, and frames identical with any thread
// count. Reading and refusing files: test_explicit_files.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clhair/renderer.h"
#include "clhair/strand_groom.h"
#include "float_frames.h"
#include "groom/presets.h"
#include "io/cyhair.h"
#include "synthetic_groom.h"
#include "test_util.h"

namespace clhair {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::countOf;
using test::writeBytes;

// Pixels that are not the background colour.
double hairFraction(const Image& img, glm::vec3 background) {
  std::size_t n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const float* p = img.pixel(x, y);
      n += std::fabs(p[0] - background.x) + std::fabs(p[1] - background.y) +
               std::fabs(p[2] - background.z) >
           0.03f;
    }
  return static_cast<double>(n) / (static_cast<double>(img.width) * img.height);
}

// One finite but absurd vertex (x = 1e30) must not make a camera preset frame it: the hair
// is framed as without it, and one warning names the strand.
TEST(ExplicitCli, PresetFramingIgnoresAnOutlierVertexAndNamesItsStrand) {
  const std::string dir = test::scratchDir();
  Renderer r(test::sharedDevice());
  HairMesh mesh = makeGroomPreset("tiny");
  mesh.strandCount = 300;
  CyHair h = test::toCyHair(r.generateStrands(mesh), mesh.appearance.strandWidth);
  writeCyHair(h, dir + "/clean.hair");
  // strand 7's third point
  std::size_t first = 0;
  for (std::size_t s = 0; s < 7; ++s) first += h.segments[s] + 1;
  h.points[3 * (first + 2)] = 1e30f;
  writeCyHair(h, dir + "/outlier.hair");
  const glm::vec3 background(0.0f, 0.0f, 1.0f);
  auto render = [&](const std::string& file) {
    json s = {{"resolution", {96, 64}},
              {"background", {background.x, background.y, background.z}},
              {"camera", {{"preset", "close"}, {"azimuth", 30}}},
              {"lights", {{{"type", "directional"}, {"direction", {0.4, 0.8, 0.5}}}}},
              {"grooms", {{{"strands_file", file}}}}};
    writeBytes(dir + "/" + file + ".json", s.dump());
    const std::string out = dir + "/" + file + ".png";
    test::CommandResult c = test::runCli("render " + test::quote(dir + "/" + file + ".json") +
                                         " -o " + test::quote(out));
    EXPECT_EQ(c.exitCode, 0) << c.output;
    return std::make_pair(c.output, readImage(out));
  };
  const auto clean = render("clean.hair");
  const auto bad = render("outlier.hair");
  EXPECT_EQ(countOf(clean.first, "clhair: warning:"), 0u) << clean.first;
  const double cleanHair = hairFraction(clean.second, background),
               badHair = hairFraction(bad.second, background);
  ASSERT_GT(cleanHair, 0.05) << "the clean groom hardly shows; see " << dir;
  EXPECT_GT(badHair, 0.5 * cleanHair) << "the outlier took over the framing; see " << dir;
  ASSERT_EQ(countOf(bad.first, "clhair: warning:"), 1u) << bad.first;
  const std::size_t begin = bad.first.find("clhair: warning:");
  const std::string line = bad.first.substr(begin, bad.first.find('\n', begin) - begin);
  EXPECT_NE(line.find("strand 7 "), std::string::npos) << line;
  EXPECT_NE(line.find("1e+30"), std::string::npos) << line;
}

// A file in centimetres without "scale" draws fibres ~100 times too thin for its size; the
// CLI says so once and suggests "scale". The same file with "scale": 0.01, and the metre
// file even at the far preset on a small image, give no warning; a groom seen from so far
// that it covers less than a pixel does.
TEST(ExplicitCli, WarnsAboutGroomsInTheWrongUnits) {
  const std::string dir = test::scratchDir();
  Renderer r(test::sharedDevice());
  HairMesh mesh = makeGroomPreset("tiny");
  mesh.strandCount = 300;
  CyHair h = test::toCyHair(r.generateStrands(mesh), mesh.appearance.strandWidth);
  writeCyHair(h, dir + "/metres.hair");
  for (float& v : h.points) v *= 100.0f;
  writeCyHair(h, dir + "/cm.hair");
  auto render = [&](const std::string& name, json groom, json camera) {
    json s = {{"resolution", {96, 64}}, {"camera", camera}, {"grooms", {groom}}};
    writeBytes(dir + "/" + name + ".json", s.dump());
    test::CommandResult c = test::runCli("render " + test::quote(dir + "/" + name + ".json") +
                                         " -o " + test::quote(dir + "/" + name + ".png"));
    EXPECT_EQ(c.exitCode, 0) << c.output;
    return c.output;
  };
  const json close = {{"preset", "close"}};
  const std::string cm = render("cm", {{"strands_file", "cm.hair"}}, close);
  ASSERT_EQ(countOf(cm, "clhair: warning:"), 1u) << cm;
  const std::size_t begin = cm.find("clhair: warning:");
  const std::string line = cm.substr(begin, cm.find('\n', begin) - begin);
  for (const char* f : {"cm.json", "grooms[0]", "\"cm\"", "\"scale\"", "pixels wide"})
    EXPECT_NE(line.find(f), std::string::npos) << "missing " << f << ": " << line;

  const std::string scaled =
      render("scaled", {{"strands_file", "cm.hair"}, {"scale", 0.01}}, close);
  EXPECT_EQ(countOf(scaled, "clhair: warning:"), 0u) << scaled;
  const std::string far = render("far", {{"strands_file", "metres.hair"}}, {{"preset", "far"}});
  EXPECT_EQ(countOf(far, "clhair: warning:"), 0u) << far;
  const std::string tiny = render("tiny", {{"strands_file", "metres.hair"}},
                                  {{"position", {0.0, 0.0, 200.0}}, {"target", {0.0, 0.0, 0.0}}});
  ASSERT_EQ(countOf(tiny, "clhair: warning:"), 1u) << tiny;
  EXPECT_NE(tiny.find("pixels of the 96x64 image"), std::string::npos) << tiny;
}

// cyHair per-point colours and thicknesses: drawn by default; a scene appearance key of the
// same kind (a colour key, strand_width) or "use_file_color": false draws the scene's, without
// a warning. Colours: the root half of every strand blue, the tip half green (the
// groom's own brown melanin makes red the strongest channel), so blue- and green-dominated
// hair pixels both appear only when colour reaches the shading per point. Thickness: ten
// times the default width covers clearly more pixel centers than the default width.
TEST(ExplicitCli, FileColoursAndThicknessesAreDrawnUnlessTheSceneGivesItsOwn) {
  const std::string dir = test::scratchDir();
  Renderer r(test::sharedDevice());
  HairMesh mesh = makeGroomPreset("tiny");
  mesh.strandCount = 300;
  CyHair h = test::toCyHair(r.generateStrands(mesh), mesh.appearance.strandWidth);
  for (std::uint32_t seg : h.segments)
    for (std::uint32_t k = 0; k <= seg; ++k) {
      const bool root = 2 * k < seg;
      h.colors.insert(h.colors.end(), {0.02f, root ? 0.02f : 0.6f, root ? 0.6f : 0.02f});
    }
  writeCyHair(h, dir + "/colour.hair");
  h.thickness.assign(h.points.size() / 3, mesh.appearance.strandWidth);
  writeCyHair(h, dir + "/thin.hair");
  h.thickness.assign(h.points.size() / 3, 10.0f * mesh.appearance.strandWidth);
  writeCyHair(h, dir + "/thick.hair");

  struct Result {
    std::string output;
    double hair = 0.0, blue = 0.0, green = 0.0, red = 0.0;  // fractions of the image
  };
  auto render = [&](const std::string& name, const std::string& file, const json& appearance,
                    const std::string& options = "") {
    json groom = {{"strands_file", file}};
    if (!appearance.is_null()) groom["appearance"] = appearance;
    json s = {
        {"resolution", {96, 64}},
        {"background", {0.0, 0.0, 0.0}},
        // enough ambient light that the hair away from the light is above the cut-off below
        // (TT under ambient light is darkened by the groom behind, shade.cl)
        {"ambient", {0.15, 0.15, 0.15}},
        {"camera", {{"preset", "close"}, {"azimuth", 30}}},
        {"lights", {{{"type", "directional"}, {"direction", {0.4, 0.8, 0.5}}, {"intensity", 3}}}},
        {"grooms", {groom}}};
    writeBytes(dir + "/" + name + ".json", s.dump());
    const std::string out = dir + "/" + name + ".png";
    test::CommandResult c = test::runCli("render " + test::quote(dir + "/" + name + ".json") +
                                         " -o " + test::quote(out) + options);
    EXPECT_EQ(c.exitCode, 0) << c.output;
    Result res;
    res.output = c.output;
    const Image img = readImage(out);
    const double n = static_cast<double>(img.width) * img.height;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const float* p = img.pixel(x, y);
        if (p[0] + p[1] + p[2] < 0.03f) continue;
        res.hair += 1.0 / n;
        if (p[2] > 1.5f * p[0] && p[2] > 1.5f * p[1]) res.blue += 1.0 / n;
        if (p[1] > 1.5f * p[0] && p[1] > 1.5f * p[2]) res.green += 1.0 / n;
        if (p[0] > 1.5f * p[1] && p[0] > 1.5f * p[2]) res.red += 1.0 / n;
      }
    return res;
  };
  // Lipp's filter, as these fractions were set for: Huang's (the default) gives sub-pixel
  // strands their fractional coverage, which leaves fewer pixels above the cut-off
  const json melanin = {{"eumelanin", {1.3, 1.0}}, {"pheomelanin", {0.1, 0.1}}};
  const Result ignored = render("ignored", "colour.hair", melanin, " --filter lipp");
  const Result off = render("off", "colour.hair", {{"use_file_color", false}}, " --filter lipp");
  const Result used = render("used", "colour.hair", json(), " --filter lipp");
  ASSERT_GT(ignored.hair, 0.05) << "see " << dir;
  for (const Result* r : {&ignored, &off}) {
    EXPECT_EQ(countOf(r->output, "clhair: warning:"), 0u) << r->output;
    EXPECT_EQ(r->blue + r->green, 0.0) << "the groom's brown drew blue or green; see " << dir;
    EXPECT_GT(r->red, 0.2 * r->hair);
  }

  EXPECT_EQ(countOf(used.output, "clhair: warning:"), 0u) << used.output;
  EXPECT_EQ(used.red, 0.0) << "see " << dir;
  EXPECT_GT(used.blue, 0.1 * used.hair) << "no blue roots; see " << dir;
  EXPECT_GT(used.green, 0.1 * used.hair) << "no green tips; see " << dir;

  // without the filter a pixel shows hair only where a fibre covers its center, so the
  // covered fraction grows with the fibres' width. AO off: thicker fibres also occlude more
  // of the ambient light (the strand file's AO field), which would take pixels under the
  // brightness cut-off that counts them
  const Result thin = render("thin", "thin.hair", json(), " --filter off --ao off");
  const Result thick = render("thick", "thick.hair", json(), " --filter off --ao off");
  EXPECT_GT(thick.hair, 1.5 * thin.hair) << "file thickness not drawn; see " << dir;
  const Result thickIgnored =
      render("thick_ignored", "thick.hair", {{"strand_width", mesh.appearance.strandWidth}},
             " --filter off --ao off");
  EXPECT_EQ(countOf(thickIgnored.output, "clhair: warning:"), 0u) << thickIgnored.output;
  EXPECT_LT(thickIgnored.hair, 1.2 * thin.hair)
      << "thickness drawn although not asked for; see " << dir;
}

// Bit-identical float frames of a strand file (LOD on, a shadowed light) with 1, 2 and 3 CPU
// threads, on every device whose thread count can be set (float_frames.h).
TEST(ExplicitCli, RendersAStrandFileIdenticallyWithAnyThreadCount) {
  const std::string dir = test::scratchDir();
  Renderer r(test::sharedDevice());
  HairMesh mesh = makeGroomPreset("tiny");
  mesh.strandCount = 2000;  // dense: strands of concurrent work-groups meet in many pixels
  writeCyHair(test::toCyHair(r.generateStrands(mesh), mesh.appearance.strandWidth),
              dir + "/tiny.hair");
  json s = {
      {"resolution", {96, 64}},
      {"camera", {{"preset", "close"}, {"azimuth", 30}}},
      {"lights", {{{"type", "directional"}, {"direction", {0.4, 0.8, 0.5}}, {"shadows", true}}}},
      {"shadows", {{"resolution", 32}}},
      {"grooms", {{{"strands_file", "tiny.hair"}, {"lod", {{"enabled", true}}}}}}};
  writeBytes(dir + "/scene.json", s.dump());
  test::expectBitIdenticalAcrossThreadCounts(dir + "/scene.json", dir);
}

}  // namespace
}  // namespace clhair
