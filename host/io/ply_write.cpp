// ply_write.cpp — writing strands as binary little-endian PLY (layout in ply_strands.h):
// what export-strands writes for `-o F.ply`, read back by readPlyStrands.
#include <algorithm>
#include <cmath>

#include "clhair/error.h"
#include "io/binary_file.h"
#include "io/json_util.h"
#include "io/ply_strands.h"

namespace clhair {

namespace {

unsigned char linearToSrgb8(float c) {
  c = std::min(std::max(c, 0.0f), 1.0f);
  const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
  return static_cast<unsigned char>(std::lround(s * 255.0f));
}

}  // namespace

void writePlyStrands(const CyHair& h, const std::string& path) {
  std::uint64_t points = 0;
  for (std::uint32_t s : h.segments) points += std::uint64_t(s) + 1;
  if (h.points.size() != 3 * points)
    throw Error(path + ": point array does not match the segment counts");
  const bool colours = !h.colors.empty();
  if (colours && h.colors.size() != 3 * points)
    throw Error(path + ": colour array does not match the points");
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment clhair export-strands\n";
  out += "element vertex " + std::to_string(points) + "\n";
  out += "property float x\nproperty float y\nproperty float z\n";
  if (colours) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  out += "element strand " + std::to_string(h.segments.size()) + "\n";
  out += "property uint segment_count\nend_header\n";
  out.reserve(out.size() + points * (colours ? 15 : 12) + 4 * h.segments.size());
  for (std::uint64_t i = 0; i < points; ++i) {
    for (int c = 0; c < 3; ++c) appendF32(out, h.points[3 * i + c]);
    if (colours)
      for (int c = 0; c < 3; ++c)
        out.push_back(static_cast<char>(linearToSrgb8(h.colors[3 * i + c])));
  }
  for (std::uint32_t s : h.segments) appendU32(out, s);
  writeTextAtomically(path, out);
}

}  // namespace clhair
