// lod_defaults.cpp — the segment budget (a safety limit) and LOD's λ by image size
// (clhair/scene.h).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "clhair/scene.h"

namespace clhair {

std::uint64_t defaultSegmentBudget(int width, int height) {
  const double pixels = static_cast<double>(std::max(width, 0)) * std::max(height, 0);
  const double scaled = static_cast<double>(kBudgetSegmentsPerPixel) * pixels;
  return std::max(kDefaultSegmentBudget, static_cast<std::uint64_t>(std::min(
                                             scaled, static_cast<double>(kMaxSegmentBudget))));
}

float lodResolutionScale(int height) {
  return std::max(1.0f, static_cast<float>(height) / static_cast<float>(kLodReferenceHeight));
}

}  // namespace clhair
