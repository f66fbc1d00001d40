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

std::vector<double> octaveContrast(const Image& image, const std::vector<char>& mask) {
  const int w = image.width, h = image.height;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  std::vector<double> level(n), ones(n, 1.0);
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = &image.rgba[i * 4];
    const double lum = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    level[i] = std::log(std::max(lum, 1e-4));
    count += mask[i] ? 1u : 0u;
  }
  std::vector<double> out;
  if (count == 0) return std::vector<double>(lookScaleRadii().size() + 1, 0.0);
  const BoxSums sums(w, h, mask, level), weight(w, h, mask, ones);
  std::vector<double> finer(level), coarser(n);
  for (int r : lookScaleRadii()) {
    double band = 0.0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * w + x;
        if (!mask[i]) continue;
        coarser[i] = sums.box(x, y, r) / weight.box(x, y, r);
        band += (finer[i] - coarser[i]) * (finer[i] - coarser[i]);
      }
    out.push_back(std::sqrt(band / static_cast<double>(count)));
    finer.swap(coarser);
  }
  double mean = 0.0, sq = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    if (mask[i]) mean += finer[i];
  mean /= static_cast<double>(count);
  for (std::size_t i = 0; i < n; ++i)
    if (mask[i]) sq += (finer[i] - mean) * (finer[i] - mean);
  out.push_back(std::sqrt(sq / static_cast<double>(count)));
  return out;
}

}  // namespace clhair::bench
