// test_ply_layouts.cpp — PLY strand files as the scan tools write them (host/io/ply_read.cpp,
// ply_layout.cpp): hapPLY's header copied byte for byte with vertex (x, y, z float; red,
// green, blue uchar), strand (ushort nsegs) and edge (int vertex1, vertex2) in one file, and
// the two single-element layouts. Each reads to the same strands and renders the same image,
// byte for byte, as the same strands in a cyHair file; the count's usual names and integer
// types read alike; float colours are linear. Each layout's broken twin is one error line.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "clhair/error.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "io/cyhair.h"
#include "io/ply_strands.h"
#include "test_util.h"

namespace clhair {
namespace {

constexpr std::uint64_t kLimit = 1ull << 30;
constexpr int kStrands = 40;
constexpr int kPoints = 8;  // per strand

void writeBytes(const std::string& path, const std::string& data) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << data;
}

template <typename T>
std::string le(T v) {  // little-endian bytes (the hosts the tests run on are little endian)
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  return std::string(b, sizeof(T));
}

// The strands: kStrands hanging strands of kPoints points (metres), 8-bit sRGB colours that
// change along each strand and from strand to strand.
struct Strands {
  std::vector<float> xyz;
  std::vector<unsigned char> rgb;
};

Strands sampleStrands() {
  Strands s;
  for (int i = 0; i < kStrands; ++i)
    for (int k = 0; k < kPoints; ++k) {
      const float a = 0.157f * static_cast<float>(i);
      s.xyz.insert(s.xyz.end(), {0.08f * std::cos(a) + 0.002f * static_cast<float>(k),
                                 0.1f - 0.025f * static_cast<float>(k), 0.08f * std::sin(a)});
      s.rgb.insert(s.rgb.end(), {static_cast<unsigned char>(200 - 10 * k),
                                 static_cast<unsigned char>(150 + i), 60});
    }
  return s;
}

enum class Layout { StrandAndEdge, StrandOnly, EdgeOnly };

// hapPLY's header, as its writer puts it (binary little endian, its comment line, elements
// and properties in the order they were added), then the data.
std::string happlyFile(const Strands& s, Layout layout) {
  const int V = kStrands * kPoints, E = kStrands * (kPoints - 1);
  std::string h =
      "ply\nformat binary_little_endian 1.0\n"
      "comment Written with hapPLY (https://github.com/nmwsharp/happly)\n"
      "element vertex " +
      std::to_string(V) +
      "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\n"
      "property uchar green\nproperty uchar blue\n";
  if (layout != Layout::EdgeOnly)
    h += "element strand " + std::to_string(kStrands) + "\nproperty ushort nsegs\n";
  if (layout != Layout::StrandOnly)
    h += "element edge " + std::to_string(E) + "\nproperty int vertex1\nproperty int vertex2\n";
  h += "end_header\n";
  for (int v = 0; v < V; ++v) {
    for (int c = 0; c < 3; ++c) h += le(s.xyz[3 * v + c]);
    for (int c = 0; c < 3; ++c) h += static_cast<char>(s.rgb[3 * v + c]);
  }
  if (layout != Layout::EdgeOnly)
    for (int i = 0; i < kStrands; ++i) h += le(static_cast<std::uint16_t>(kPoints - 1));
  if (layout != Layout::StrandOnly)
    for (int i = 0; i < kStrands; ++i)
      for (int k = 0; k + 1 < kPoints; ++k)
        h += le(std::int32_t{i * kPoints + k}) + le(std::int32_t{i * kPoints + k + 1});
  return h;
}

float srgbToLinear(unsigned char c8) {  // IEC 61966-2-1
  const double c = c8 / 255.0;
  return static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

CyHair cyHairOf(const Strands& s) {
  CyHair h;
  h.segments.assign(kStrands, kPoints - 1);
  h.points = s.xyz;
  for (unsigned char c : s.rgb) h.colors.push_back(srgbToLinear(c));
  h.info = "twin";
  return h;
}

Image renderFile(Renderer& r, const std::string& dir, const std::string& file) {
  writeBytes(dir + "/s.json",
             "{\"resolution\": [96, 72], \"camera\": {\"position\": [0, 0.02, 0.45], "
             "\"target\": [0, 0.02, 0], \"fov\": 40}, \"lights\": [{\"type\": \"directional\", "
             "\"direction\": [0.3, 0.8, 0.5]}], \"grooms\": [{\"strands_file\": \"" +
                 file + "\", \"appearance\": {\"strand_width\": 0.002}}]}");
  return r.render(loadScene(dir + "/s.json"), RenderOptions{}).color;
}

TEST(PlyLayouts, EachWritersLayoutRendersAsTheSameStrandsInCyHair) {
  const std::string dir = test::scratchDir();
  const Strands s = sampleStrands();
  const CyHair twin = cyHairOf(s);
  writeCyHair(twin, dir + "/twin.hair");
  Renderer r(test::sharedDevice());
  const Image want = renderFile(r, dir, "twin.hair");
  double lit = 0.0;
  for (std::size_t i = 0; i < want.rgba.size(); i += 4) lit += want.rgba[i + 3];
  ASSERT_GT(lit, 50.0) << "the strands cover some pixels";
  const char* names[] = {"strand_and_edge.ply", "strand.ply", "edge.ply"};
  for (Layout l : {Layout::StrandAndEdge, Layout::StrandOnly, Layout::EdgeOnly}) {
    const std::string name = names[static_cast<int>(l)];
    SCOPED_TRACE(name);
    writeBytes(dir + "/" + name, happlyFile(s, l));
    const PlyStrands p = readPlyStrands(dir + "/" + name, kLimit);
    EXPECT_EQ(p.hair.segments, twin.segments);
    EXPECT_EQ(p.hair.points, twin.points);
    EXPECT_EQ(p.hair.colors, twin.colors);
    const Image got = renderFile(r, dir, name);
    ASSERT_EQ(got.rgba.size(), want.rgba.size());
    EXPECT_EQ(std::memcmp(got.rgba.data(), want.rgba.data(), want.rgba.size() * sizeof(float)), 0)
        << "not byte-identical to the cyHair twin";
  }
}

// The count's usual names and every integer type from uchar to uint32; float colours linear.
TEST(PlyLayouts, CountNamesTypesAndFloatColours) {
  const std::string dir = test::scratchDir();
  const struct {
    const char* type;
    const char* name;
    int value;  // for a strand of 3 points
  } counts[] = {
      {"uchar", "nsegs", 2},        {"char", "segment_count", 2}, {"ushort", "num_segments", 2},
      {"short", "vertex_count", 3}, {"uint", "num_vertices", 3},  {"int", "num_points", 3},
      {"uint32", "point_count", 3}, {"uint8", "nverts", 3},       {"int16", "segments", 2}};
  for (const auto& c : counts) {
    SCOPED_TRACE(std::string(c.type) + " " + c.name);
    writeBytes(dir + "/c.ply",
               std::string("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                           "property float y\nproperty float z\nproperty float red\n"
                           "property float green\nproperty float blue\nelement strand 1\n"
                           "property int id\nproperty ") +
                   c.type + " " + c.name + "\nend_header\n0 0 0 0.5 0.25 1\n0 1 0 0 0 0\n" +
                   "0 2 0 1 1 1\n7 " + std::to_string(c.value) + "\n");
    const PlyStrands p = readPlyStrands(dir + "/c.ply", kLimit);
    EXPECT_EQ(p.hair.segments, (std::vector<std::uint32_t>{2}));
    ASSERT_EQ(p.hair.colors.size(), 9u);
    EXPECT_EQ(p.hair.colors[0], 0.5f) << "float colours are linear, kept as written";
    EXPECT_EQ(p.hair.colors[1], 0.25f);
  }
}

// Each layout's broken twin: one error line naming the file and what is wrong.
TEST(PlyLayouts, BrokenTwinsAreOneErrorLine) {
  const std::string dir = test::scratchDir();
  const Strands s = sampleStrands();
  const std::string both = happlyFile(s, Layout::StrandAndEdge);
  const std::string strandOnly = happlyFile(s, Layout::StrandOnly);
  const std::string edgeOnly = happlyFile(s, Layout::EdgeOnly);
  const std::size_t edgesAt = both.size() - 8u * kStrands * (kPoints - 1);
  std::string missingEdge = both;  // strand 0's first edge repeats its second: 0-1 missing
  missingEdge.replace(edgesAt, 8, le(std::int32_t{1}) + le(std::int32_t{2}));
  std::string crossingEdge = both;  // one more edge, from strand 0's tip to strand 1's root
  const std::string edgeCount = "element edge " + std::to_string(kStrands * (kPoints - 1));
  crossingEdge.replace(crossingEdge.find(edgeCount), edgeCount.size(),
                       "element edge " + std::to_string(kStrands * (kPoints - 1) + 1));
  crossingEdge += le(std::int32_t{kPoints - 1}) + le(std::int32_t{kPoints});
  std::string renamed = strandOnly;
  renamed.replace(renamed.find("nsegs"), 5, "nseg_");
  std::string floatCount = strandOnly;
  floatCount.replace(floatCount.find("ushort nsegs"), 6, "float ");
  floatCount.insert(floatCount.size() - 2 * kStrands, 2 * kStrands, '\0');
  std::string edgeProps = edgeOnly;
  edgeProps.replace(edgeProps.find("int vertex2\n"), 12, "int vertex2\nproperty int w\n");
  edgeProps.replace(edgeProps.find("vertex1"), 7, "first__");
  const struct {
    const char* name;
    std::string bytes;
    const char* says;
  } cases[] = {{"missing edge", missingEdge, "no edge joining vertices 0 and 1"},
               {"crossing edge", crossingEdge, "joins vertices 7 and 8"},
               {"unknown count name", renamed, "nsegs, segment_count"},
               {"float count", floatCount, "scalar integer"},
               {"edge without vertex1", edgeProps, "vertex1 and vertex2"}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir + "/bad.ply";
    writeBytes(path, c.bytes);
    const std::string m = test::errorOf([&] { readPlyStrands(path, kLimit); });
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_EQ(m.rfind(path, 0), 0u) << m;
    EXPECT_NE(m.find(c.says), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace clhair
