// cyhair.h — Cem Yuksel's cyHair `.hair` strand format.
//
// Layout (little endian): a 128-byte header — "HAIR", strand count, point count, array
// flags (1 segments, 2 points, 4 thickness, 8 transparency, 16 colour), default segment
// count, default thickness, default transparency, default colour (3 floats), 88 bytes of
// text — then, in this order and only when flagged: uint16 segments per strand, float xyz
// per point, float thickness per point, float transparency per point, float rgb per point.
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
};

// Writes atomically; the segments array is omitted when every strand has the same count.
void writeCyHair(const CyHair& hair, const std::string& path);

}  // namespace clhair
