// auto_scale.h — "scale": "auto"'s rule, shared by scenes (scene_strand_groom.cpp) and
// `clhair fit-mesh --scale auto`: the factor that makes the roots' largest extent (file
// units) a human head's hair line, kAutoRootExtent metres; 1 when the roots have no extent.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include <glm/common.hpp>

#include "clhair/strand_groom.h"

namespace clhair {

constexpr float kAutoRootExtent = 0.18f;

// Grows [lo, hi] by the roots of `g` (file units).
inline void addRootBounds(const StrandGroom& g, glm::vec3& lo, glm::vec3& hi) {
  std::size_t at = 0;
  for (std::uint32_t n : g.pointCounts) {
    lo = glm::min(lo, g.points[at]);
    hi = glm::max(hi, g.points[at]);
    at += n;
  }
}

// The factor for roots spanning [lo, hi]; `extent` receives their largest extent.
inline float autoScaleFactor(const glm::vec3& lo, const glm::vec3& hi, float* extent) {
  const glm::vec3 e = hi - lo;
  *extent = std::max(e.x, std::max(e.y, e.z));
  return *extent > 0.0f ? kAutoRootExtent / *extent : 1.0f;
}

}  // namespace clhair
