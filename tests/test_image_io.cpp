// test_image_io.cpp — the image writers and readers (clhair/image.h, host/io/srgb_encode.h).
//
// - The table-driven sRGB encoder gives the byte of the formula (round(255 * srgb(clamp(x))),
//   evaluated in float) for every float tested: a dense sample of [0, 1] (every 61st bit
//   pattern), every float within 64 steps of each of the 255 thresholds, and NaNs, infinities,
//   negatives, subnormals and values above 1. (All 2^32 floats were compared once when the
//   table was written; DESIGN.md.) 8-bit files hold exactly those bytes.
// - PNG compression levels and EXR compressions change the file, never the pixels read back;
//   values outside the lists are refused (the command names the flag, before any work).
// - Writers run from several threads at once on different paths: each file reads back as its
//   own image, each failure names its own path.
// - Reading refuses FIFOs and folders unopened, and a PNG with a damaged chunk, in one line.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>
#include <sys/stat.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "clhair/aov.h"
#include "clhair/image.h"
#include "fault_fs.h"
#include "io/image_file.h"
#include "io/safe_write.h"
#include "io/srgb_encode.h"
#include "test_util.h"

namespace clhair::test {
namespace {

namespace fs = std::filesystem;

float fromBits(std::uint32_t b) {
  float x;
  std::memcpy(&x, &b, sizeof(x));
  return x;
}

std::uint32_t bitsOf(float x) {
  std::uint32_t b;
  std::memcpy(&b, &x, sizeof(b));
  return b;
}

TEST(ImageIo, SrgbTableGivesTheFormulasByteForEveryFloatTested) {
  std::size_t checked = 0, mismatches = 0;
  auto check = [&](float x) {
    ++checked;
    if (srgbByte(x) != srgbByteFormula(x) && ++mismatches <= 10)
      ADD_FAILURE() << "x = " << x << " (bits " << std::hex << bitsOf(x) << std::dec << "): table "
                    << int(srgbByte(x)) << ", formula " << int(srgbByteFormula(x));
  };
  for (std::uint32_t b = 0; b <= 0x3F800000u; b += 61) check(fromBits(b));
  for (int code = 1; code <= 255; ++code) {
    const std::uint32_t t = bitsOf(srgbThreshold(code));
    EXPECT_GE(srgbByteFormula(srgbThreshold(code)), code) << code;
    if (t > 0) {
      EXPECT_LT(srgbByteFormula(fromBits(t - 1)), code) << "threshold " << code;
    }
    for (std::uint32_t d = 0; d <= 64; ++d) {
      check(fromBits(t + d));
      if (t >= d) check(fromBits(t - d));
    }
  }
  const float specials[] = {0.0f,
                            -0.0f,
                            std::numeric_limits<float>::denorm_min(),
                            std::numeric_limits<float>::min(),
                            -1e-30f,
                            -1.0f,
                            1.0f,
                            std::nextafter(1.0f, 0.0f),
                            std::nextafter(1.0f, 2.0f),
                            2.0f,
                            1e30f,
                            std::numeric_limits<float>::max(),
                            std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(),
                            std::numeric_limits<float>::quiet_NaN(),
                            -std::numeric_limits<float>::quiet_NaN(),
                            fromBits(0x7F800001u),
                            fromBits(0xFFFFFFFFu)};
  for (float x : specials) check(x);
  EXPECT_EQ(srgbByte(std::numeric_limits<float>::quiet_NaN()), 0);
  EXPECT_EQ(srgbByte(-1.0f), 0);
  EXPECT_EQ(srgbByte(2.0f), 255);
  EXPECT_EQ(srgbByte(std::numeric_limits<float>::infinity()), 255);
  EXPECT_EQ(mismatches, 0u) << "of " << checked;
  EXPECT_GT(checked, 17'000'000u);
}

TEST(ImageIo, EightBitFilesHoldTheFormulasBytes) {
  const std::string dir = scratchDir();
  std::vector<float> values = {0.0f,
                               1.0f,
                               -1.0f,
                               2.0f,
                               std::numeric_limits<float>::quiet_NaN(),
                               std::numeric_limits<float>::infinity(),
                               0.0031308f,
                               0.5f};
  for (int code = 1; code <= 255; ++code) {
    values.push_back(srgbThreshold(code));
    values.push_back(std::nextafter(srgbThreshold(code), 0.0f));
  }
  // row 0: the values as colour, opaque; row 1: the values as alpha over black (PNG stores
  // colour unassociated, so colour is checked where alpha is 1)
  Image img;
  img.width = static_cast<int>(values.size());
  img.height = 2;
  for (float v : values) img.rgba.insert(img.rgba.end(), {v, v, v, 1.0f});
  for (float v : values) img.rgba.insert(img.rgba.end(), {0.0f, 0.0f, 0.0f, v});
  writeImage(img, dir + "/codes.png");
  auto in = OIIO::ImageInput::open(dir + "/codes.png");
  ASSERT_TRUE(in);
  ASSERT_EQ(in->spec().nchannels, 4);
  std::vector<unsigned char> bytes(values.size() * 8);
  ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, bytes.data()));
  const std::size_t row = values.size() * 4;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const float v = values[i];
    for (int c = 0; c < 3; ++c) EXPECT_EQ(bytes[i * 4 + c], srgbByteFormula(v)) << "value " << v;
    const float a = std::isnan(v) ? 0.0f : std::min(std::max(v, 0.0f), 1.0f);
    EXPECT_EQ(bytes[row + i * 4 + 3], std::lround(a * 255.0f)) << "alpha " << v;
  }
}

Image noise(int w, int h, unsigned seed) {
  Image img;
  img.width = w;
  img.height = h;
  img.rgba.resize(static_cast<std::size_t>(w) * h * 4);
  unsigned s = seed;
  for (float& v : img.rgba) {
    s = s * 1664525u + 1013904223u;
    v = static_cast<float>(s >> 8) / static_cast<float>(1u << 24);
  }
  for (std::size_t p = 3; p < img.rgba.size(); p += 4) img.rgba[p] = 1.0f;
  return img;
}

TEST(ImageIo, CompressionChangesTheFileNotThePixels) {
  const std::string dir = scratchDir();
  const Image img = noise(64, 48, 7);
  std::vector<std::uintmax_t> sizes;
  std::vector<float> first;
  for (int level : {0, 1, 6, 9}) {
    ImageWriteOptions o;
    o.pngCompression = level;
    const std::string path = dir + "/level" + std::to_string(level) + ".png";
    writeImage(img, path, o);
    sizes.push_back(fs::file_size(path));
    const Image back = readImage(path);
    if (first.empty()) first = back.rgba;
    EXPECT_EQ(back.rgba, first) << "level " << level << " reads back other pixels";
  }
  EXPECT_GT(sizes[0], sizes[3]) << "level 0 (stored) is not larger than level 9";
  EXPECT_GE(sizes[1], sizes[3]);
  std::vector<float> exr;
  for (const std::string c : {"none", "rle", "zip", "zips", "piz"}) {
    ImageWriteOptions o;
    o.exrCompression = c;
    writeImage(img, dir + "/" + c + ".exr", o);
    const Image back = readImage(dir + "/" + c + ".exr");
    if (exr.empty()) exr = back.rgba;
    EXPECT_EQ(back.rgba, exr) << c << " is lossless, yet reads back other pixels";
  }
  EXPECT_NE(fs::file_size(dir + "/none.exr"), fs::file_size(dir + "/zip.exr"));
  for (int bad : {-1, 10}) {
    ImageWriteOptions o;
    o.pngCompression = bad;
    EXPECT_NE(errorOf([&] { writeImage(img, dir + "/bad.png", o); }).find("outside 0..9"),
              std::string::npos);
  }
  ImageWriteOptions o;
  o.exrCompression = "zstd";
  EXPECT_NE(errorOf([&] { writeImage(img, dir + "/bad.exr", o); }).find("\"zstd\""),
            std::string::npos);
  EXPECT_FALSE(fs::exists(dir + "/bad.png"));
  EXPECT_FALSE(fs::exists(dir + "/bad.exr"));
}

TEST(ImageIo, CompressionFlagsRefusedBeforeAnyWork) {
  const std::string dir = scratchDir();
  const std::string render =
      "render " + quote(dir + "/no_scene.json") + " -o " + quote(dir + "/x.png");
  for (const auto& [flag, fragment] : std::vector<std::pair<std::string, std::string>>{
           {" --png-compression 12", "--png-compression must be 0..9, not 12"},
           {" --png-compression -1", "--png-compression must be 0..9, not -1"},
           {" --exr-compression zstd", "--exr-compression"}}) {
    const CommandResult r = runCli(render + flag);
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(onlyErrorLine(r.output).find(fragment), std::string::npos) << r.output;
  }
}

// Writers from several threads: each of eight threads writes a PNG, an EXR and a layered EXR
// of its own image to its own paths, half of them into a folder that does not exist.
TEST(ImageIo, ConcurrentWritersOnDifferentPaths) {
  const std::string dir = scratchDir();
  constexpr int kThreads = 8;
  std::vector<std::string> errors(kThreads);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      const std::string base =
          (t % 2 ? dir + "/missing_" + std::to_string(t) : dir) + "/t" + std::to_string(t);
      const Image img = noise(96, 64, 100 + t);
      try {
        for (int k = 0; k < 3; ++k) {
          writeImage(img, base + ".png");
          writeImage(img, base + ".exr");
          std::vector<ImageChannel> ch = {{"R", {}, false}, {"G", {}, true}};
          for (std::size_t p = 0; p < img.rgba.size() / 4; ++p) {
            ch[0].values.push_back(img.rgba[p * 4]);
            ch[1].values.push_back(img.rgba[p * 4 + 1]);
          }
          writeChannels(ch, img.width, img.height, base + ".layers.exr");
        }
      } catch (const Error& e) {
        errors[t] = e.what();
      }
    });
  for (std::thread& t : threads) t.join();
  for (int t = 0; t < kThreads; ++t) {
    SCOPED_TRACE(t);
    const std::string base = dir + "/t" + std::to_string(t);
    if (t % 2) {
      EXPECT_NE(errors[t].find("missing_" + std::to_string(t) + "/t" + std::to_string(t) + ".png"),
                std::string::npos)
          << errors[t];
      continue;
    }
    EXPECT_EQ(errors[t], "");
    const Image img = noise(96, 64, 100 + t);
    const Image png = readImage(base + ".png"), exr = readImage(base + ".exr");
    ASSERT_EQ(png.rgba.size(), img.rgba.size());
    for (std::size_t i = 0; i < img.rgba.size(); ++i) {
      EXPECT_NEAR(png.rgba[i], img.rgba[i], 0.01f) << i;
      EXPECT_NEAR(exr.rgba[i], img.rgba[i], 1e-3f) << i;
    }
  }
  EXPECT_TRUE(temporariesIn(dir).empty());
}

// Several threads writing the same file at once: each write is whole, the last rename wins,
// and no temporary is left (each writer holds its own temporary slot).
TEST(ImageIo, ConcurrentWritersOnOnePath) {
  const std::string dir = scratchDir();
  const std::string path = dir + "/same.png";
  constexpr int kThreads = 6;
  std::vector<std::string> errors(kThreads);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      try {
        for (int k = 0; k < 4; ++k) writeImage(noise(64, 48, 200 + t), path);
      } catch (const Error& e) {
        errors[t] = e.what();
      }
    });
  for (std::thread& t : threads) t.join();
  for (int t = 0; t < kThreads; ++t) EXPECT_EQ(errors[t], "") << t;
  const Image got = readImage(path);
  int matches = 0;
  for (int t = 0; t < kThreads; ++t) {
    const Image want = noise(64, 48, 200 + t);
    bool same = got.rgba.size() == want.rgba.size();
    for (std::size_t i = 0; same && i < want.rgba.size(); ++i)
      same = std::fabs(got.rgba[i] - want.rgba[i]) < 0.01f;
    matches += same ? 1 : 0;
  }
  EXPECT_EQ(matches, 1);  // one whole image of one writer, not a mix
  EXPECT_TRUE(temporariesIn(dir).empty());
}

// The table of formats checked before any work (io/image_file.h) names only formats this
// build's OpenImageIO encodes into memory, with the alpha channel the table says.
// The streaming write: pieces placed at any offset (an encoder filling in a table it wrote
// ahead) make the file; dropped without commit, nothing is left and the target is as it was.
TEST(ImageIo, AtomicFileTakesPiecesAndLeavesNothingUnlessCommitted) {
  const std::string dir = scratchDir();
  const std::string target = dir + "/pieces.bin";
  {
    AtomicFile f(target);
    f.write("world", 5, 6);
    f.write("hello ", 6, 0);
    EXPECT_EQ(f.size(), 11u);
    char back[5] = {};
    EXPECT_EQ(f.read(back, 5, 6), 5u);
    EXPECT_EQ(std::string(back, 5), "world");
    EXPECT_FALSE(fs::exists(target)) << "nothing at the target before the commit";
    f.commit();
  }
  EXPECT_EQ(readBytes(target), "hello world");
  {
    AtomicFile f(target);
    f.write("replaced", 8, 0);
  }  // an encoder that failed: no commit
  EXPECT_EQ(readBytes(target), "hello world");
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir)) entries += e.path().filename() != "pieces.bin";
  EXPECT_EQ(entries, 0u) << "the temporary is removed";
}

TEST(ImageIo, FormatTableMatchesTheCodecs) {
  const std::vector<std::string> exts = imageFormatExtensions();
  ASSERT_GE(exts.size(), 5u);
  for (const std::string& ext : exts) {
    SCOPED_TRACE(ext);
    auto out = OIIO::ImageOutput::create(ext.substr(1));
    OIIO::geterror();
    ASSERT_TRUE(out != nullptr);
    EXPECT_TRUE(out->supports("ioproxy"));
    EXPECT_EQ(imageFormatHasAlpha("x" + ext), out->supports("alpha") != 0);
    EXPECT_TRUE(imageFormatWritable("dir/x" + ext));
  }
  EXPECT_FALSE(imageFormatWritable("x.xyz"));
  EXPECT_FALSE(imageFormatWritable("x.gif"));
  EXPECT_FALSE(imageFormatWritable("noextension"));
}

TEST(ImageIo, ReadingRefusesSpecialFilesAndDamage) {
  const std::string dir = scratchDir();
  ASSERT_EQ(::mkfifo((dir + "/fifo.png").c_str(), 0644), 0);
  EXPECT_NE(errorOf([&] { readImage(dir + "/fifo.png"); }).find("a FIFO"), std::string::npos);
  EXPECT_NE(errorOf([&] { readImage(dir); }).find("a folder"), std::string::npos);
  writeImage(noise(16, 16, 3), dir + "/ok.png");
  std::string bytes = readBytes(dir + "/ok.png");
  bytes[bytes.size() / 2] ^= 0x55;
  writeBytes(dir + "/damaged.png", bytes);
  const std::string e = errorOf([&] { readImage(dir + "/damaged.png"); });
  EXPECT_NE(e.find("damaged.png: damaged PNG file"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  writeBytes(dir + "/short.png", readBytes(dir + "/ok.png").substr(0, bytes.size() - 20));
  EXPECT_NE(errorOf([&] { readImage(dir + "/short.png"); }).find("short.png"), std::string::npos);
}

}  // namespace
}  // namespace clhair::test
