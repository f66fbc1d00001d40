// style_stats.cpp — see style_stats.h. Monte Carlo with fixed seeds (a few million cheap
// evaluations, once per process), so every run gets the same constants.
#include "fit/style_stats.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <vector>

#include "clhair/gpu_types.h"

namespace clhair::fit {

namespace {

constexpr int kTable = 64;  // correlation table over d in [0, 1.5]
constexpr double kTableMax = 1.5;

double smooth01(double x) { return x * x * (3.0 - 2.0 * x); }

struct Stats {
  double variance = 0.0;
  std::array<double, kTable + 1> corr{};
  double clump = 0.0;
};

std::uint64_t next(std::uint64_t& s) {
  s = s * 6364136223846793005ull + 1442695040888963407ull;
  return s >> 11;
}
double uniform(std::uint64_t& s) { return static_cast<double>(next(s)) / 9007199254740992.0; }

// value noise with knot values drawn from a fixed sequence keyed by the knot index
double noiseAt(std::uint32_t key, double x) {
  const double fl = std::floor(x);
  const std::int64_t i = static_cast<std::int64_t>(fl);
  auto knot = [&](std::int64_t k) {
    return gpu::clh_u01(gpu::clh_hash2(key, static_cast<std::uint32_t>(k))) * 2.0 - 1.0;
  };
  const double a = knot(i), b = knot(i + 1);
  return a + (b - a) * smooth01(x - fl);
}

Stats compute() {
  Stats st;
  std::uint64_t rng = 0x2545f4914f6cdd1dull;
  const int strands = 4000, per = 64;
  std::array<double, kTable + 1> cross{};
  double sum2 = 0.0;
  std::size_t count = 0;
  for (int s = 0; s < strands; ++s) {
    const std::uint32_t key = static_cast<std::uint32_t>(next(rng));
    for (int k = 0; k < per; ++k) {
      const double x = uniform(rng) * 100.0;
      const double n0 = noiseAt(key, x);
      sum2 += n0 * n0;
      ++count;
      for (int t = 0; t <= kTable; ++t) cross[t] += n0 * noiseAt(key, x + kTableMax * t / kTable);
    }
  }
  st.variance = sum2 / static_cast<double>(count);
  for (int t = 0; t <= kTable; ++t)
    st.corr[t] = cross[t] / static_cast<double>(count) / st.variance;
  // clump: uv uniform over many cells, nearest jittered centre (the generator's formula)
  double dist = 0.0;
  const int samples = 200000;
  for (int k = 0; k < samples; ++k) {
    const double gx = uniform(rng) * 200.0 - 100.0, gy = uniform(rng) * 200.0 - 100.0;
    const int cx0 = static_cast<int>(std::floor(gx)), cy0 = static_cast<int>(std::floor(gy));
    double best = 1e30;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int cx = cx0 + dx, cy = cy0 + dy;
        const std::uint32_t cell = gpu::clh_hash3(17u ^ 0x5c1u, static_cast<std::uint32_t>(cx),
                                                  static_cast<std::uint32_t>(cy));
        const double jx = gpu::clh_u01(gpu::clh_hash2(cell, 0u));
        const double jy = gpu::clh_u01(gpu::clh_hash2(cell, 1u));
        const double ex = cx + 0.5 + (jx - 0.5) * 0.8 - gx, ey = cy + 0.5 + (jy - 0.5) * 0.8 - gy;
        best = std::min(best, ex * ex + ey * ey);
      }
    dist += std::sqrt(best);
  }
  st.clump = dist / samples;
  return st;
}

const Stats& stats() {
  static std::once_flag once;
  static Stats s;
  std::call_once(once, [] { s = compute(); });
  return s;
}

}  // namespace

double valueNoiseVariance() { return stats().variance; }

double valueNoiseCorrelation(double d) {
  const auto& c = stats().corr;
  const double x = std::clamp(d, 0.0, kTableMax) / kTableMax * kTable;
  const int i = std::min(static_cast<int>(x), kTable - 1);
  return c[i] + (c[i + 1] - c[i]) * (x - i);
}

double valueNoiseLagForCorrelation(double target) {
  double lo = 0.0, hi = 1.0;  // the correlation falls monotonically over one knot spacing
  if (target >= 1.0) return 0.0;
  if (target <= valueNoiseCorrelation(hi)) return hi;
  for (int it = 0; it < 40; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (valueNoiseCorrelation(mid) > target)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

double clumpDistanceTimesFrequency() { return stats().clump; }

FrizzLeftover frizzLeftover(double F, int points, double rho, double f, double shape, bool curl) {
  constexpr int kRuns = 1024;
  const int cols = curl ? 3 : 1;
  std::vector<double> w(points), x(static_cast<std::size_t>(points) * cols);
  for (int k = 0; k < points; ++k) {
    w[k] = rho * (k + 1) / points;
    const double ramp = smooth01(std::min(w[k] / 0.15, 1.0));
    x[k * cols] = std::pow(w[k], shape);
    if (curl) {
      x[k * cols + 1] = ramp * std::cos(6.283185307179586 * f * w[k]);
      x[k * cols + 2] = ramp * std::sin(6.283185307179586 * f * w[k]);
    }
  }
  // the projection onto the fit's columns, once: (X^T X)^-1 X^T by normal equations
  double ata[9] = {}, inv[9] = {};
  for (int k = 0; k < points; ++k)
    for (int a = 0; a < cols; ++a)
      for (int b = 0; b < cols; ++b) ata[a * 3 + b] += x[k * cols + a] * x[k * cols + b];
  for (int a = 0; a < cols; ++a) ata[a * 3 + a] += 1e-9;
  if (cols == 1) {
    inv[0] = 1.0 / ata[0];
  } else {
    const double det = ata[0] * (ata[4] * ata[8] - ata[5] * ata[7]) -
                       ata[1] * (ata[3] * ata[8] - ata[5] * ata[6]) +
                       ata[2] * (ata[3] * ata[7] - ata[4] * ata[6]);
    inv[0] = (ata[4] * ata[8] - ata[5] * ata[7]) / det;
    inv[1] = (ata[2] * ata[7] - ata[1] * ata[8]) / det;
    inv[2] = (ata[1] * ata[5] - ata[2] * ata[4]) / det;
    inv[3] = (ata[5] * ata[6] - ata[3] * ata[8]) / det;
    inv[4] = (ata[0] * ata[8] - ata[2] * ata[6]) / det;
    inv[5] = (ata[2] * ata[3] - ata[0] * ata[5]) / det;
    inv[6] = (ata[3] * ata[7] - ata[4] * ata[6]) / det;
    inv[7] = (ata[1] * ata[6] - ata[0] * ata[7]) / det;
    inv[8] = (ata[0] * ata[4] - ata[1] * ata[3]) / det;
  }
  std::uint64_t rng = 0x9e3779b97f4a7c15ull;
  const int lags[5] = {0, 1, 2, 4, 8};
  double energy = 0.0, w4 = 0.0, lag[5] = {};
  std::vector<double> e(points), left(points);
  for (int run = 0; run < kRuns; ++run) {
    const std::uint32_t key = static_cast<std::uint32_t>(next(rng));
    for (int k = 0; k < points; ++k) e[k] = w[k] * w[k] * noiseAt(key, w[k] * F);
    double atb[3] = {};
    for (int k = 0; k < points; ++k)
      for (int a = 0; a < cols; ++a) atb[a] += x[k * cols + a] * e[k];
    double coef[3] = {};
    for (int a = 0; a < cols; ++a)
      for (int b = 0; b < cols; ++b) coef[a] += inv[a * 3 + b] * atb[b];
    int first = points;
    for (int k = 0; k < points; ++k) {
      left[k] = e[k];
      for (int a = 0; a < cols; ++a) left[k] -= coef[a] * x[k * cols + a];
      if (first == points && w[k] >= 0.3) first = k;
    }
    for (int k = first; k < points; ++k) {
      energy += left[k] * left[k];
      w4 += w[k] * w[k] * w[k] * w[k];
      for (int j = 0; j < 5; ++j)
        if (k + lags[j] < points) lag[j] += left[k] * left[k + lags[j]];
    }
  }
  FrizzLeftover out;
  if (w4 > 0.0) out.energy = energy / (w4 * stats().variance);
  for (int j = 0; j < 4; ++j)
    if (lag[0] > 0.0) out.corr[j] = lag[j + 1] / lag[0];
  return out;
}

}  // namespace clhair::fit
