// test_ply.cpp — PLY and CT2Hair `.bin` strand files (host/io/ply_read.cpp): the layouts
// read (binary both byte orders and ascii, segment counts, vertex counts and edge lists,
// 8-bit colours), a round trip through `clhair export-strands`, and malformed variants, each
// refused with one error line.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include "clhair/error.h"
#include "clhair/strand_groom.h"
#include "io/cyhair.h"
#include "io/ply_strands.h"
#include "test_util.h"

namespace clhair {
namespace {

constexpr std::uint64_t kLimit = 1ull << 30;

void writeBytes(const std::string& path, const std::string& data) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << data;
}

std::string f32(float v, bool big = false) {
  char b[4];
  std::memcpy(b, &v, 4);
  if (big) std::swap(b[0], b[3]), std::swap(b[1], b[2]);
  return std::string(b, 4);
}

std::string u32(std::uint32_t v, bool big = false) {
  char b[4];
  std::memcpy(b, &v, 4);
  if (big) std::swap(b[0], b[3]), std::swap(b[1], b[2]);
  return std::string(b, 4);
}

// Two strands of 3 and 2 points, big or little endian, counted by vertex_count.
std::string binaryPly(bool big) {
  std::string s =
      std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
      " 1.0\ncomment two strands\nelement vertex 5\nproperty float x\nproperty float y\n"
      "property float z\nproperty float nx\nelement strand 2\n"
      "property uint vertex_count\nend_header\n";
  for (int i = 0; i < 5; ++i)
    for (float v : {static_cast<float>(i), 1.0f, -static_cast<float>(i), 9.0f}) s += f32(v, big);
  s += u32(3, big) + u32(2, big);
  return s;
}

TEST(PlyStrands, BinaryBothByteOrdersAndVertexCounts) {
  const std::string dir = test::scratchDir();
  for (bool big : {false, true}) {
    writeBytes(dir + "/b.ply", binaryPly(big));
    const PlyStrands p = readPlyStrands(dir + "/b.ply", kLimit);
    ASSERT_EQ(p.hair.segments, (std::vector<std::uint32_t>{2, 1})) << big;
    ASSERT_EQ(p.hair.points.size(), 15u);
    EXPECT_EQ(p.hair.points[12], 4.0f);
    EXPECT_EQ(p.hair.points[14], -4.0f);
    EXPECT_TRUE(p.hair.colors.empty());
  }
}

TEST(PlyStrands, AsciiWithEdgesAndColours) {
  const std::string dir = test::scratchDir();
  // vertices 0-1-2 and 4-5 joined; 3 alone (left out)
  writeBytes(dir + "/a.ply",
             "ply\nformat ascii 1.0\nelement vertex 6\nproperty double x\nproperty double y\n"
             "property double z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
             "element edge 3\nproperty int vertex1\nproperty int vertex2\nend_header\n"
             "0 0 0 255 0 0\n0 1 0 255 0 0\n0 2 0 255 0 0\n5 5 5 0 0 0\n1 0 0 0 128 0\n"
             "1 1 0 0 128 0\n0 1\n2 1\n4 5\n");
  const PlyStrands p = readPlyStrands(dir + "/a.ply", kLimit);
  ASSERT_EQ(p.hair.segments, (std::vector<std::uint32_t>{2, 1}));
  EXPECT_EQ(p.skippedStrands, 1u);
  ASSERT_EQ(p.hair.colors.size(), 15u);
  EXPECT_FLOAT_EQ(p.hair.colors[0], 1.0f);
  EXPECT_NEAR(p.hair.colors[10], 0.2158605f, 1e-5f) << "8-bit sRGB 128, linear";
  EXPECT_EQ(p.hair.points[9], 1.0f);
}

TEST(PlyStrands, CountsOfSegments) {
  const std::string dir = test::scratchDir();
  writeBytes(dir + "/s.ply",
             "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
             "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
             "element strand 1\nproperty ushort segment_count\nend_header\n"
             "0 0 0\n0 1 0\n0 2 0\n0 3 0\n3 0 1 2\n3\n");
  const PlyStrands p = readPlyStrands(dir + "/s.ply", kLimit);
  EXPECT_EQ(p.hair.segments, (std::vector<std::uint32_t>{3}));
}

// Every malformed variant is one clhair::Error line that names the file.
TEST(PlyStrands, MalformedFilesAreOneErrorLine) {
  const std::string dir = test::scratchDir();
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement strand 1\nproperty uint vertex_count\nend_header\n";
  std::string truncated = binaryPly(false);
  truncated.resize(truncated.size() - 10);
  const struct {
    const char* name;
    std::string bytes;
    const char* says;
  } cases[] = {
      {"signature", "plx\nformat ascii 1.0\nend_header\n", "signature"},
      {"no end", "ply\nformat ascii 1.0\nelement vertex 3\n", "end_header"},
      {"format", "ply\nformat binary_middle_endian 1.0\nend_header\n", "unknown format"},
      {"keyword", "ply\nformat ascii 1.0\nvertex 3\nend_header\n", "unknown header keyword"},
      {"type", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n",
       "unknown type"},
      {"no xyz", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n",
       "x, y and z"},
      {"mesh",
       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n0 0 0\n",
       "neither"},
      {"truncated", truncated, "truncated"},
      {"ascii short", head + "0 0 0\n0 1 0\n", "truncated"},
      {"disagree", head + "0 0 0\n0 1 0\n0 2 0\n4\n", "add up"},
      {"nan", head + "0 0 0\nnan 1 0\n0 2 0\n3\n", "finite"},
      {"not a number", head + "0 0 0\nx 1 0\n0 2 0\n3\n", "not a number"},
      {"huge",
       "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n"
       "property float x\nproperty float y\nproperty float z\nelement strand 1\n"
       "property uint vertex_count\nend_header\n" +
           std::string(64, '\0'),
       "truncated"},
      {"far edge",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nelement edge 1\nproperty int vertex1\nproperty int vertex2\n"
       "end_header\n0 0 0\n0 1 0\n0 2 0\n0 2\n",
       "consecutive"},
      {"edge range",
       "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
       "property float z\nelement edge 1\nproperty int vertex1\nproperty int vertex2\n"
       "end_header\n0 0 0\n0 1 0\n1 7\n",
       "vertices"},
      {"single points",
       head.substr(0, head.find("element strand")) +
           "element strand 3\nproperty uint vertex_count\nend_header\n"
           "0 0 0\n0 1 0\n0 2 0\n1\n1\n1\n",
       "nothing to draw"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir + "/bad.ply";
    writeBytes(path, c.bytes);
    try {
      readPlyStrands(path, kLimit);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
      EXPECT_EQ(m.rfind(path, 0), 0u) << m;
      EXPECT_NE(m.find(c.says), std::string::npos) << m;
    }
  }
  // the byte limit (the device's largest allocation) before anything is allocated
  writeBytes(dir + "/b.ply", binaryPly(false));
  EXPECT_THROW(readPlyStrands(dir + "/b.ply", 64), Error);
}

// An element of 2^40 entries without properties costs no bytes and no time: skipped in one
// step wherever it stands (the fuzz seeds bad_empty_element_2e40*.ply, read as they are).
TEST(PlyStrands, ElementWithoutPropertiesIsSkippedWhole) {
  for (const char* seed : {"bad_empty_element_2e40.ply", "bad_empty_element_2e40_ascii.ply"}) {
    SCOPED_TRACE(seed);
    const PlyStrands p =
        readPlyStrands(test::sourceDir() + "/tests/fuzz/corpus/ply/" + seed, kLimit);
    EXPECT_EQ(p.hair.segments, (std::vector<std::uint32_t>{1}));
    ASSERT_EQ(p.hair.points.size(), 6u);
    EXPECT_EQ(p.hair.points[4], 1.0f);
  }
}

// A file cut anywhere after its header says it is cut short ("truncated"), in both formats;
// a file of the signature alone says nothing follows it.
TEST(PlyStrands, EveryCutAfterTheHeaderSaysTruncated) {
  const std::string dir = test::scratchDir();
  const std::string ascii =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement strand 1\nproperty uint vertex_count\nend_header\n"
      "0.25 0.5 0.75\n0.25 1.5 0.75\n0.25 2.5 0.75\n3\n";
  for (const std::string& whole : {binaryPly(false), binaryPly(true), ascii}) {
    const std::size_t data = whole.find("end_header\n") + 11;
    for (std::size_t cut = data; cut < whole.size(); ++cut) {
      SCOPED_TRACE(cut);
      writeBytes(dir + "/cut.ply", whole.substr(0, cut));
      if (cut + 1 == whole.size() && whole.back() == '\n') continue;  // only the last newline
      const std::string m = test::errorOf([&] { readPlyStrands(dir + "/cut.ply", kLimit); });
      EXPECT_NE(m.find("truncated"), std::string::npos) << m;
    }
  }
  writeBytes(dir + "/sig.ply", "ply");
  const std::string m = test::errorOf([&] { readPlyStrands(dir + "/sig.ply", kLimit); });
  EXPECT_NE(m.find("ends after its PLY signature"), std::string::npos) << m;
  EXPECT_EQ(m.find("not the PLY signature"), std::string::npos) << m;
}

TEST(PlyStrands, Ct2HairBinSkipsNonFiniteStrands) {
  const std::string dir = test::scratchDir();
  std::string s = u32(3);
  auto strand = [&](int n, float bad) {
    s += u32(static_cast<std::uint32_t>(n));
    for (int k = 0; k < n; ++k)
      for (float v : {k == 1 ? bad : 0.0f, static_cast<float>(k), 1.0f, 0.f, 0.f, 0.f, 5.f})
        s += f32(v);
  };
  strand(4, 0.5f);
  strand(3, std::numeric_limits<float>::quiet_NaN());
  strand(2, 0.25f);
  writeBytes(dir + "/c.bin", s);
  const PlyStrands p = readCt2HairBin(dir + "/c.bin", kLimit);
  EXPECT_EQ(p.hair.segments, (std::vector<std::uint32_t>{3, 1}));
  EXPECT_EQ(p.skippedStrands, 1u);
  EXPECT_EQ(p.hair.points[3], 0.5f);
  // through the strand-file loader too
  const StrandGroom g = loadStrandGroom(dir + "/c.bin", kLimit);
  EXPECT_EQ(g.pointCounts, (std::vector<std::uint32_t>{4, 2}));
  s.resize(s.size() - 3);
  writeBytes(dir + "/t.bin", s);
  EXPECT_THROW(readCt2HairBin(dir + "/t.bin", kLimit), Error);
}

// export-strands writes PLY, and what it wrote reads back point for point.
TEST(PlyStrands, RoundTripThroughExportStrands) {
  const std::string dir = test::scratchDir();
  const std::string mesh = test::assetPath("grooms/tiny.hairmesh.json");
  test::CommandResult a =
      test::runCli("export-strands " + test::quote(mesh) + " -o " + test::quote(dir + "/t.hair"));
  ASSERT_EQ(a.exitCode, 0) << a.output;
  test::CommandResult b =
      test::runCli("export-strands " + test::quote(mesh) + " -o " + test::quote(dir + "/t.ply"));
  ASSERT_EQ(b.exitCode, 0) << b.output;
  const CyHair h = readCyHair(dir + "/t.hair", kLimit);
  const PlyStrands p = readPlyStrands(dir + "/t.ply", kLimit);
  EXPECT_EQ(p.hair.segments, h.segments);
  EXPECT_EQ(p.hair.points, h.points);
  ASSERT_EQ(p.hair.colors.size(), h.colors.size());
  for (std::size_t i = 0; i < h.colors.size(); ++i)
    EXPECT_NEAR(p.hair.colors[i], h.colors[i], 0.01f) << i;  // 8-bit sRGB
  // and again from the PLY file itself
  test::CommandResult c = test::runCli("export-strands " + test::quote(dir + "/t.ply") + " -o " +
                                       test::quote(dir + "/u.ply"));
  ASSERT_EQ(c.exitCode, 0) << c.output;
  const PlyStrands q = readPlyStrands(dir + "/u.ply", kLimit);
  EXPECT_EQ(q.hair.points.size(), p.hair.points.size());
  // a broken PLY file in a scene: one error line, exit status 1
  writeBytes(dir + "/bad.ply", "ply\nformat ascii 1.0\nelement vertex 2\nend_header\n");
  writeBytes(dir + "/s.json", "{\"grooms\": [{\"strands_file\": \"bad.ply\"}]}");
  test::CommandResult r =
      test::runCli("render " + test::quote(dir + "/s.json") + " -o " + test::quote(dir + "/x.png"));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_EQ(r.output.find("clhair: error:"), r.output.rfind("clhair: error:")) << r.output;
  EXPECT_NE(r.output.find("bad.ply"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace clhair
