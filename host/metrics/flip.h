// flip.h — LDR-FLIP, NVIDIA's perceptual image difference (Andersson, Nilsson, Akenine-Möller,
// Oskarsson, Åström and Fairchild, "FLIP: A Difference Evaluator for Alternating Images",
// Proc. ACM Comput. Graph. Interact. Tech. 3(2), 2020).
//
// Input: a reference and a test image of the same size, linear RGB as clhair::Image holds
// it (alpha is ignored). LDR-FLIP models a display, so RGB is clamped to [0, 1] first; an
// sRGB PNG read by readImage() therefore gives the same result as NVIDIA's tool on the PNG.
// Output: one error per pixel in [0, 1] (0 = no perceived difference) and their mean.
// The viewing condition enters only through pixels per degree of visual angle; 67 is the
// paper's default (a 0.7 m wide 3840-pixel monitor seen from 0.7 m).
//
// Invariants: identical inputs give exactly 0 everywhere; the metric is symmetric in its two
// inputs; image borders are handled by clamping to the edge. Validated against NVIDIA's
// flip-evaluator package (see tests/test_metrics.cpp and docs/image-metrics.md).
#pragma once

#include <vector>

#include "clhair/image.h"

namespace clhair {

inline constexpr double kFlipDefaultPpd = 67.0;
inline constexpr double kFlipMinPpd = 1.0;  // below this the feature filters vanish
inline constexpr double kFlipMaxPpd = 1000.0;

struct FlipResult {
  int width = 0;
  int height = 0;
  std::vector<float> error;  // width * height values in [0, 1], row-major, top row first
  double mean = 0.0;         // arithmetic mean of `error`

  float at(int x, int y) const { return error[static_cast<std::size_t>(y) * width + x]; }
};

// Throws clhair::Error when the sizes differ, an image is empty or ppd is outside
// [kFlipMinPpd, kFlipMaxPpd].
FlipResult computeFlip(const Image& reference, const Image& test,
                       double pixelsPerDegree = kFlipDefaultPpd);

// Pixels per degree for a monitor `monitorWidthMeters` wide with `monitorWidthPixels`
// columns seen from `distanceMeters` (the paper's viewing-condition formula).
double flipPixelsPerDegree(double distanceMeters, double monitorWidthMeters,
                           int monitorWidthPixels);

}  // namespace clhair
