// test_image_codec.cpp — the command loads the image codec (OpenImageIO and the libraries it
// brings) as a module on its first image, not at start (io/image_codec.h,
// cli/image_codec_loader.cpp).
//
// Which libraries a process loads is read from the dynamic loader's own trace
// (LD_DEBUG=libs, glibc: a "find library=NAME" line per library it looks for, on stderr).
// A command that writes no image (help, the device list) must not look for OpenImageIO, nor
// a render to PNG (libpng writes it: io/png_write.cpp); a render to OpenEXR must. A codec
// module that is missing or is not one is refused with one error line when the first image
// the codec writes is written: nothing is written and the command exits 1, while a PNG is
// still written without it. A broken module beside the command is that error too, not passed
// over for the one the build made.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "test_util.h"

namespace clhair::test {
namespace {

namespace fs = std::filesystem;

const std::string kTinyScene = "/tests/data/oclgrind_tiny.json";  // 48x32, the tiny groom

bool looksForOpenImageIO(const std::string& output) {
  return output.find("find library=libOpenImageIO") != std::string::npos;
}

TEST(ImageCodecCli, OnlyACommandWithImagesLoadsTheCodec) {
  const fs::path dir = testOutputPath();
  fs::remove_all(dir);
  fs::create_directories(dir);
  // without OpenImageIO: help, and a command that writes no image
  CommandResult help = runCommand("LD_DEBUG=libs " + quote(cliPath()) + " --help");
  ASSERT_EQ(help.exitCode, 0) << help.output;
  EXPECT_NE(help.output.find("find library=libOpenCL"), std::string::npos)
      << "LD_DEBUG=libs traces nothing here, so the checks below prove nothing:\n"
      << help.output.substr(0, 2000);
  EXPECT_FALSE(looksForOpenImageIO(help.output)) << help.output.substr(0, 4000);
  CommandResult devices = runCommand("LD_DEBUG=libs " + quote(cliPath()) + " devices");
  ASSERT_EQ(devices.exitCode, 0) << devices.output.substr(0, 4000);
  EXPECT_FALSE(looksForOpenImageIO(devices.output)) << devices.output.substr(0, 4000);
  // a render to PNG does not (libpng writes it); a render to OpenEXR loads it
  const fs::path png = dir / "tiny.png";
  CommandResult toPng =
      runCommand("LD_DEBUG=libs " + quote(cliPath()) + " render " +
                 quote(sourceDir() + kTinyScene) + " -q -o " + quote(png.string()));
  ASSERT_EQ(toPng.exitCode, 0) << toPng.output.substr(0, 4000);
  EXPECT_NE(toPng.output.find("find library=libpng16"), std::string::npos)
      << toPng.output.substr(0, 4000);
  EXPECT_FALSE(looksForOpenImageIO(toPng.output)) << toPng.output.substr(0, 4000);
  EXPECT_GT(fs::file_size(png), 0u);
  const fs::path exr = dir / "tiny.exr";
  CommandResult toExr =
      runCommand("LD_DEBUG=libs " + quote(cliPath()) + " render " +
                 quote(sourceDir() + kTinyScene) + " -q -o " + quote(exr.string()));
  ASSERT_EQ(toExr.exitCode, 0) << toExr.output.substr(0, 4000);
  EXPECT_TRUE(looksForOpenImageIO(toExr.output));
  EXPECT_GT(fs::file_size(exr), 0u);
}

TEST(ImageCodecCli, AMissingOrForeignModuleIsOneLineAndNoImage) {
  const fs::path dir = testOutputPath();
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path notModule = dir / "not-a-module.so";
  std::ofstream(notModule) << "not an ELF file\n";
  const fs::path wrongModule = "/lib/x86_64-linux-gnu/libz.so.1";  // a library, not the codec
  struct Case {
    std::string module, says;
  };
  std::vector<Case> cases = {{(dir / "missing.so").string(), "missing.so"},
                             {notModule.string(), "not-a-module.so"}};
  if (fs::exists(wrongModule)) cases.push_back({wrongModule.string(), "not clhair's image codec"});
  for (const Case& c : cases) {
    const fs::path exr = dir / "out.exr";
    CommandResult r =
        runCommand("CLHAIR_IMAGE_CODEC=" + quote(c.module) + " " + quote(cliPath()) + " render " +
                   quote(sourceDir() + kTinyScene) + " -o " + quote(exr.string()));
    EXPECT_EQ(r.exitCode, 1) << c.module << ":\n" << r.output;
    const std::string line = onlyErrorLine(r.output);
    EXPECT_NE(line.find("cannot load the image codec"), std::string::npos) << line;
    EXPECT_NE(line.find(c.says), std::string::npos) << line;
    EXPECT_FALSE(fs::exists(exr)) << c.module;
  }
  // a PNG needs no module
  const fs::path png = dir / "out.png";
  CommandResult p =
      runCommand("CLHAIR_IMAGE_CODEC=" + quote(cases[0].module) + " " + quote(cliPath()) +
                 " render " + quote(sourceDir() + kTinyScene) + " -q -o " + quote(png.string()));
  EXPECT_EQ(p.exitCode, 0) << p.output;
  EXPECT_TRUE(fs::exists(png));
  // a broken module beside the command is the error, not passed over for the build's own
  const fs::path copy = dir / "copy";
  fs::create_directories(copy);
  fs::copy_file(cliPath(), copy / "clhair", fs::copy_options::overwrite_existing);
  fs::copy_file(notModule, copy / "libclhair_image_codec.so", fs::copy_options::overwrite_existing);
  const fs::path exr = dir / "beside.exr";
  CommandResult r = runCommand(quote((copy / "clhair").string()) + " render " +
                               quote(sourceDir() + kTinyScene) + " -q -o " + quote(exr.string()));
  EXPECT_EQ(r.exitCode, 1) << r.output;
  const std::string line = onlyErrorLine(r.output);
  EXPECT_NE(line.find((copy / "libclhair_image_codec.so").string()), std::string::npos) << line;
  EXPECT_FALSE(fs::exists(exr));
}

}  // namespace
}  // namespace clhair::test
