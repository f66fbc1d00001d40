// colour_difference.h — the mean colour of an image's hair and its distance to another's, as
// a viewer would compare them: the mean of the masked pixels' 8-bit sRGB values, CIELAB
// (D65 white), CIE76 ΔE and chroma. Used by the look benchmark and the tests of colour.
#pragma once

#include <array>
#include <vector>

#include "clhair/image.h"

namespace clhair {

// CIELAB (D65 white) of an sRGB colour given 0..255 per channel.
std::array<double, 3> srgbToLab(const std::array<double, 3>& srgb);
// CIE76 distance between two sRGB colours (0..255 per channel).
double deltaE(const std::array<double, 3>& a, const std::array<double, 3>& b);
// CIELAB chroma of an sRGB colour (0..255 per channel).
double chroma(const std::array<double, 3>& srgb);
// The mean 8-bit sRGB colour of the pixels where mask is non-zero (one per pixel).
std::array<double, 3> meanSrgb(const Image& img, const std::vector<char>& mask);

}  // namespace clhair
