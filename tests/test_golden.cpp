// test_golden.cpp — end-to-end images against the goldens of tests/golden/: each image of
// tests/golden/goldens.txt is rendered again by the `clhair` CLI, with the same scene and
// options, and compared with the stored file under the tolerance stated below
// (image_assert.h: largest channel difference, share of pixels over a threshold, RMSE, mean
// difference per channel). The goldens come from PoCL (tests/golden/device.txt) and change
// only through `cmake --build build --target update_goldens`, in a commit of their own.
//
// Every tolerance must also see a uniform error: the golden with its linear colour scaled by
// 0.97 (a light 3 % too dim) is checked to fall outside it, without rendering.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "image_assert.h"
#include "test_util.h"

namespace clhair::test {
namespace {

namespace fs = std::filesystem;

struct ManifestLine {
  std::string file, scene, options;
};

std::string goldenDir() { return sourceDir() + "/tests/golden"; }

std::vector<ManifestLine> readManifest() {
  std::ifstream in(goldenDir() + "/goldens.txt");
  EXPECT_TRUE(in) << goldenDir() << "/goldens.txt is missing";
  std::vector<ManifestLine> out;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    ManifestLine m;
    if (!(words >> m.file) || m.file[0] == '#') continue;
    words >> m.scene;
    std::string w;
    while (words >> w) m.options += " " + w;
    out.push_back(m);
  }
  return out;
}

struct Golden {
  const char* file;
  ImageTolerance tolerance;
};

// Tolerance, in display values (image_assert.h: sRGB codes / 255; an EXR's linear values
// through the sRGB curve). The goldens' own variation: PoCL renders them bit-identical with
// 1, 2 or 3 threads (float frames: Render.ThreadCountsGiveBitIdenticalFloatFrames; these
// files: compared too). Intel's CPU runtime (its own compiler, division, sqrt and exp)
// differed from them in at most 3 pixels by more than one code and by at most 3/255, with
// mean differences of 3e-7. A runtime may also move one strand's hit by a rounding, which
// changes a few pixels wholly (hair for background). So:
//   - a pixel differs when a channel moves by more than one 8-bit code (1.5/255, so that a
//     rounding of the last code passes; a half float's step is far below a code);
//   - up to 0.2 % of the pixels (74 of a 256 x 144 image) may differ, each by up to 0.5:
//     room for a few flipped strands of 10 to 40 pixels each;
//   - RMSE up to sqrt(0.002) x 0.5 = 0.022, all of that at once;
//   - the mean difference of a channel within 0.001, a quarter of a code, the most those
//     pixels can move it (0.002 x 0.5): a light 3 % too dim over the whole image moves it
//     by 0.0035 or more in these images (each test prints its figure).
constexpr ImageTolerance kTolerance{0.5, 1.5 / 255.0, 0.002, 0.022, 0.001};

const Golden kGoldens[] = {
    {"hair_mesh_shadows.png", kTolerance},       // hair mesh, deep opacity shadows, sphere
    {"strand_file_head.png", kTolerance},        // .hair strand file, OBJ head mesh, shadows
    {"strand_file_head_msaa4.exr", kTolerance},  // the same with MSAA 4, half-float EXR
    {"environment_sky.exr", kTolerance},         // sky environment lighting, visible sky
    {"fur_filter_off.png", kTolerance},          // fur, ground plane, point light, no filter
};

// The golden with its linear colour times `scale`, stored again as the file stores it.
StoredImage scaled(const StoredImage& s, double scale) {
  StoredImage out = s;
  for (std::size_t i = 0; i < out.values.rgba.size(); ++i) {
    if (i % 4 == 3) continue;
    const double v = out.values.rgba[i];
    out.values.rgba[i] = static_cast<float>(
        s.encoding == ImageEncoding::Srgb8
            ? std::lround(srgbEncode(std::min(1.0, srgbDecode(v) * scale)) * 255.0) / 255.0
            : v * scale);
  }
  return out;
}

void PrintTo(const Golden& g, std::ostream* os) { *os << g.file; }

class GoldenImage : public ::testing::TestWithParam<Golden> {};

TEST_P(GoldenImage, CliRendersIt) {
  const Golden& g = GetParam();
  const std::vector<ManifestLine> manifest = readManifest();
  const ManifestLine* line = nullptr;
  for (const ManifestLine& m : manifest)
    if (m.file == g.file) line = &m;
  ASSERT_NE(line, nullptr) << g.file << " is not in tests/golden/goldens.txt";
  const std::string goldenPath = goldenDir() + "/" + g.file;
  ASSERT_TRUE(fs::exists(goldenPath))
      << goldenPath << " is missing: cmake --build build --target update_goldens";
  const StoredImage golden = readStoredImage(goldenPath);

  // the tolerance sees a uniform 3 % error
  const ImageDifference dim =
      measureDifference(golden, scaled(golden, 0.97), g.tolerance.pixelThreshold);
  EXPECT_FALSE(toleranceViolations(dim, g.tolerance).empty())
      << "the tolerance of " << g.file << " accepts the golden 3 % darker: " << describe(dim);
  std::printf("[ golden   ] %s 3 %% darker: %s\n", g.file, describe(dim).c_str());

  const std::string out = scratchDir() + "/" + g.file;
  const CommandResult r = runCli("render " + quote(sourceDir() + "/" + line->scene) + " -o " +
                                 quote(out) + line->options + " --quiet");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const StoredImage actual = readStoredImage(out);
  const ImageDifference d = measureDifference(golden, actual, g.tolerance.pixelThreshold);
  RecordProperty("difference", describe(d));
  std::printf("[ golden   ] %s: %s\n", g.file, describe(d).c_str());
  EXPECT_IMAGES_NEAR(golden, actual, g.tolerance);
}

INSTANTIATE_TEST_SUITE_P(Goldens, GoldenImage, ::testing::ValuesIn(kGoldens),
                         [](const ::testing::TestParamInfo<Golden>& info) {
                           std::string name = info.param.file;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

// Every image of the manifest has a test (and so a tolerance), and every test an image.
TEST(GoldenManifest, ListsExactlyTheTestedImages) {
  std::vector<std::string> listed, tested;
  for (const ManifestLine& m : readManifest()) listed.push_back(m.file);
  for (const Golden& g : kGoldens) tested.push_back(g.file);
  std::sort(listed.begin(), listed.end());
  std::sort(tested.begin(), tested.end());
  EXPECT_EQ(listed, tested);
  for (const std::string& f : listed) EXPECT_TRUE(fs::exists(goldenDir() + "/" + f)) << f;
}

}  // namespace
}  // namespace clhair::test
