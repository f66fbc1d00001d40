// diffusion_field.h — light that goes round a strand file's groom: the light its fibres
// scatter, diffused through the groom's volume on the AO field's density grid.
//
// Fibres that absorb little (a file colour of red 1) pass light on until it leaves the groom,
// wherever it entered: the side away from a light glows almost as much as the side facing
// it. Dual scattering (hair_dual.h) reads only the light's own ray through the deep opacity
// map and cannot bring light around the groom (DESIGN.md, "Hair the colour of hair"). Here
// the groom is a participating medium on the AO field's grid (extinction = fibre length times
// diameter per volume, the head as opaque voxels):
// - each light's uncollided light reaches every voxel through the grid (march toward the
//   light, exp(-optical depth), zero through an opaque voxel);
// - what the fibres there scatter is the source of a diffusion equation
//   -div(D grad phi) + sigma_a phi = sigma_s phi_0, D = 1 / (3 (sigma_a + sigma_s (1 - g))),
//   sigma_s = albedo sigma_t, sigma_a = (1 - albedo) sigma_t, per channel, over the voxels
//   with hair; light leaves through a face to an empty or opaque voxel at 0.3 of Marshak's
//   rate for an isotropic medium (measured: diffusion_field.cpp, kLeak);
// - a fibre in the scattered light, taken as isotropic (phi / 4 pi), sends albedo phi / 4 pi
//   toward the eye; voxels beside the hair take their hair neighbours' mean, so lookups at
//   the groom's surface do not blend with zero.
// Left out: the fibres' alignment (light keeps its direction along the hair; the leak
// constant stands for it), a colour per voxel (the groom's mean file colour is the albedo),
// lights without a map, and the ambient light (dual scattering's probe term keeps it).
// The shading then takes, for the lights, the unscattered light through the map plus this,
// instead of dual scattering's estimates (shade.cl).
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "groom/ao_field.h"

namespace clhair {

struct DiffusionLight {
  bool point = false;
  glm::vec3 at{0.0f};        // object space: a point light's position, or the direction to it
  glm::vec3 radiance{0.0f};  // colour times intensity (linear RGB)
};

// Per voxel of `d`'s grid (x fastest): the radiance a fibre of `albedo` there sends toward
// the eye from the light its neighbours scattered. `worldPerObject` scales object lengths to
// world lengths (a point light's falloff is in world units, as the shading's). `g` is the
// mean cosine of a fibre's scattering.
std::vector<glm::vec3> diffuseGroomLight(const AoDensity& d, glm::vec3 albedo,
                                         const std::vector<DiffusionLight>& lights,
                                         float worldPerObject, float g = 0.4f,
                                         int iterations = 400);

}  // namespace clhair
