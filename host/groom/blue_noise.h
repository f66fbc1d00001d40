// blue_noise.h — progressive blue-noise root sample sets (Bhokare §3.3).
//
// Weighted sample elimination (Yuksel 2015) reduces 5N uniform candidates to N samples;
// repeating it on the survivors for N/2, N/4, ... orders them so that every prefix of the
// set is itself blue noise, which is what strand LOD needs: drawing the first N_LOD roots
// of a bundle keeps an even distribution. The quad set covers [0,1]^2; the triangle set is
// generated in the half s + t < 1 and mapped to (s / (1 - t), t) so bilinear interpolation
// of a triangle stored as a quad with a repeated corner is barycentric.
// Deterministic: the same size and seed give the same set on every machine.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

namespace clhair {

struct RootSets {
  std::vector<glm::vec2> quad;
  std::vector<glm::vec2> triangle;  // already mapped to bilinear (s, t)
  std::uint32_t size() const { return static_cast<std::uint32_t>(quad.size()); }
};

// Progressive blue-noise set of `count` samples in [0,1]^2 (triangle: in s + t < 1, not
// yet mapped).
std::vector<glm::vec2> progressiveBlueNoise(std::uint32_t count, bool triangle, std::uint32_t seed);

// Both sets with `count` samples each.
RootSets makeRootSets(std::uint32_t count, std::uint32_t seed = 0x9e3779b9u);

}  // namespace clhair
