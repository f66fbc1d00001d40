// visibility.h — a groom's baked spherical visibility (Kulikov 2025, "precomputed
// self-shadowing"): per cell of the G-buffer's styling codes (u, v, w: root uv and position
// along the strand), the mean number of scattering events toward every direction as four
// real L1 SH coefficients (kernels/include/clhair/visibility_sh.h). Written by `clhair
// bake-visibility`, referenced from a scene's groom entry ("visibility", docs/scene-format.md)
// and looked up by shade.cl for every light without a deep opacity map.
//
// File (.clhvis, little-endian; docs/scene-format.md, "Baked visibility"):
//   bytes  0..7   magic "CLHVIS01"
//          8..11  u32 version, 1
//         12..15  u32 cells per axis, 64
//         16..19  u32 coefficients per cell, 4
//         20..23  u32 strands of the groom it was baked for (checked against the groom)
//         24..27  u32 rays per sample point
//         28..31  u32 most sample points per cell
//         32..35  f32 HAIR_MAX_SCATTER_EVENTS (the miss bias), 5
//         36..39  u32 reserved, 0
//         40..    64^3 cells x 4 f32, cell (u, v, w) at index (u * 64 + v) * 64 + w
// A file is read whole or refused with one line: wrong magic or version, wrong size
// (truncated or trailing bytes), a non-finite or absurd coefficient.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace clhair {

struct VisibilityBake {
  std::uint32_t strands = 0;  // full-detail strands of the groom it belongs to
  std::uint32_t raysPerPoint = 0;
  std::uint32_t pointsPerCell = 0;
  float maxScatterEvents = 5.0f;
  std::vector<float> sh;  // 4 per cell, CLH_VIS_CELLS cells
};

// Largest |coefficient| a file may hold: a ray counts at most 32 events (the bake's
// kMaxEventsLimit), so |c_i| <= 4 pi * 0.49 * 32 ~ 197; the bound leaves room and catches
// garbage.
constexpr float kMaxVisibilityCoefficient = 1000.0f;
constexpr std::uint32_t kVisibilityHeaderBytes = 40;

VisibilityBake readVisibility(const std::string& path);
// Written to a temporary file and renamed into place. Throws on an inconsistent bake.
void writeVisibility(const VisibilityBake& bake, const std::string& path);

}  // namespace clhair
