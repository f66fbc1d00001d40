// test_fit_units.cpp — `clhair fit-mesh --scale`: a file in centimetres fitted with
// --scale 0.01 reports its distances and fibre width in metres, the same as the file in
// metres (and --scale auto the same as the number that puts its roots at 0.18 m); a fibre
// width or a scale out of range is one error line and no output.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "fit_groom.h"
#include "io/cyhair.h"
#include "test_util.h"

namespace clhair {
namespace {

// The patch's strands (0.1 m across) written in file units of `unit` metres.
void writePatch(const std::string& path, float unit) {
  test::PatchShape shape;
  shape.cells = 4;
  HairMesh mesh = test::patchMesh(shape);
  mesh.strandCount = 1500;  // enough for 8 bundles, quick to fit
  const StrandGroom g = test::strandsOf(mesh);
  CyHair h;
  for (std::uint32_t c : g.pointCounts) h.segments.push_back(c - 1);
  for (const glm::vec3& p : g.points)
    h.points.insert(h.points.end(), {p.x / unit, p.y / unit, p.z / unit});
  h.defaultThickness = 7e-5f / unit;
  writeCyHair(h, path);
}

nlohmann::json fit(const std::string& dir, const std::string& file, const std::string& flags) {
  const auto r = test::runCli("fit-mesh " + test::quote(dir + "/" + file) + " -o " +
                              test::quote(dir + "/fit.json") +
                              " --bundles 8 --layers 3 --error-sample 200 --report " +
                              test::quote(dir + "/r.json") + " " + flags);
  EXPECT_EQ(r.exitCode, 0) << r.output;
  std::ifstream in(dir + "/r.json");
  return nlohmann::json::parse(in);
}

TEST(FitUnits, ACentimetreFileWithItsScaleReportsMetres) {
  const std::string dir = test::scratchDir();
  writePatch(dir + "/m.hair", 1.0f);
  writePatch(dir + "/cm.hair", 0.01f);
  const nlohmann::json m = fit(dir, "m.hair", "");
  const nlohmann::json cm = fit(dir, "cm.hair", "--scale 0.01");
  const double mean = m["error"]["mean_m"].get<double>();
  ASSERT_GT(mean, 0.0);
  EXPECT_NEAR(cm["error"]["mean_m"].get<double>(), mean, 0.05 * mean) << "metres, not cm";
  EXPECT_NEAR(cm["fibre_width_m"].get<double>(), 7e-5, 1e-7);
  // without --scale the same file reports centimetres: the flag is what changes it
  const nlohmann::json raw = fit(dir, "cm.hair", "");
  EXPECT_GT(raw["error"]["mean_m"].get<double>(), 20.0 * mean);
}

// No generated strand is longer than the longest input strand by more than 10 %: the
// example head's bob (1200 strands in centimetres, frizzy) generated strands up to 1.31x
// the longest input strand when the layers followed an estimated full length past it.
TEST(FitLengths, NoGeneratedStrandPastTheLongestInputByMoreThanTenPercent) {
  const std::string dir = test::scratchDir();
  std::filesystem::copy_file(test::assetPath("grooms/head_bob.hair"), dir + "/bob.hair");
  writePatch(dir + "/patch.hair", 1.0f);
  for (const auto& [file, flags] :
       {std::pair<std::string, std::string>{"bob.hair", "--scale 0.01"}, {"patch.hair", ""}}) {
    SCOPED_TRACE(file);
    const nlohmann::json r = fit(dir, file, flags);
    const double in = r["length"]["in"]["max_m"].get<double>();
    const double out = r["length"]["out"]["max_m"].get<double>();
    ASSERT_GT(in, 0.0);
    EXPECT_LE(out, 1.1 * in);
    EXPECT_GE(r["length"]["out"]["median_m"].get<double>(),
              0.9 * r["length"]["in"]["median_m"].get<double>());
  }
}

TEST(FitUnits, BadScaleOrFibreWidthIsOneErrorLine) {
  const std::string dir = test::scratchDir();
  writePatch(dir + "/cm.hair", 0.01f);
  const struct {
    const char* flags;
    const char* says;
  } cases[] = {{"--scale 0.01 --fibre-width 0.007", "metres"},
               {"--scale centimetres", "--scale"},
               {"--scale=-1", "--scale"}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.flags);
    const auto r = test::runCli("fit-mesh " + test::quote(dir + "/cm.hair") + " -o " +
                                test::quote(dir + "/out.json") + " " + c.flags);
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(test::onlyErrorLine(r.output).find(c.says), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir + "/out.json"));
  }
}

}  // namespace
}  // namespace clhair
