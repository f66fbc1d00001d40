// colour_difference.cpp — see colour_difference.h.
#include "metrics/colour_difference.h"

#include <algorithm>
#include <cmath>

#include "metrics/image_metrics.h"

namespace clhair {

// CIELAB (D65 white) of an sRGB colour given 0..255 per channel.
std::array<double, 3> srgbToLab(const std::array<double, 3>& srgb) {
  double lin[3];
  for (int c = 0; c < 3; ++c) {
    const double v = srgb[c] / 255.0;
    lin[c] = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
  }
  const double x = (0.4124564 * lin[0] + 0.3575761 * lin[1] + 0.1804375 * lin[2]) / 0.95047;
  const double y = 0.2126729 * lin[0] + 0.7151522 * lin[1] + 0.0721750 * lin[2];
  const double z = (0.0193339 * lin[0] + 0.1191920 * lin[1] + 0.9503041 * lin[2]) / 1.08883;
  auto f = [](double t) {
    return t > 216.0 / 24389.0 ? std::cbrt(t) : (24389.0 / 27.0 * t + 16.0) / 116.0;
  };
  return {116.0 * f(y) - 16.0, 500.0 * (f(x) - f(y)), 200.0 * (f(y) - f(z))};
}

double deltaE(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  const std::array<double, 3> la = srgbToLab(a), lb = srgbToLab(b);
  return std::sqrt((la[0] - lb[0]) * (la[0] - lb[0]) + (la[1] - lb[1]) * (la[1] - lb[1]) +
                   (la[2] - lb[2]) * (la[2] - lb[2]));
}

double chroma(const std::array<double, 3>& srgb) {
  const std::array<double, 3> l = srgbToLab(srgb);
  return std::sqrt(l[1] * l[1] + l[2] * l[2]);
}

// The mean 8-bit sRGB colour of the masked pixels (as a viewer's picker would average them).
std::array<double, 3> meanSrgb(const Image& img, const std::vector<char>& mask) {
  std::array<double, 3> sum{0.0, 0.0, 0.0};
  std::size_t n = 0;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    ++n;
    for (int c = 0; c < 3; ++c)
      sum[c] += std::round(255.0 * linearToSrgbClamped(img.rgba[4 * i + c]));
  }
  for (double& v : sum) v /= static_cast<double>(std::max<std::size_t>(n, 1));
  return sum;
}

}  // namespace clhair
