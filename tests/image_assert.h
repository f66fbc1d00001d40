// image_assert.h — comparing a rendered image with an expected one under a stated
// tolerance, for golden and other image tests: EXPECT_IMAGES_NEAR / ASSERT_IMAGES_NEAR.
//
// Images are compared in display values, so one tolerance means the same for every file
// type and is as strict in the shadows as in the highlights: an 8-bit file by its sRGB codes
// (0..255 as 0..1), a float file by its linear values through the sRGB curve, continued
// above 1 as 1 + 0.44 ln(v) (the curve's slope at 1, so bright HDR values such as a sun in
// an environment map compare by their ratio). Measured over r, g and b (alpha is compared
// exactly: every clhair frame is opaque):
//   - the largest difference anywhere;
//   - the fraction of pixels with a channel differing by more than `pixelThreshold`;
//   - the RMSE;
//   - the mean signed difference of each channel (a uniform shading error moves it even when
//     every single pixel stays within the other limits: the sensitive test of a "uniform
//     error" such as a light 3 % too dim).
// On failure the expected, actual and a difference image go to the test's folder under the
// build's test-output (test::outputDir()), and the message names them. The difference image
// shows each channel's difference over pixelThreshold: mid grey at the threshold, white at
// twice it or more.
#pragma once

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "clhair/error.h"
#include "clhair/image.h"
#include "test_util.h"

namespace clhair::test {

// How the values of a compared image are encoded.
enum class ImageEncoding {
  Srgb8,   // sRGB codes / 255 (PNG)
  Linear,  // linear radiance (EXR)
};

struct StoredImage {
  Image values;  // as stored: codes / 255 for Srgb8, linear for Linear
  ImageEncoding encoding = ImageEncoding::Linear;
};

struct ImageTolerance {
  double maxDifference = 0.0;   // no channel of any pixel may differ by more
  double pixelThreshold = 0.0;  // a pixel differs when one of its channels differs by more
  double maxFraction = 0.0;     // at most this share of the pixels may differ
  double maxRmse = 0.0;         // over r, g, b of every pixel
  double maxMeanBias = 0.0;     // |mean(actual - expected)| of each of r, g, b
};

struct ImageDifference {
  double largest = 0.0;
  int largestX = 0, largestY = 0;
  double fraction = 0.0;
  double rmse = 0.0;
  double meanBias[3] = {0.0, 0.0, 0.0};
  bool alphaDiffers = false;
};

inline double srgbEncode(double linear) {
  if (linear <= 0.0) return 0.0;
  if (linear <= 0.0031308) return 12.92 * linear;
  if (linear <= 1.0) return 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
  return 1.0 + 1.055 / 2.4 * std::log(linear);
}

inline double srgbDecode(double encoded) {
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

// The display value of a stored value (see the top of this file).
inline double displayValue(double v, ImageEncoding e) {
  return e == ImageEncoding::Srgb8 ? v : srgbEncode(v);
}

// Reads an image file keeping its stored encoding: 8-bit formats as codes / 255, float
// formats as linear values (clhair::readImage would linearise the 8-bit ones).
inline StoredImage readStoredImage(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw Error(path + ": cannot read image (" + OIIO::geterror() + ")");
  const OIIO::ImageSpec spec = in->spec();
  const int channels = spec.nchannels;
  StoredImage s;
  s.encoding =
      spec.format.basetype == OIIO::TypeDesc::UINT8 ? ImageEncoding::Srgb8 : ImageEncoding::Linear;
  std::vector<float> data(static_cast<std::size_t>(spec.width) * spec.height * channels);
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, data.data()))
    throw Error(path + ": reading pixels failed (" + in->geterror() + ")");
  s.values.width = spec.width;
  s.values.height = spec.height;
  s.values.rgba.assign(static_cast<std::size_t>(spec.width) * spec.height * 4, 1.0f);
  for (std::size_t p = 0; p < static_cast<std::size_t>(spec.width) * spec.height; ++p)
    for (int c = 0; c < std::min(channels, 4); ++c)
      s.values.rgba[p * 4 + c] = data[p * channels + c];
  return s;
}

inline ImageDifference measureDifference(const StoredImage& expected, const StoredImage& actual,
                                         double pixelThreshold) {
  ImageDifference d;
  const Image& e = expected.values;
  const Image& a = actual.values;
  const std::size_t pixels = static_cast<std::size_t>(e.width) * e.height;
  double sumSq = 0.0, sum[3] = {0.0, 0.0, 0.0};
  std::size_t over = 0;
  for (std::size_t p = 0; p < pixels; ++p) {
    double worst = 0.0;
    for (int c = 0; c < 3; ++c) {
      const double diff = displayValue(a.rgba[4 * p + c], actual.encoding) -
                          displayValue(e.rgba[4 * p + c], expected.encoding);
      sumSq += diff * diff;
      sum[c] += diff;
      worst = std::max(worst, std::fabs(diff));
    }
    if (e.rgba[4 * p + 3] != a.rgba[4 * p + 3]) d.alphaDiffers = true;
    if (worst > pixelThreshold) ++over;
    if (worst > d.largest) {
      d.largest = worst;
      d.largestX = static_cast<int>(p % e.width);
      d.largestY = static_cast<int>(p / e.width);
    }
  }
  const double n = static_cast<double>(std::max<std::size_t>(pixels, 1));
  d.fraction = static_cast<double>(over) / n;
  d.rmse = std::sqrt(sumSq / (3.0 * n));
  for (int c = 0; c < 3; ++c) d.meanBias[c] = sum[c] / n;
  return d;
}

// Empty when `d` is within `tol`, else one line per limit exceeded.
inline std::string toleranceViolations(const ImageDifference& d, const ImageTolerance& tol) {
  std::ostringstream out;
  if (d.alphaDiffers) out << "  alpha differs\n";
  if (d.largest > tol.maxDifference)
    out << "  largest difference " << d.largest << " at (" << d.largestX << ", " << d.largestY
        << ") > " << tol.maxDifference << "\n";
  if (d.fraction > tol.maxFraction)
    out << "  " << 100.0 * d.fraction << " % of the pixels differ by more than "
        << tol.pixelThreshold << " > " << 100.0 * tol.maxFraction << " %\n";
  if (d.rmse > tol.maxRmse) out << "  RMSE " << d.rmse << " > " << tol.maxRmse << "\n";
  for (int c = 0; c < 3; ++c)
    if (std::fabs(d.meanBias[c]) > tol.maxMeanBias)
      out << "  mean difference of channel "
          << "rgb"[c] << " " << d.meanBias[c] << ", beyond +-" << tol.maxMeanBias << "\n";
  return out.str();
}

inline std::string describe(const ImageDifference& d) {
  std::ostringstream out;
  out << "largest " << d.largest << ", " << 100.0 * d.fraction << " % over the threshold, RMSE "
      << d.rmse << ", mean difference (" << d.meanBias[0] << ", " << d.meanBias[1] << ", "
      << d.meanBias[2] << ")";
  return out.str();
}

// The folder of the running test under the build's test-output, created if needed but,
// unlike scratchDir(), not emptied.
inline std::string outputDir() {
  const std::filesystem::path p = testOutputPath();
  std::filesystem::create_directories(p);
  return p.string();
}

// Writes `s` so an image viewer shows what was compared (an Srgb8 image keeps its codes).
inline void writeStoredImage(const StoredImage& s, const std::string& pathWithoutExtension,
                             std::string* written) {
  Image linear = s.values;
  if (s.encoding == ImageEncoding::Srgb8)
    for (std::size_t i = 0; i < linear.rgba.size(); ++i)
      if (i % 4 != 3) linear.rgba[i] = static_cast<float>(srgbDecode(linear.rgba[i]));
  *written = pathWithoutExtension + (s.encoding == ImageEncoding::Srgb8 ? ".png" : ".exr");
  writeImage(linear, *written);
}

inline ::testing::AssertionResult imagesNear(const char* expectedExpr, const char* actualExpr,
                                             const char*, const StoredImage& expected,
                                             const StoredImage& actual, const ImageTolerance& tol) {
  if (expected.values.width != actual.values.width ||
      expected.values.height != actual.values.height)
    return ::testing::AssertionFailure()
           << actualExpr << " is " << actual.values.width << "x" << actual.values.height << ", "
           << expectedExpr << " " << expected.values.width << "x" << expected.values.height;
  if (expected.encoding != actual.encoding)
    return ::testing::AssertionFailure()
           << expectedExpr << " and " << actualExpr << " are stored differently";
  const ImageDifference d = measureDifference(expected, actual, tol.pixelThreshold);
  const std::string violations = toleranceViolations(d, tol);
  if (violations.empty()) return ::testing::AssertionSuccess();

  const std::string dir = outputDir();
  std::string expectedPath, actualPath;
  writeStoredImage(expected, dir + "/expected", &expectedPath);
  writeStoredImage(actual, dir + "/actual", &actualPath);
  Image diff = expected.values;
  const double unit = tol.pixelThreshold > 0.0 ? tol.pixelThreshold : 1.0 / 255.0;
  for (std::size_t i = 0; i < diff.rgba.size(); ++i) {
    if (i % 4 == 3) {
      diff.rgba[i] = 1.0f;
      continue;
    }
    // the display value wanted, turned into the linear value the PNG writer encodes to it
    const double shown =
        std::min(1.0, 0.5 *
                          std::fabs(displayValue(actual.values.rgba[i], actual.encoding) -
                                    displayValue(expected.values.rgba[i], expected.encoding)) /
                          unit);
    diff.rgba[i] = static_cast<float>(srgbDecode(shown));
  }
  const std::string diffPath = dir + "/diff.png";
  writeImage(diff, diffPath);
  return ::testing::AssertionFailure()
         << actualExpr << " differs from " << expectedExpr << " (" << describe(d) << "):\n"
         << violations << "  expected: " << expectedPath << "\n  actual:   " << actualPath
         << "\n  diff:     " << diffPath;
}

#define EXPECT_IMAGES_NEAR(expected, actual, tolerance) \
  EXPECT_PRED_FORMAT3(::clhair::test::imagesNear, expected, actual, tolerance)
#define ASSERT_IMAGES_NEAR(expected, actual, tolerance) \
  ASSERT_PRED_FORMAT3(::clhair::test::imagesNear, expected, actual, tolerance)

}  // namespace clhair::test
