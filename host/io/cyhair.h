// cyhair.h — Cem Yuksel's cyHair `.hair` strand format.
//
// Layout (little endian): a 128-byte header — "HAIR", strand count, point count, array
// flags (1 segments, 2 points, 4 thickness, 8 transparency, 16 colour), default segment
// count, default thickness, default transparency, default colour (3 floats), 88 bytes of
// text — then, in this order and only when flagged: uint16 segments per strand, float xyz
// per point, float thickness per point, float transparency per point, float rgb per point.
// When the segments array is absent every strand has the default segment count.
//
// Reading (cyhair_read.cpp) trusts nothing in the header: sizes are checked against the
// file size and a caller's byte limit before anything is allocated, every float must be
// finite, and the segment counts must add up to the point count. Strands of 0 segments (a
// single point) are legal in the format and kept. Bytes after the last array are ignored,
// as Yuksel's own loader does, and counted in `trailingBytes` so that a caller can warn.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace clhair {

struct CyHair {
  std::vector<std::uint32_t> segments;  // per strand (points = segments + 1)
  std::vector<float> points;            // xyz
  std::vector<float> thickness;         // per point, or empty (default used)
  std::vector<float> transparency;      // per point, or empty
  std::vector<float> colors;            // rgb per point, or empty
  float defaultThickness = 1.0f;
  float defaultTransparency = 0.0f;
  float defaultColor[3] = {1.0f, 1.0f, 1.0f};
  std::string info;
  std::uint64_t trailingBytes = 0;  // read: bytes after the last array (not written)
};

inline std::uint64_t strandCount(const CyHair& hair) { return hair.segments.size(); }
inline std::uint64_t pointCount(const CyHair& hair) { return hair.points.size() / 3; }

// Writes atomically; the segments array is omitted when every strand has the same count.
void writeCyHair(const CyHair& hair, const std::string& path);

// Reads a `.hair` file. Throws clhair::Error, one line naming the file, when it is shorter
// than its header, has the wrong signature, no points array, zero strands, unknown flag
// bits, truncated arrays, segment counts that do not add up to the point count, a
// non-finite float, or arrays that would take more than `maxBytes` in memory (as CyHair
// holds them: 4 bytes per strand, 12/4/4/12 bytes per point for points, thickness,
// transparency, colours). Pass the device's largest allocation as `maxBytes`.
CyHair readCyHair(const std::string& path, std::uint64_t maxBytes);

}  // namespace clhair
