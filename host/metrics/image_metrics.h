// image_metrics.h — comparing a rendered image against a reference: PSNR/RMSE, LDR-FLIP
// (flip.h) and an error-map image, as `clhair compare` reports them.
//
// Inputs are clhair::Image (linear RGBA, as readImage returns); alpha is ignored by every
// metric. PSNR and RMSE are computed on display values: each RGB channel clamped to [0, 1]
// and sRGB-encoded, so for 8-bit PNGs they equal the usual 8-bit figures with peak 255.
// All functions throw clhair::Error when the two images differ in size.
#pragma once

#include <string>
#include <vector>

#include "clhair/image.h"
#include "metrics/flip.h"

namespace clhair {

struct PsnrResult {
  double mse = 0.0;     // mean of squared sRGB differences over all pixels and R, G, B
  double rmse = 0.0;    // sqrt(mse), in sRGB units of [0, 1]
  double psnrDb = 0.0;  // 10 log10(1 / mse); +infinity when mse == 0
};

// With `mask` (one entry per pixel, non-zero = counted) only those pixels are compared; an
// empty mask selection gives mse 0.
PsnrResult computePsnr(const Image& reference, const Image& test,
                       const std::vector<char>* mask = nullptr);

struct ImageComparison {
  PsnrResult psnr;
  FlipResult flip;
  // Share of pixels whose largest sRGB channel difference is at most 1/255 (plus a rounding
  // allowance of 1e-4): for 8-bit images, "equal up to one code".
  double withinOneCode = 0.0;
  double pixelsPerDegree = kFlipDefaultPpd;
};

ImageComparison compareImages(const Image& reference, const Image& test,
                              double pixelsPerDegree = kFlipDefaultPpd);

// The FLIP error map as an image: with `magma` each pixel gets the magma colour of its error
// (stored linear, so a PNG holds exactly the map's sRGB colours); without, R = G = B = error
// (for float formats such as EXR, where the values themselves matter). Alpha is 1.
Image flipErrorImage(const FlipResult& flip, bool magma);

// Throws clhair::Error "<what>: A is WxH but B is WxH ..." unless the sizes match.
void requireSameSize(const Image& a, const Image& b, const std::string& nameA,
                     const std::string& nameB);

// The sRGB encoding used for the PSNR (in double), of a linear value clamped to [0, 1];
// NaN counts as 0.
double linearToSrgbClamped(double linear);

}  // namespace clhair
