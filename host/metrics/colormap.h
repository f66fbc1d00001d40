// colormap.h — a perceptually uniform colour map for error images.
//
// magmaSrgb(t) maps t in [0, 1] (clamped; NaN counts as 0) to one of 256 sRGB-encoded
// colours of the magma map, picking the nearest entry as NVIDIA's FLIP tool does, so an error
// map written by clhair has the same colours as one written by that tool.
#pragma once

#include <array>

namespace clhair {

std::array<float, 3> magmaSrgb(float t);

}  // namespace clhair
