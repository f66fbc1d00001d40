// test_strand_files.cpp — the cyHair, USC-HairSalon and TressFX strand readers and writers.
//
// Files are built byte by byte in the test's scratch folder, so every field a hostile or
// broken file could hold is under the test's control. Round trips go through writeCyHair
// and compare exactly; every rejection must be a clhair::Error of one line that names the
// file and the problem. No OpenCL device is needed.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "clhair/error.h"
#include "clhair/strand_groom.h"
#include "io/cyhair.h"
#include "io/tressfx.h"
#include "io/usc_hair.h"
#include "test_util.h"

namespace clhair {
namespace {

constexpr std::uint64_t kNoLimit = std::numeric_limits<std::uint64_t>::max();
const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

// Little-endian bytes, appended field by field.
struct Bytes {
  std::string data;
  Bytes& u16(std::uint16_t v) {
    for (int i = 0; i < 2; ++i) data += static_cast<char>(v >> (8 * i) & 0xFF);
    return *this;
  }
  Bytes& u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) data += static_cast<char>(v >> (8 * i) & 0xFF);
    return *this;
  }
  Bytes& i32(std::int32_t v) { return u32(static_cast<std::uint32_t>(v)); }
  Bytes& f32(float v) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, sizeof(bits));
    return u32(bits);
  }
  Bytes& text(const std::string& s) {
    data += s;
    return *this;
  }
};

std::string writeFile(const std::string& dir, const std::string& name, const std::string& data) {
  std::string path = dir + "/" + name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(data.data(), static_cast<std::streamsize>(data.size()));
  return path;
}

// The fields of a cyHair header; arrays are appended by the caller.
struct Header {
  std::uint32_t strands = 2;
  std::uint32_t points = 5;
  std::uint32_t flags = 0x3;
  std::uint32_t defaultSegments = 0;
  float thickness = 1.0f;
  float transparency = 0.0f;
  float color[3] = {1.0f, 1.0f, 1.0f};
  std::string info = "test";

  Bytes bytes() const {
    Bytes b;
    b.text("HAIR").u32(strands).u32(points).u32(flags).u32(defaultSegments);
    b.f32(thickness).f32(transparency).f32(color[0]).f32(color[1]).f32(color[2]);
    std::string padded = info;
    padded.resize(88, '\0');
    return b.text(padded);
  }
};

// A valid file: 2 strands of 1 and 2 segments (5 points) with a segments array and points.
Bytes validTwoStrands() {
  Bytes b = Header().bytes();
  b.u16(1).u16(2);
  for (int i = 0; i < 15; ++i) b.f32(0.5f * i);
  return b;
}

// Runs fn, which must throw clhair::Error of one line holding `path` and every fragment.
void expectError(const std::function<void()>& fn, const std::string& path,
                 const std::vector<std::string>& fragments) {
  try {
    fn();
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << "message does not name the file: " << msg;
    for (const std::string& f : fragments)
      EXPECT_NE(msg.find(f), std::string::npos) << "expected \"" << f << "\" in: " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "message is not one line: " << msg;
    return;
  }
  ADD_FAILURE() << "no clhair::Error thrown for " << path;
}

void expectCyHairError(const std::string& path, const std::vector<std::string>& fragments,
                       std::uint64_t maxBytes = kNoLimit) {
  expectError([&] { readCyHair(path, maxBytes); }, path, fragments);
}

void expectUscError(const std::string& path, const std::vector<std::string>& fragments,
                    std::uint64_t maxBytes = kNoLimit) {
  expectError([&] { readUscHair(path, maxBytes); }, path, fragments);
}

// ---- cyHair: round trips ------------------------------------------------------------------

CyHair makeHair(bool uniform, bool thickness, bool transparency, bool colors) {
  CyHair h;
  h.segments = uniform ? std::vector<std::uint32_t>{3, 3, 3} : std::vector<std::uint32_t>{1, 4, 2};
  std::size_t points = 0;
  for (std::uint32_t s : h.segments) points += s + 1;
  for (std::size_t i = 0; i < points * 3; ++i) h.points.push_back(0.1f * i - 1.25f + 1e-7f * i * i);
  for (std::size_t i = 0; thickness && i < points; ++i) h.thickness.push_back(0.01f + 0.003f * i);
  for (std::size_t i = 0; transparency && i < points; ++i) h.transparency.push_back(0.05f * i);
  for (std::size_t i = 0; colors && i < points * 3; ++i) h.colors.push_back(1.0f / (1 + i));
  h.defaultThickness = 0.125f;
  h.defaultTransparency = 0.5f;
  h.defaultColor[0] = 0.25f;
  h.defaultColor[1] = 0.5f;
  h.defaultColor[2] = 0.75f;
  h.info = "round trip";
  return h;
}

TEST(StrandFileCyHair, RoundTripsEveryArrayCombination) {
  const std::string dir = test::scratchDir();
  for (int mask = 0; mask < 16; ++mask) {
    const bool uniform = mask & 1, thickness = mask & 2, transparency = mask & 4, colors = mask & 8;
    SCOPED_TRACE("uniform " + std::to_string(uniform) + " thickness " + std::to_string(thickness) +
                 " transparency " + std::to_string(transparency) + " colours " +
                 std::to_string(colors));
    const CyHair h = makeHair(uniform, thickness, transparency, colors);
    const std::string path = dir + "/mask" + std::to_string(mask) + ".hair";
    writeCyHair(h, path);
    const CyHair r = readCyHair(path, kNoLimit);
    EXPECT_EQ(r.segments, h.segments);
    EXPECT_EQ(r.points, h.points);
    EXPECT_EQ(r.thickness, h.thickness);
    EXPECT_EQ(r.transparency, h.transparency);
    EXPECT_EQ(r.colors, h.colors);
    EXPECT_EQ(r.defaultThickness, h.defaultThickness);
    EXPECT_EQ(r.defaultTransparency, h.defaultTransparency);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(r.defaultColor[c], h.defaultColor[c]);
    EXPECT_EQ(r.info, h.info);
    EXPECT_EQ(strandCount(r), 3u);
    EXPECT_EQ(pointCount(r), r.points.size() / 3);
  }
}

TEST(StrandFileCyHair, AppliesHeaderDefaults) {
  const std::string dir = test::scratchDir();
  Header hd;
  hd.strands = 3;
  hd.points = 9;
  hd.flags = 0x2;  // points only: segments, thickness, transparency, colour from the header
  hd.defaultSegments = 2;
  hd.thickness = 0.5f;
  hd.transparency = 0.25f;
  hd.color[0] = 0.1f;
  hd.color[1] = 0.2f;
  hd.color[2] = 0.3f;
  hd.info = std::string(88, 'i');  // no terminating NUL: all 88 bytes are the text
  Bytes b = hd.bytes();
  for (int i = 0; i < 27; ++i) b.f32(static_cast<float>(i));
  const CyHair r = readCyHair(writeFile(dir, "defaults.hair", b.data), kNoLimit);
  EXPECT_EQ(r.segments, (std::vector<std::uint32_t>{2, 2, 2}));
  ASSERT_EQ(r.points.size(), 27u);
  EXPECT_EQ(r.points[26], 26.0f);
  EXPECT_TRUE(r.thickness.empty());
  EXPECT_TRUE(r.transparency.empty());
  EXPECT_TRUE(r.colors.empty());
  EXPECT_EQ(r.defaultThickness, 0.5f);
  EXPECT_EQ(r.defaultTransparency, 0.25f);
  EXPECT_EQ(r.defaultColor[0], 0.1f);
  EXPECT_EQ(r.defaultColor[1], 0.2f);
  EXPECT_EQ(r.defaultColor[2], 0.3f);
  EXPECT_EQ(r.info, std::string(88, 'i'));
}

TEST(StrandFileCyHair, IgnoresTrailingBytesAndKeepsSinglePointStrands) {
  const std::string dir = test::scratchDir();
  Header hd;
  hd.strands = 2;
  hd.points = 3;
  Bytes b = hd.bytes();
  b.u16(0).u16(1);  // a single-point strand is legal cyHair
  for (int i = 0; i < 9; ++i) b.f32(1.0f * i);
  b.text("trailing bytes are ignored");
  const CyHair r = readCyHair(writeFile(dir, "trailing.hair", b.data), kNoLimit);
  EXPECT_EQ(r.segments, (std::vector<std::uint32_t>{0, 1}));
  EXPECT_EQ(r.points.size(), 9u);
  EXPECT_EQ(r.trailingBytes, 26u);
  EXPECT_EQ(
      readCyHair(writeFile(dir, "exact.hair", validTwoStrands().data), kNoLimit).trailingBytes, 0u);
}

TEST(StrandFileCyHair, ReadsAtExactlyTheByteLimit) {
  const std::string dir = test::scratchDir();
  const std::string path = writeFile(dir, "limit.hair", validTwoStrands().data);
  // 2 strands * 4 bytes + 5 points * 12 bytes = 68 bytes of arrays.
  EXPECT_EQ(readCyHair(path, 68).points.size(), 15u);
  expectCyHairError(path, {"2 strands and 5 points need 68 bytes", "67-byte limit"}, 67);
}

// ---- cyHair: rejections -------------------------------------------------------------------

TEST(StrandFileCyHair, RejectsMissingFileAndDirectory) {
  const std::string dir = test::scratchDir();
  expectCyHairError(dir + "/absent.hair", {"cannot open cyHair file"});
  expectCyHairError(dir, {"is not a regular file"});
}

TEST(StrandFileCyHair, RejectsFileShorterThanHeader) {
  const std::string dir = test::scratchDir();
  expectCyHairError(writeFile(dir, "empty.hair", ""), {"is 0 bytes", "128-byte cyHair header"});
  const std::string cut = validTwoStrands().data.substr(0, 127);
  expectCyHairError(writeFile(dir, "short.hair", cut), {"is 127 bytes", "128-byte"});
}

TEST(StrandFileCyHair, RejectsWrongSignature) {
  const std::string dir = test::scratchDir();
  std::string data = validTwoStrands().data;
  data.replace(0, 4, std::string("HA\x01R", 4));
  expectCyHairError(writeFile(dir, "sig.hair", data), {"starts with \"HA\\x01R\"", "\"HAIR\""});
}

TEST(StrandFileCyHair, RejectsZeroStrands) {
  const std::string dir = test::scratchDir();
  Header hd;
  hd.strands = 0;
  hd.points = 0;
  expectCyHairError(writeFile(dir, "zero.hair", hd.bytes().data), {"0 strands"});
}

TEST(StrandFileCyHair, RejectsMissingPointsArray) {
  const std::string dir = test::scratchDir();
  Header hd;
  hd.flags = 0x1 | 0x4;  // segments and thickness, no points
  Bytes b = hd.bytes();
  b.u16(1).u16(2);
  for (int i = 0; i < 5; ++i) b.f32(1.0f);
  expectCyHairError(writeFile(dir, "nopoints.hair", b.data), {"has no points array", "0x5"});
}

TEST(StrandFileCyHair, RejectsUnknownFlags) {
  const std::string dir = test::scratchDir();
  Header hd;
  hd.flags = 0x3 | 0x40;
  expectCyHairError(writeFile(dir, "flags.hair", hd.bytes().data), {"unknown bits 0x40"});
}

TEST(StrandFileCyHair, RejectsEveryTruncatedArray) {
  const std::string dir = test::scratchDir();
  // 2 strands, 5 points, every array: header 128, segments 4, points 60, thickness 20,
  // transparency 20, colours 60 bytes.
  Header hd;
  hd.flags = 0x1F;
  Bytes b = hd.bytes();
  b.u16(1).u16(2);
  for (int i = 0; i < 15 + 5 + 5 + 15; ++i) b.f32(0.25f);
  ASSERT_EQ(b.data.size(), 292u);
  EXPECT_EQ(readCyHair(writeFile(dir, "full.hair", b.data), kNoLimit).colors.size(), 15u);
  const struct {
    std::size_t size;
    const char* array;
    const char* endsAt;
  } cases[] = {{128, "segments array", "byte 132"},  {131, "segments array", "byte 132"},
               {132, "points array", "byte 192"},    {191, "points array", "byte 192"},
               {211, "thickness array", "byte 212"}, {231, "transparency array", "byte 232"},
               {291, "colour array", "byte 292"}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.size);
    const std::string path =
        writeFile(dir, "cut" + std::to_string(c.size) + ".hair", b.data.substr(0, c.size));
    expectCyHairError(
        path, {"truncated", c.array, c.endsAt, "file has " + std::to_string(c.size) + " bytes"});
  }
}

TEST(StrandFileCyHair, RejectsSegmentsThatDoNotAddUp) {
  const std::string dir = test::scratchDir();
  Header hd;
  hd.points = 6;  // the segments say 2 + 3 = 5
  Bytes b = hd.bytes();
  b.u16(1).u16(2);
  for (int i = 0; i < 18; ++i) b.f32(0.0f);
  expectCyHairError(writeFile(dir, "sum.hair", b.data),
                    {"header says 6 points but the segments array adds up to 5"});

  Header def;
  def.flags = 0x2;
  def.defaultSegments = 3;  // 2 strands * 4 points = 8, not 5
  Bytes d = def.bytes();
  for (int i = 0; i < 15; ++i) d.f32(0.0f);
  expectCyHairError(writeFile(dir, "default.hair", d.data),
                    {"header says 5 points but 2 strands of 3 default segments make 8"});
}

TEST(StrandFileCyHair, RejectsNonFiniteFloatsInEveryArray) {
  const std::string dir = test::scratchDir();
  // Offsets into a file with every array (see RejectsEveryTruncatedArray).
  Header hd;
  hd.flags = 0x1F;
  Bytes b = hd.bytes();
  b.u16(1).u16(2);
  for (int i = 0; i < 40; ++i) b.f32(0.25f);
  auto poke = [&](std::size_t offset, float v) {
    std::string data = b.data;
    std::string bits = Bytes().f32(v).data;
    data.replace(offset, 4, bits);
    return data;
  };
  const struct {
    std::size_t offset;
    float value;
    std::vector<std::string> fragments;
  } cases[] = {
      {132 + 4 * 4, kNaN, {"points array: point 1 y (strand 0) is nan"}},
      {132 + 4 * 14, -kInf, {"points array: point 4 z (strand 1) is -inf"}},
      {192 + 4 * 2, kInf, {"thickness array: point 2 (strand 1) is inf"}},
      {212 + 4 * 0, kNaN, {"transparency array: point 0 (strand 0) is nan"}},
      {232 + 4 * 5, kNaN, {"colour array: point 1 b (strand 0) is nan"}},
      {20, kNaN, {"header default thickness is nan"}},
      {24, kInf, {"header default transparency is inf"}},
      {36, kNaN, {"header default colour b is nan"}},
  };
  int n = 0;
  for (const auto& c : cases) {
    SCOPED_TRACE(c.fragments[0]);
    const std::string path =
        writeFile(dir, "nan" + std::to_string(n++) + ".hair", poke(c.offset, c.value));
    expectCyHairError(path, c.fragments);
  }
}

TEST(StrandFileCyHair, RefusesAbsurdCountsQuickly) {
  const std::string dir = test::scratchDir();
  // 4e9 points would need 48 GB of points alone; the file has a few hundred bytes.
  Header hd;
  hd.strands = 1;
  hd.points = 4'000'000'000u;
  hd.flags = 0x2 | 0x10;
  hd.defaultSegments = 3'999'999'999u;
  Bytes b = hd.bytes();
  for (int i = 0; i < 64; ++i) b.f32(0.0f);
  const std::string path = writeFile(dir, "huge.hair", b.data);
  const auto start = std::chrono::steady_clock::now();
  expectCyHairError(path, {"truncated", "4000000000 points", "file has 384 bytes"});
  // The largest strand count: its segments array alone would be 8 GB.
  hd.flags = 0x1 | 0x2;
  hd.strands = 0xFFFFFFFFu;
  expectCyHairError(writeFile(dir, "strands.hair", hd.bytes().data),
                    {"truncated", "4294967295 strands", "segments array"});
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 0.5) << "refusing a hostile header should not touch memory";
}

// ---- USC-HairSalon ------------------------------------------------------------------------

// Three strands: 2 points, 1 point (skipped), 3 points.
Bytes validUsc() {
  Bytes b;
  b.i32(3);
  b.i32(2).f32(0.0f).f32(1.0f).f32(2.0f).f32(3.0f).f32(4.0f).f32(5.0f);
  b.i32(1).f32(kNaN).f32(9.0f).f32(9.0f);  // skipped, so its values are not inspected
  b.i32(3);
  for (int i = 0; i < 9; ++i) b.f32(10.0f + i);
  return b;
}

TEST(StrandFileUsc, ReadsStrandsAndSkipsSinglePoints) {
  const std::string dir = test::scratchDir();
  const UscHair u = readUscHair(writeFile(dir, "three.data", validUsc().data), kNoLimit);
  EXPECT_EQ(u.skippedStrands, 1u);
  EXPECT_EQ(u.hair.segments, (std::vector<std::uint32_t>{1, 2}));
  EXPECT_EQ(u.hair.points,
            (std::vector<float>{0, 1, 2, 3, 4, 5, 10, 11, 12, 13, 14, 15, 16, 17, 18}));
  EXPECT_TRUE(u.hair.thickness.empty());
  EXPECT_TRUE(u.hair.transparency.empty());
  EXPECT_TRUE(u.hair.colors.empty());
  EXPECT_EQ(u.hair.defaultThickness, CyHair().defaultThickness);
  EXPECT_EQ(u.hair.info, "USC-HairSalon");

  // Zero-point strands are skipped too.
  Bytes b;
  b.i32(2).i32(0).i32(2);
  for (int i = 0; i < 6; ++i) b.f32(1.0f);
  const UscHair z = readUscHair(writeFile(dir, "zero.data", b.data), kNoLimit);
  EXPECT_EQ(z.skippedStrands, 1u);
  EXPECT_EQ(z.hair.segments, (std::vector<std::uint32_t>{1}));
}

TEST(StrandFileUsc, RoundTripsThroughCyHair) {
  const std::string dir = test::scratchDir();
  const UscHair u = readUscHair(writeFile(dir, "three.data", validUsc().data), kNoLimit);
  writeCyHair(u.hair, dir + "/three.hair");
  const CyHair r = readCyHair(dir + "/three.hair", kNoLimit);
  EXPECT_EQ(r.segments, u.hair.segments);
  EXPECT_EQ(r.points, u.hair.points);
}

TEST(StrandFileUsc, WriterRoundTripsPointsAndRejectsMismatchedArrays) {
  const std::string dir = test::scratchDir();
  CyHair h;
  h.segments = {1, 3};
  for (int i = 0; i < 6 * 3; ++i) h.points.push_back(0.25f * i - 1.0f);
  h.thickness.assign(6, 0.5f);  // not representable in the format: dropped
  writeUscHair(h, dir + "/two.data");
  EXPECT_EQ(std::filesystem::file_size(dir + "/two.data"), 4u + 2u * 4u + 6u * 12u);
  const UscHair u = readUscHair(dir + "/two.data", kNoLimit);
  EXPECT_EQ(u.skippedStrands, 0u);
  EXPECT_EQ(u.hair.segments, h.segments);
  EXPECT_EQ(u.hair.points, h.points);
  EXPECT_TRUE(u.hair.thickness.empty());

  h.points.pop_back();
  expectError([&] { writeUscHair(h, dir + "/bad.data"); }, dir + "/bad.data",
              {"point array does not match"});
  EXPECT_FALSE(std::filesystem::exists(dir + "/bad.data"));
}

TEST(StrandFileUsc, RejectsShortFileAndBadStrandCounts) {
  const std::string dir = test::scratchDir();
  expectUscError(writeFile(dir, "short.data", "ab"), {"is 2 bytes", "strand count"});
  expectUscError(writeFile(dir, "neg.data", Bytes().i32(-5).data), {"strand count is -5"});
  expectUscError(writeFile(dir, "zero.data", Bytes().i32(0).data), {"strand count is 0"});
  // A cyHair file read as USC: "HAIR" is 1380532552 strands.
  expectUscError(writeFile(dir, "cyhair.data", validTwoStrands().data),
                 {"strand count is 1380532552 but a file of 192 bytes holds at most 47 strands"});
  expectUscError(writeFile(dir, "missing.data", Bytes().i32(2).i32(0).data),
                 {"strand count is 2", "holds at most 1 strands"});
  expectUscError(dir + "/absent.data", {"cannot open USC-HairSalon file"});
}

TEST(StrandFileUsc, RejectsNegativeAndTruncatedPointCounts) {
  const std::string dir = test::scratchDir();
  Bytes neg;
  neg.i32(2).i32(2);
  for (int i = 0; i < 6; ++i) neg.f32(0.0f);
  neg.i32(-1);
  expectUscError(writeFile(dir, "neg.data", neg.data),
                 {"strand 1 has a negative point count (-1) at byte 32"});

  std::string cut = validUsc().data;
  cut.pop_back();
  expectUscError(writeFile(dir, "cut.data", cut),
                 {"truncated", "strand 2 of 3 says 3 points", "file has 87 bytes"});

  Bytes huge;
  huge.i32(1).i32(0x7FFFFFFF).f32(0.0f);
  const auto start = std::chrono::steady_clock::now();
  expectUscError(writeFile(dir, "huge.data", huge.data),
                 {"truncated", "strand 0 of 1 says 2147483647 points"});
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 0.5);
}

TEST(StrandFileUsc, RejectsNonFiniteCoordinates) {
  const std::string dir = test::scratchDir();
  std::string data = validUsc().data;
  // Strand 2, point 1, y: 4 + (4 + 24) + (4 + 12) + 4 + 12 + 4 = 68.
  data.replace(68, 4, Bytes().f32(kInf).data);
  expectUscError(writeFile(dir, "inf.data", data), {"strand 2 point 1 y is inf"});
}

TEST(StrandFileUsc, RejectsNoUsableStrands) {
  const std::string dir = test::scratchDir();
  Bytes single;
  single.i32(2).i32(1).f32(0.0f).f32(0.0f).f32(0.0f).i32(0);
  expectUscError(writeFile(dir, "single.data", single.data),
                 {"none of its 2 strands has 2 or more points"});
}

// Trailing bytes are read past and counted, as by the cyHair reader.
TEST(StrandFileUsc, CountsTrailingBytesLikeCyHair) {
  const std::string dir = test::scratchDir();
  const UscHair u = readUscHair(writeFile(dir, "trailing.data", validUsc().data + "xyz"), kNoLimit);
  EXPECT_EQ(u.hair.trailingBytes, 3u);
  EXPECT_EQ(u.hair.segments, (std::vector<std::uint32_t>{1, 2}));
  EXPECT_EQ(readUscHair(writeFile(dir, "exact.data", validUsc().data), kNoLimit).hair.trailingBytes,
            0u);
}

// Both formats: a file with trailing bytes loads, with one warning naming the file and the
// byte count; a file without them gives none.
TEST(StrandFileLoad, TrailingBytesWarnOnceForBothFormats) {
  const std::string dir = test::scratchDir();
  const struct {
    std::string name, data, count;
  } cases[] = {{"trailing.hair", validTwoStrands().data + "0123456789", "10 bytes"},
               {"trailing.data", validUsc().data + "xyz", "3 bytes"}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = writeFile(dir, c.name, c.data);
    std::vector<std::string> warnings;
    const StrandGroom g = loadStrandGroom(path, kNoLimit, nullptr, &warnings);
    EXPECT_EQ(g.pointCounts.size(), 2u);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find(path), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find(c.count), std::string::npos) << warnings[0];
    EXPECT_EQ(warnings[0].find('\n'), std::string::npos) << warnings[0];
  }
  std::vector<std::string> none;
  loadStrandGroom(writeFile(dir, "exact.hair", validTwoStrands().data), kNoLimit, nullptr, &none);
  loadStrandGroom(writeFile(dir, "exact.data", validUsc().data), kNoLimit, nullptr, &none);
  EXPECT_TRUE(none.empty()) << none.front();
}

TEST(StrandFileUsc, RefusesMoreThanTheByteLimit) {
  const std::string dir = test::scratchDir();
  const std::string path = writeFile(dir, "three.data", validUsc().data);
  // Kept: 2 strands * 4 bytes + 5 points * 12 bytes = 68 bytes.
  EXPECT_EQ(readUscHair(path, 68).hair.points.size(), 15u);
  expectUscError(path, {"up to strand 2 already need 68 bytes", "67-byte limit"}, 67);
}

// ---- TressFX --------------------------------------------------------------------------------

// Point k of strand s in the files below.
float tfxCoord(std::uint32_t s, std::uint32_t k, int c) {
  return 0.1f * s + (c == 0 ? 0.01f * k : c == 1 ? -0.02f * k : 0.5f);
}

// A TressFX 4.0 file: `strands` strands of `perStrand` vertices (xyz from tfxCoord, w 0 for
// the first two), then strand uv (0.25 s mod 1, 0.75) when `uv`.
Bytes tfx4(std::uint32_t strands, std::uint32_t perStrand, bool uv, float version = 4.0f) {
  Bytes b;
  const std::uint32_t uvOffset = 160 + 16 * strands * perStrand;
  b.f32(version).u32(strands).u32(perStrand).u32(160).u32(uv ? uvOffset : 0).u32(0).u32(0).u32(0);
  for (int i = 0; i < 32; ++i) b.u32(0);
  for (std::uint32_t s = 0; s < strands; ++s)
    for (std::uint32_t k = 0; k < perStrand; ++k)
      b.f32(tfxCoord(s, k, 0))
          .f32(tfxCoord(s, k, 1))
          .f32(tfxCoord(s, k, 2))
          .f32(k < 2 ? 0.0f : 1.0f);
  if (uv)
    for (std::uint32_t s = 0; s < strands; ++s) b.f32(std::fmod(0.25f * s, 1.0f)).f32(0.75f);
  return b;
}

// The same strands in the TressFX 3.0 layout: a 296-byte header, float xyz, strand uv after.
Bytes tfx3(std::uint32_t strands, std::uint32_t perStrand, bool uv) {
  Bytes b;
  const std::uint32_t uvOffset = 296 + 12 * strands * perStrand;
  b.f32(3.0f).u32(strands).u32(perStrand).u32(0).u32(1);  // no follow hairs, both ends pinned
  for (int i = 0; i < 31; ++i) b.u32(0);
  b.u32(296).u32(0).u32(uv ? uvOffset : 0).u32(0).u32(0).u32(0);
  for (int i = 0; i < 32; ++i) b.u32(0);
  for (std::uint32_t s = 0; s < strands; ++s)
    for (std::uint32_t k = 0; k < perStrand; ++k)
      b.f32(tfxCoord(s, k, 0)).f32(tfxCoord(s, k, 1)).f32(tfxCoord(s, k, 2));
  if (uv)
    for (std::uint32_t s = 0; s < strands; ++s) b.f32(std::fmod(0.25f * s, 1.0f)).f32(0.75f);
  return b;
}

// Replaces the 4 bytes at `offset` with `v`.
std::string patched(std::string data, std::size_t offset, float v) {
  data.replace(offset, 4, Bytes().f32(v).data);
  return data;
}

std::string patchedU32(std::string data, std::size_t offset, std::uint32_t v) {
  data.replace(offset, 4, Bytes().u32(v).data);
  return data;
}

void expectTfxError(const std::string& path, const std::vector<std::string>& fragments,
                    std::uint64_t maxBytes = kNoLimit) {
  expectError([&] { readTressFx(path, maxBytes); }, path, fragments);
}

void expectTfxStrands(const TressFxHair& t, std::uint32_t strands, std::uint32_t perStrand,
                      bool uv) {
  EXPECT_EQ(t.hair.segments, std::vector<std::uint32_t>(strands, perStrand - 1));
  ASSERT_EQ(t.hair.points.size(), 3u * strands * perStrand);
  for (std::uint32_t s = 0; s < strands; ++s)
    for (std::uint32_t k = 0; k < perStrand; ++k)
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(t.hair.points[3 * (s * perStrand + k) + c], tfxCoord(s, k, c))
            << s << " " << k << " " << c;
  ASSERT_EQ(t.strandUv.size(), uv ? 2u * strands : 0u);
  for (std::uint32_t s = 0; uv && s < strands; ++s) {
    EXPECT_EQ(t.strandUv[2 * s], std::fmod(0.25f * s, 1.0f));
    EXPECT_EQ(t.strandUv[2 * s + 1], 0.75f);
  }
  EXPECT_TRUE(t.hair.thickness.empty() && t.hair.colors.empty() && t.hair.transparency.empty());
  EXPECT_EQ(t.hair.trailingBytes, 0u);
}

TEST(StrandFileTressFx, ReadsVersion4PositionsAndStrandUv) {
  const std::string dir = test::scratchDir();
  const TressFxHair t = readTressFx(writeFile(dir, "v4.tfx", tfx4(3, 5, true).data), kNoLimit);
  EXPECT_EQ(t.version, 4.0f);
  expectTfxStrands(t, 3, 5, true);
  expectTfxStrands(readTressFx(writeFile(dir, "v4nouv.tfx", tfx4(2, 4, false).data), kNoLimit), 2,
                   4, false);
  // 4.x minor versions share the layout
  EXPECT_EQ(readTressFx(writeFile(dir, "v41.tfx", tfx4(1, 4, false, 4.1f).data), kNoLimit).version,
            4.1f);
}

TEST(StrandFileTressFx, ReadsVersion3Layout) {
  const std::string dir = test::scratchDir();
  const TressFxHair t = readTressFx(writeFile(dir, "v3.tfx", tfx3(3, 4, true).data), kNoLimit);
  EXPECT_EQ(t.version, 3.0f);
  expectTfxStrands(t, 3, 4, true);
  // Read as 4.x (16-byte vertices at byte 160) these bytes would give other points.
  expectTfxStrands(readTressFx(writeFile(dir, "v3nouv.tfx", tfx3(2, 8, false).data), kNoLimit), 2,
                   8, false);
}

TEST(StrandFileTressFx, WriterRoundTripsAndPinsTheFirstTwoVertices) {
  const std::string dir = test::scratchDir();
  TressFxHair t;
  t.hair.segments = {3, 3};
  for (int i = 0; i < 8 * 3; ++i) t.hair.points.push_back(0.125f * i - 1.0f);
  t.hair.colors.assign(8 * 3, 0.5f);  // no place in the format: dropped
  t.strandUv = {0.1f, 0.2f, 0.3f, 0.4f};
  const std::string path = dir + "/two.tfx";
  writeTressFx(t, path);
  EXPECT_EQ(std::filesystem::file_size(path), 160u + 8u * 16u + 2u * 8u);
  const TressFxHair r = readTressFx(path, kNoLimit);
  EXPECT_EQ(r.version, 4.0f);
  EXPECT_EQ(r.hair.segments, t.hair.segments);
  EXPECT_EQ(r.hair.points, t.hair.points);
  EXPECT_EQ(r.strandUv, t.strandUv);
  EXPECT_TRUE(r.hair.colors.empty());
  // w (inverse mass) of strand 1's vertices: 0, 0, 1, 1
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (int k = 0; k < 4; ++k) {
    float w;
    std::memcpy(&w, bytes.data() + 160 + 16 * (4 + k) + 12, 4);
    EXPECT_EQ(w, k < 2 ? 0.0f : 1.0f) << "vertex " << k;
  }

  t.hair.segments = {3, 2};
  t.hair.points.resize(7 * 3);
  expectError([&] { writeTressFx(t, dir + "/uneven.tfx"); }, dir + "/uneven.tfx",
              {"strand 1 has 3 points but strand 0 has 4", "resample"});
  EXPECT_FALSE(std::filesystem::exists(dir + "/uneven.tfx"));
}

TEST(StrandFileTressFx, ResamplingKeepsRootAndTipAndSpacesPointsEvenly) {
  CyHair h;
  // An L: 3 units along x, then 1 along y (length 4), and a single-point strand.
  h.segments = {2, 0};
  h.points = {0, 0, 0, 3, 0, 0, 3, 1, 0, 7, 7, 7};
  const CyHair r = resampleStrands(h, 5);
  EXPECT_EQ(r.segments, (std::vector<std::uint32_t>{4, 4}));
  EXPECT_EQ(r.points, (std::vector<float>{0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0, 3, 1, 0,  //
                                          7, 7, 7, 7, 7, 7, 7, 7, 7, 7, 7, 7, 7, 7, 7}));
  const CyHair two = resampleStrands(h, 2);
  EXPECT_EQ(std::vector<float>(two.points.begin(), two.points.begin() + 6),
            (std::vector<float>{0, 0, 0, 3, 1, 0}));
  // the count: the largest power of two in 4..64 not above the longest strand
  const struct {
    std::uint32_t points, expected;
  } cases[] = {{2, 4}, {3, 4}, {5, 4}, {8, 8}, {9, 8}, {33, 32}, {64, 64}, {65, 64}, {129, 64}};
  for (const auto& c : cases) {
    CyHair one;
    one.segments = {1, c.points - 1};
    EXPECT_EQ(tressFxVertexCount(one), c.expected) << c.points << " points";
  }
}

TEST(StrandFileTressFx, RejectsTruncatedHeaders) {
  const std::string dir = test::scratchDir();
  expectTfxError(writeFile(dir, "tiny.tfx", std::string(2, '\0')), {"is 2 bytes", "version field"});
  expectTfxError(writeFile(dir, "h4.tfx", tfx4(1, 4, false).data.substr(0, 159)),
                 {"is 159 bytes", "160-byte header", "TressFX 4.x"});
  expectTfxError(writeFile(dir, "h3.tfx", tfx3(1, 4, false).data.substr(0, 295)),
                 {"is 295 bytes", "296-byte header", "TressFX 3.x"});
}

TEST(StrandFileTressFx, RejectsEveryArrayThatRunsPastTheFile) {
  const std::string dir = test::scratchDir();
  const std::string v4 = tfx4(2, 4, true).data;
  expectTfxError(writeFile(dir, "uv.tfx", v4.substr(0, v4.size() - 1)),
                 {"truncated", "2 strands of 4 vertices", "strand uv", "file's 303 bytes"});
  const std::string noUv = tfx4(2, 4, false).data;
  expectTfxError(
      writeFile(dir, "pos.tfx", noUv.substr(0, noUv.size() - 1)),
      {"truncated", "vertex positions (8 x 16 bytes from byte 160)", "file's 287 bytes"});
  expectTfxError(writeFile(dir, "pos3.tfx", tfx3(2, 4, false).data.substr(0, 296 + 95)),
                 {"truncated", "vertex positions (8 x 12 bytes from byte 296)"});
  // arrays the reader does not use must fit too: vertex colours (4.x byte 28), offset past the end
  expectTfxError(writeFile(dir, "colour.tfx", patchedU32(noUv, 28, 200)),
                 {"truncated", "vertex colours"});
  expectTfxError(writeFile(dir, "guide.tfx", patchedU32(tfx3(2, 4, false).data, 160, 1u << 30)),
                 {"truncated", "guide strand indices"});
}

TEST(StrandFileTressFx, RejectsNonFiniteFloats) {
  const std::string dir = test::scratchDir();
  const std::string v4 = tfx4(2, 4, true).data;
  // strand 1 vertex 2: 160 + 16 * 6; y is 4 bytes in, w 12
  expectTfxError(writeFile(dir, "y.tfx", patched(v4, 160 + 16 * 6 + 4, kNaN)),
                 {"vertex positions: strand 1 vertex 2 y is nan"});
  expectTfxError(writeFile(dir, "w.tfx", patched(v4, 160 + 16 * 6 + 12, kInf)),
                 {"strand 1 vertex 2 w (inverse mass) is inf"});
  expectTfxError(writeFile(dir, "uv.tfx", patched(v4, 160 + 16 * 8 + 8 + 4, -kInf)),
                 {"strand uv: strand 1 v is -inf"});
  expectTfxError(writeFile(dir, "z3.tfx", patched(tfx3(2, 4, false).data, 296 + 12 * 5 + 8, kNaN)),
                 {"strand 1 vertex 1 z is nan"});
}

TEST(StrandFileTressFx, RefusesHugeCountsQuickly) {
  const std::string dir = test::scratchDir();
  const auto start = std::chrono::steady_clock::now();
  // 2^32 - 1 strands of 2^32 - 1 vertices: 2^68 bytes of positions, from a 300-byte file
  std::string data = patchedU32(patchedU32(tfx4(2, 4, false).data, 4, 0xFFFFFFFFu), 8, 0xFFFFFFFFu);
  expectTfxError(writeFile(dir, "huge.tfx", data),
                 {"truncated", "4294967295 strands of 4294967295 vertices"});
  data = patchedU32(patchedU32(tfx3(2, 4, false).data, 4, 0xFFFFFFFFu), 8, 64);
  expectTfxError(writeFile(dir, "huge3.tfx", data),
                 {"truncated", "4294967295 strands of 64 vertices"});
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 0.5);
}

TEST(StrandFileTressFx, RejectsUnknownVersionsAndTheTextLayout) {
  const std::string dir = test::scratchDir();
  const std::string v4 = tfx4(2, 4, false).data;
  expectTfxError(writeFile(dir, "v2.tfx", patched(v4, 0, 2.0f)),
                 {"version field is 2", "expected 3.x or 4.x"});
  expectTfxError(writeFile(dir, "v5.tfx", patched(v4, 0, 5.0f)),
                 {"version field is 5", "expected 3.x or 4.x"});
  expectTfxError(writeFile(dir, "vnan.tfx", patched(v4, 0, kNaN)), {"version field is nan"});
  expectTfxError(writeFile(dir, "text.tfx", "numStrands 2\nis sorted 1\n"),
                 {"\"numS\"", "text layout is not supported", "3.x and 4.x"});
}

TEST(StrandFileTressFx, RejectsEmptyShortStrandsAndOffsetsIntoTheHeader) {
  const std::string dir = test::scratchDir();
  const std::string v4 = tfx4(2, 4, true).data;
  expectTfxError(writeFile(dir, "zero.tfx", patchedU32(v4, 4, 0)), {"0 strands"});
  expectTfxError(writeFile(dir, "one.tfx", patchedU32(v4, 8, 1)),
                 {"1 vertices per strand", "at least 2"});
  expectTfxError(writeFile(dir, "nopos.tfx", patchedU32(v4, 12, 0)),
                 {"no offset for the vertex positions"});
  expectTfxError(writeFile(dir, "inside.tfx", patchedU32(v4, 12, 8)),
                 {"vertex positions", "inside the 160-byte header"});
  expectTfxError(writeFile(dir, "uvinside.tfx", patchedU32(v4, 16, 4)),
                 {"strand uv", "inside the 160-byte header"});
}

TEST(StrandFileTressFx, RefusesMoreThanTheByteLimit) {
  const std::string dir = test::scratchDir();
  const std::string path = writeFile(dir, "two.tfx", tfx4(2, 4, true).data);
  // 2 strands * (4 + 8 uv) + 8 points * 12 = 120 bytes
  EXPECT_EQ(readTressFx(path, 120).hair.points.size(), 24u);
  expectTfxError(path, {"2 strands of 4 vertices need 120 bytes", "119-byte limit"}, 119);
}

// As a groom: trailing bytes warn once, strand uv in [0, 1] become root uv, uv outside are
// dropped with one warning.
TEST(StrandFileLoad, TressFxTrailingBytesAndStrandUv) {
  const std::string dir = test::scratchDir();
  std::vector<std::string> warnings;
  const StrandGroom g = loadStrandGroom(writeFile(dir, "extra.tfx", tfx4(3, 4, true).data + "xyzw"),
                                        kNoLimit, nullptr, &warnings);
  EXPECT_EQ(g.pointCounts, std::vector<std::uint32_t>(3, 4));
  ASSERT_EQ(g.rootUv.size(), 3u);
  EXPECT_EQ(g.rootUv[1], glm::vec2(0.25f, 0.75f));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("extra.tfx: 4 bytes after the end"), std::string::npos) << warnings[0];

  warnings.clear();
  const std::string outside =
      patched(tfx4(3, 4, true).data, 160 + 16 * 12 + 8, 1.5f);  // strand 1 u
  const StrandGroom o =
      loadStrandGroom(writeFile(dir, "outside.tfx", outside), kNoLimit, nullptr, &warnings);
  EXPECT_TRUE(o.rootUv.empty());
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("strand 1 has uv (1.5, 0.75) outside [0, 1]"), std::string::npos)
      << warnings[0];

  warnings.clear();
  loadStrandGroom(writeFile(dir, "exact.tfx", tfx4(3, 4, false).data), kNoLimit, nullptr,
                  &warnings);
  EXPECT_TRUE(warnings.empty());
}

}  // namespace
}  // namespace clhair
