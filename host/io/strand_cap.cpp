// strand_cap.cpp — the per-asset strand cap with thickness compensation (scene.h,
// capStrands): fewer strands, each wider by the ratio, so the groom's coverage holds.
#include <algorithm>
#include <cstdint>

#include "clhair/scene.h"

namespace clhair {

namespace {

// Widens the fibres of `look` by k: width, and the minimum hit diameter up to the raster's
// 3-pixel cap (CLH_MAX_HIT_DIAMETER).
void widen(AppearanceParams& look, float k) {
  look.strandWidth *= k;
  look.minHitDiameterPx = std::min(look.minHitDiameterPx * k, 3.0f);
}

}  // namespace

float capStrands(HairMesh& mesh, std::uint64_t cap) {
  if (cap == 0 || mesh.strandCount <= 0 || static_cast<std::uint64_t>(mesh.strandCount) <= cap)
    return 1.0f;
  const float k = static_cast<float>(static_cast<double>(mesh.strandCount) / cap);
  mesh.strandCount = static_cast<std::int64_t>(cap);
  widen(mesh.appearance, k);
  return k;
}

float capStrands(StrandGroom& groom, std::uint64_t cap) {
  const std::uint64_t n = groom.pointCounts.size();
  if (cap == 0 || n <= cap) return 1.0f;
  const float k = static_cast<float>(static_cast<double>(n) / cap);
  std::vector<std::uint64_t> first(n + 1, 0);
  for (std::uint64_t s = 0; s < n; ++s) first[s + 1] = first[s] + groom.pointCounts[s];
  StrandGroom out;
  out.name = groom.name;
  out.seed = groom.seed;
  out.appearance = groom.appearance;
  out.lod = groom.lod;
  out.children = groom.children;
  for (std::uint64_t j = 0; j < cap; ++j) {
    // strand floor((j + 1/2) n / cap): evenly spread over the file's order
    const std::uint64_t s = std::min<std::uint64_t>((2 * j + 1) * n / (2 * cap), n - 1);
    out.pointCounts.push_back(groom.pointCounts[s]);
    out.points.insert(out.points.end(), groom.points.begin() + first[s],
                      groom.points.begin() + first[s + 1]);
    if (!groom.thickness.empty())
      for (std::uint64_t i = first[s]; i < first[s + 1]; ++i)
        out.thickness.push_back(groom.thickness[i] * k);
    if (!groom.colors.empty())
      out.colors.insert(out.colors.end(), groom.colors.begin() + first[s],
                        groom.colors.begin() + first[s + 1]);
    if (!groom.transparency.empty())
      out.transparency.insert(out.transparency.end(), groom.transparency.begin() + first[s],
                              groom.transparency.begin() + first[s + 1]);
    if (!groom.rootUv.empty()) out.rootUv.push_back(groom.rootUv[s]);
  }
  widen(out.appearance, k);
  groom = std::move(out);
  return k;
}

}  // namespace clhair
