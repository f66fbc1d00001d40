// test_refusals_outputs.cpp — inputs are never outputs, and every output is checked before
// any work: each command that writes refuses an output that is one of its inputs (named
// directly, through a symbolic link, through "..", or as a hard link) and every side output
// it cannot write (a missing folder, a folder in its place, an extension its writer does not
// make), with one error line, exit 1, and every existing file byte-identical — including the
// main output when only a side output is wrong (fit-mesh --report).
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "clhair/image.h"
#include "io/cyhair.h"
#include "test_util.h"

namespace clhair::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

std::size_t lineCount(const std::string& text) {
  std::size_t n = 0;
  for (char c : text) n += c == '\n';
  return n + (!text.empty() && text.back() != '\n');
}

// A refused command: exit 1, one line, the error line holding every fragment.
void expectRefused(const CommandResult& r, const std::vector<std::string>& fragments) {
  SCOPED_TRACE("output was:\n" + r.output);
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_EQ(lineCount(r.output), 1u);
  const std::string line = onlyErrorLine(r.output);
  for (const std::string& f : fragments)
    EXPECT_NE(line.find(f), std::string::npos) << "the line lacks \"" << f << "\"";
}

// 61 straight strands of 9 points on a 0.01 m grid around the origin, as a cyHair file.
void writeStrands(const std::string& path) {
  CyHair h;
  for (int i = 0; i < 61; ++i) {
    const float x = 0.01f * static_cast<float>(i % 8 - 4),
                z = 0.01f * static_cast<float>(i / 8 - 4);
    h.segments.push_back(8);
    for (int k = 0; k < 9; ++k) h.points.insert(h.points.end(), {x, 0.01f * k, z + 0.002f * k});
  }
  h.defaultThickness = 7e-5f;
  writeCyHair(h, path);
}

// Every file of `dir` with its bytes.
std::vector<std::pair<std::string, std::string>> snapshot(const std::string& dir) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (fs::is_regular_file(fs::symlink_status(e.path())))
      out.push_back({e.path().string(), readAll(e.path().string())});
  std::sort(out.begin(), out.end());
  return out;
}

TEST(InputsNeverOutputs, FitMeshNeverWritesOverItsInputs) {
  const std::string dir = scratchDir();
  writeStrands(dir + "/groom.hair");
  fs::create_directories(dir + "/sub");
  fs::create_symlink(dir + "/groom.hair", dir + "/link.json");
  fs::create_hard_link(dir + "/groom.hair", dir + "/hard.json");
  writeText(dir + "/look.json", "{}");
  const auto before = snapshot(dir);
  const std::string g = quote(dir + "/groom.hair");
  // the case, then through "..", a symbolic link and a hard link
  for (const std::string& out :
       {dir + "/groom.hair", dir + "/sub/../groom.hair", dir + "/link.json", dir + "/hard.json"}) {
    SCOPED_TRACE(out);
    expectRefused(runCli("fit-mesh " + g + " -o " + quote(out)), {"-o", "the strand file"});
  }
  // the other inputs and the report
  expectRefused(runCli("fit-mesh " + g + " --appearance " + quote(dir + "/look.json") + " -o " +
                       quote(dir + "/look.json")),
                {"the appearance file"});
  expectRefused(runCli("fit-mesh " + g + " -o " + quote(dir + "/new.json") + " --report " +
                       quote(dir + "/link.json")),
                {"--report", "the strand file"});
  expectRefused(runCli("fit-mesh " + g + " -o " + quote(dir + "/same.json") + " --report " +
                       quote(dir + "/sub/../same.json")),
                {"--report", "also -o"});
  EXPECT_EQ(snapshot(dir), before) << "a file was written or changed";
}

TEST(InputsNeverOutputs, ExportAndBakeNeverWriteOverTheirInputs) {
  const std::string dir = scratchDir();
  writeStrands(dir + "/groom.hair");
  fs::copy_file(assetPath("grooms/tiny.hairmesh.json"), dir + "/tiny.json");
  const auto before = snapshot(dir);
  expectRefused(runCli("export-strands " + quote(dir + "/groom.hair") + " -o " +
                       quote(dir + "/./groom.hair")),
                {"-o", "the groom file"});
  expectRefused(runCli("bake-ao " + quote(dir + "/tiny.json") + " -o " + quote(dir + "/tiny.json")),
                {"-o", "the hair-mesh file"});
  EXPECT_EQ(snapshot(dir), before);
}

// A render refuses -o naming its scene or a file the scene reads (the background image, the
// environment map, a strand file through a link), before drawing anything.
TEST(InputsNeverOutputs, RenderNeverWritesOverTheScenesFiles) {
  const std::string dir = scratchDir();
  writeStrands(dir + "/groom.hair");
  Image img;
  img.width = img.height = 4;
  img.rgba.assign(64, 0.5f);
  writeImage(img, dir + "/bg.png");
  writeImage(img, dir + "/env.exr");
  fs::create_symlink(dir + "/groom.hair", dir + "/strands.png");
  const json scene = {{"resolution", {16, 12}},
                      {"background_image", "bg.png"},
                      {"environment", {{"file", "env.exr"}}},
                      {"grooms", {{{"strands_file", "groom.hair"}}}}};
  writeText(dir + "/scene.json", scene.dump());
  const auto before = snapshot(dir);
  const std::string s = "render " + quote(dir + "/scene.json") + " -q -o ";
  expectRefused(runCli(s + quote(dir + "/bg.png")), {"-o", "a file the scene reads", "bg.png"});
  expectRefused(runCli(s + quote(dir + "/env.exr")), {"-o", "env.exr"});
  expectRefused(runCli(s + quote(dir + "/strands.png")), {"-o", "groom.hair"});
  expectRefused(runCli("bake-visibility " + quote(dir + "/scene.json") + " -o " +
                       quote(dir + "/v.clhvis") + " --transmittance-out " + quote(dir + "/bg.png")),
                {"--transmittance-out", "bg.png"});
  EXPECT_EQ(snapshot(dir), before);
}

// fit-mesh's -o and --report are both checked before the fit: a report in a missing folder or
// naming a folder leaves the existing mesh file as it was; -o x.png is refused (JSON only).
TEST(OutputsChecked, FitMeshSideOutputsBeforeAnyWork) {
  const std::string dir = scratchDir();
  writeStrands(dir + "/groom.hair");
  writeText(dir + "/out.hairmesh.json", "the previous mesh");
  fs::create_directories(dir + "/folder.json");
  const auto before = snapshot(dir);
  const std::string fit =
      "fit-mesh " + quote(dir + "/groom.hair") + " -o " + quote(dir + "/out.hairmesh.json");
  expectRefused(runCli(fit + " --report " + quote(dir + "/missing/rep.json")),
                {"--report", "missing"});
  expectRefused(runCli(fit + " --report " + quote(dir + "/folder.json")), {"--report", "folder"});
  expectRefused(runCli(fit + " --report " + quote(dir + "/rep.txt")), {"--report", ".txt"});
  expectRefused(runCli("fit-mesh " + quote(dir + "/groom.hair") + " -o " + quote(dir + "/x.png")),
                {"-o", ".png", ".json"});
  EXPECT_EQ(snapshot(dir), before);
  // and with every output right, the fit runs and writes both
  const CommandResult ok = runCli(fit + " -q --report " + quote(dir + "/rep.json"));
  ASSERT_EQ(ok.exitCode, 0) << ok.output;
  EXPECT_NE(readAll(dir + "/out.hairmesh.json"), "the previous mesh");
  EXPECT_TRUE(fs::exists(dir + "/rep.json"));
}

}  // namespace
}  // namespace clhair::test
