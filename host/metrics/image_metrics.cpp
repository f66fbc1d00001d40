// image_metrics.cpp — PSNR/RMSE on display values, the combined comparison and the error-map
// image (see image_metrics.h).
#include "metrics/image_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "clhair/error.h"
#include "metrics/colormap.h"

namespace clhair {

namespace {

float srgbToLinear(float x) {
  return x <= 0.04045f ? x / 12.92f : std::pow((x + 0.055f) / 1.055f, 2.4f);
}

std::string sizeText(const Image& img) {
  return std::to_string(img.width) + "x" + std::to_string(img.height);
}

}  // namespace

double linearToSrgbClamped(double x) {
  x = std::isnan(x) ? 0.0 : std::min(std::max(x, 0.0), 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

void requireSameSize(const Image& a, const Image& b, const std::string& nameA,
                     const std::string& nameB) {
  if (a.width != b.width || a.height != b.height)
    throw Error(nameA + " is " + sizeText(a) + " but " + nameB + " is " + sizeText(b) +
                "; images must have the same size to be compared");
  if (a.width <= 0 || a.height <= 0) throw Error(nameA + " is empty; nothing to compare");
}

PsnrResult computePsnr(const Image& reference, const Image& test, const std::vector<char>* mask) {
  requireSameSize(reference, test, "the reference", "the test image");
  const std::size_t pixels = static_cast<std::size_t>(reference.width) * reference.height;
  if (mask && mask->size() != pixels)
    throw Error("PSNR mask has " + std::to_string(mask->size()) + " entries for " +
                std::to_string(pixels) + " pixels");
  double sum = 0.0;
  std::size_t counted = 0;
  for (std::size_t p = 0; p < pixels; ++p) {
    if (mask && !(*mask)[p]) continue;
    ++counted;
    for (int c = 0; c < 3; ++c) {
      double d = linearToSrgbClamped(reference.rgba[p * 4 + c]) -
                 linearToSrgbClamped(test.rgba[p * 4 + c]);
      sum += d * d;
    }
  }
  PsnrResult r;
  r.mse = counted > 0 ? sum / static_cast<double>(counted * 3) : 0.0;
  r.rmse = std::sqrt(r.mse);
  r.psnrDb = r.mse > 0.0 ? 10.0 * std::log10(1.0 / r.mse) : std::numeric_limits<double>::infinity();
  return r;
}

ImageComparison compareImages(const Image& reference, const Image& test, double pixelsPerDegree) {
  ImageComparison c;
  c.psnr = computePsnr(reference, test);
  c.flip = computeFlip(reference, test, pixelsPerDegree);
  const std::size_t pixels = std::min(reference.rgba.size(), test.rgba.size()) / 4;
  std::size_t within = 0;
  for (std::size_t i = 0; i < pixels; ++i) {
    double worst = 0.0;
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, std::abs(linearToSrgbClamped(reference.rgba[i * 4 + k]) -
                                       linearToSrgbClamped(test.rgba[i * 4 + k])));
    within += worst <= 1.0 / 255.0 + 1e-4;
  }
  c.withinOneCode = pixels ? static_cast<double>(within) / static_cast<double>(pixels) : 1.0;
  c.pixelsPerDegree = pixelsPerDegree;
  return c;
}

Image flipErrorImage(const FlipResult& flip, bool magma) {
  Image img;
  img.width = flip.width;
  img.height = flip.height;
  img.rgba.resize(flip.error.size() * 4);
  for (std::size_t i = 0; i < flip.error.size(); ++i) {
    float* px = &img.rgba[i * 4];
    if (magma) {
      std::array<float, 3> c = magmaSrgb(flip.error[i]);
      for (int k = 0; k < 3; ++k) px[k] = srgbToLinear(c[k]);
    } else {
      px[0] = px[1] = px[2] = flip.error[i];
    }
    px[3] = 1.0f;
  }
  return img;
}

}  // namespace clhair
