// synthetic_groom.h — a stored-strand groom built in the tests: `strands` wavy strands
// over a sphere cap with fixed seeds, point counts cycling through values around the
// strand kernel's lane and round boundaries (2 and 3 points, runs that are not multiples
// of 32, strands longer than one 128-segment round).
#pragma once

#include <cmath>
#include <cstdint>
#include <iterator>
#include <random>

#include <glm/geometric.hpp>

#include "clhair/strand_groom.h"
#include "io/cyhair.h"

namespace clhair::test {

inline StrandGroom syntheticGroom(std::size_t strands) {
  static const std::uint32_t kCounts[] = {2,  3,   4,   5,   9,   17,  31,  33, 64,
                                          65, 100, 129, 130, 131, 200, 258, 300};
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  StrandGroom g;
  g.name = "synthetic";
  g.lod.morphWindow = 0.5f;
  for (std::size_t s = 0; s < strands; ++s) {
    const std::uint32_t n = kCounts[s % std::size(kCounts)];
    const float theta = 2.0f * 3.14159265f * u01(rng), phi = 0.6f * u01(rng);
    const glm::vec3 dir(std::sin(phi) * std::cos(theta), std::cos(phi),
                        std::sin(phi) * std::sin(theta));
    const glm::vec3 side = glm::normalize(glm::cross(dir, glm::vec3(0.3f, 0.1f, 1.0f)));
    const float phase = 6.283f * u01(rng);
    g.pointCounts.push_back(n);
    for (std::uint32_t k = 0; k < n; ++k) {
      const float t = static_cast<float>(k) / static_cast<float>(n - 1);
      g.points.push_back(0.1f * dir + 0.15f * t * dir + 0.01f * std::sin(12.0f * t + phase) * side +
                         glm::vec3(0.0f, -0.05f * t * t, 0.0f));
    }
  }
  return g;
}

// The strands of `s` as a cyHair file's contents, every strand `width` thick.
inline CyHair toCyHair(const StrandSet& s, float width) {
  CyHair h;
  for (std::uint32_t c : s.pointCounts) h.segments.push_back(c - 1);
  h.points = s.points;
  h.defaultThickness = width;
  h.info = "clhair tests";
  return h;
}

}  // namespace clhair::test
