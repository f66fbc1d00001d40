// look_scales.cpp — the FLIP left once coarse features are exact, and the contrast per octave
// (look_scales.h).
#include "look_scales.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace clhair::bench {

namespace {

// Summed-area table over the masked pixels of one plane (W+1 by H+1), and the box sums it
// gives, clamped to the image.
class BoxSums {
 public:
  BoxSums(int w, int h, const std::vector<char>& mask, const std::vector<double>& plane)
      : w_(w), h_(h), t_(static_cast<std::size_t>(w + 1) * (h + 1), 0.0) {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * w + x;
        const double v = mask[i] ? plane[i] : 0.0;
        at(x + 1, y + 1) = v + at(x, y + 1) + at(x + 1, y) - at(x, y);
      }
  }
  double box(int x, int y, int r) const {
    const int x0 = std::max(0, x - r), x1 = std::min(w_, x + r + 1);
    const int y0 = std::max(0, y - r), y1 = std::min(h_, y + r + 1);
    return get(x1, y1) - get(x0, y1) - get(x1, y0) + get(x0, y0);
  }

 private:
  double& at(int x, int y) { return t_[static_cast<std::size_t>(y) * (w_ + 1) + x]; }
  double get(int x, int y) const { return t_[static_cast<std::size_t>(y) * (w_ + 1) + x]; }
  int w_, h_;
  std::vector<double> t_;
};

std::size_t maskCount(const std::vector<char>& mask) {
  std::size_t n = 0;
  for (char m : mask) n += m ? 1u : 0u;
  return n;
}

std::vector<double> channel(const Image& im, int c) {
  std::vector<double> p(static_cast<std::size_t>(im.width) * im.height);
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = im.rgba[i * 4 + c];
  return p;
}

}  // namespace

const std::vector<int>& lookScaleRadii() {
  static const std::vector<int> radii = {1, 2, 4, 8, 16, 32};
  return radii;
}

Image matchCoarserThan(const Image& ref, const Image& test, const std::vector<char>& mask,
                       int radius) {
  Image out = test;
  const int w = test.width, h = test.height;
  for (int c = 0; c < 3; ++c) {
    const BoxSums sr(w, h, mask, channel(ref, c)), st(w, h, mask, channel(test, c));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (!mask[static_cast<std::size_t>(y) * w + x]) continue;
        const double a = st.box(x, y, radius);
        if (a > 1e-12)
          out.pixel(x, y)[c] = static_cast<float>(test.pixel(x, y)[c] * sr.box(x, y, radius) / a);
      }
  }
  return out;
}

namespace {

// The octave bands of the log luminance over the masked pixels (lookScaleRadii(): B_{k-1} -
// B_k per radius, then the coarsest B less its mean); zero outside the mask.
std::vector<std::vector<double>> octaveBands(const Image& image, const std::vector<char>& mask) {
  const int w = image.width, h = image.height;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  std::vector<double> level(n), ones(n, 1.0);
  const std::size_t count = maskCount(mask);
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = &image.rgba[i * 4];
    const double lum = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    level[i] = std::log(std::max(lum, 1e-4));
  }
  std::vector<std::vector<double>> bands;
  if (count == 0)
    return std::vector<std::vector<double>>(lookScaleRadii().size() + 1,
                                            std::vector<double>(n, 0.0));
  const BoxSums sums(w, h, mask, level), weight(w, h, mask, ones);
  std::vector<double> finer(level), coarser(n, 0.0);
  for (int r : lookScaleRadii()) {
    std::vector<double> band(n, 0.0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * w + x;
        if (!mask[i]) continue;
        coarser[i] = sums.box(x, y, r) / weight.box(x, y, r);
        band[i] = finer[i] - coarser[i];
      }
    bands.push_back(std::move(band));
    finer.swap(coarser);
  }
  double mean = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    if (mask[i]) mean += finer[i];
  mean /= static_cast<double>(count);
  std::vector<double> rest(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    if (mask[i]) rest[i] = finer[i] - mean;
  bands.push_back(std::move(rest));
  return bands;
}

}  // namespace

std::vector<double> octaveContrast(const Image& image, const std::vector<char>& mask) {
  const std::size_t count = maskCount(mask);
  std::vector<double> out;
  for (const std::vector<double>& band : octaveBands(image, mask)) {
    double sq = 0.0;
    for (std::size_t i = 0; i < band.size(); ++i)
      if (mask[i]) sq += band[i] * band[i];
    out.push_back(count > 0 ? std::sqrt(sq / static_cast<double>(count)) : 0.0);
  }
  return out;
}

std::vector<double> octaveCorrelation(const Image& ref, const Image& test,
                                      const std::vector<char>& mask) {
  const std::vector<std::vector<double>> a = octaveBands(ref, mask), b = octaveBands(test, mask);
  const double count = static_cast<double>(maskCount(mask));
  const double kFlat = 1e-8;  // a band's mean square under this (RMS 1e-4) is flat
  std::vector<double> out;
  for (std::size_t k = 0; k < a.size(); ++k) {
    double ab = 0.0, aa = 0.0, bb = 0.0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
      if (!mask[i]) continue;
      ab += a[k][i] * b[k][i];
      aa += a[k][i] * a[k][i];
      bb += b[k][i] * b[k][i];
    }
    // a band with no contrast in either image (an image smaller than the box) has no
    // correlation to speak of: NaN, shown as "-"
    out.push_back(aa > kFlat * count && bb > kFlat * count ? ab / std::sqrt(aa * bb)
                                                           : std::nan(""));
  }
  return out;
}

}  // namespace clhair::bench
