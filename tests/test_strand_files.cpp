// test_strand_files.cpp — the cyHair and USC-HairSalon strand readers.
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
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "clhair/error.h"
#include "clhair/strand_groom.h"
#include "io/cyhair.h"
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
  EXPECT_EQ(readCyHair(writeFile(dir, "exact.hair", validTwoStrands().data), kNoLimit).trailingBytes, 0u);
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
  expectError([&] { writeUscHair(h, dir + "/bad.data"); }, dir + "/bad.data", {"point array does not match"});
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
  EXPECT_EQ(readUscHair(writeFile(dir, "exact.data", validUsc().data), kNoLimit).hair.trailingBytes, 0u);
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

}  // namespace
}  // namespace clhair
