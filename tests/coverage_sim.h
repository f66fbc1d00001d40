// coverage_sim.h — the simulation behind the coverage mode's alpha curve (clhair/coverage.h):
// many random opaque lines of similar width over one pixel, the true coverage of their
// union recorded against the sum of their coverages (Kulikov 2025: "numerically simulate
// coverage as a function of number of strands and their thickness"), and the least-squares
// fit of the curve's form to it. tests/test_coverage.cpp runs it and checks that the fit
// reproduces the constants of coverage.h and that the curve stays within its stated error.
//
// The pixel is a grid of kGrid x kGrid sample points. A trial picks a width w uniform in
// [0.1, 1] pixel; each line gets w times a factor uniform in [0.9, 1.1], a direction
// uniform in [0, pi) and a signed distance from the pixel centre uniform over every
// distance at which it can touch the pixel (isotropic random lines). Lines that cover no
// sample are not fragments and are skipped. After each line the sum x of the lines'
// coverages and the union's coverage go into the bin of x (bins of kBin up to kMaxX); a
// trial ends when x reaches kMaxX. The curve is compared with each bin's mean.
//
// The random numbers come from std::mt19937_64 (its sequence is fixed by the standard)
// turned into doubles by hand, so every standard library reproduces the same fit.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace clhair::test {

struct CoverageSimulation {
  static constexpr int kGrid = 64;
  static constexpr int kTrials = 4000;
  static constexpr double kBin = 0.05;
  static constexpr double kMaxX = 8.0;
  static constexpr std::uint64_t kSeed = 12345;
  std::vector<double> sum, count;  // per bin: the union's coverage summed, samples

  int bins() const { return static_cast<int>(sum.size()); }
  double centre(int b) const { return (b + 0.5) * kBin; }
  double mean(int b) const { return sum[b] / count[b]; }
};

inline CoverageSimulation simulateCoverage(int trials = CoverageSimulation::kTrials) {
  using S = CoverageSimulation;
  const int bins = static_cast<int>(S::kMaxX / S::kBin);
  S sim;
  sim.sum.assign(bins, 0.0);
  sim.count.assign(bins, 0.0);
  std::mt19937_64 rng(S::kSeed);
  auto u01 = [&rng] { return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0); };
  const double pi = 3.14159265358979323846;
  std::vector<std::uint8_t> mask(S::kGrid * S::kGrid);
  for (int trial = 0; trial < trials; ++trial) {
    const double w = 0.1 + 0.9 * u01();
    std::fill(mask.begin(), mask.end(), 0);
    int covered = 0;
    double x = 0.0;
    while (x < S::kMaxX) {
      const double lw = w * (0.9 + 0.2 * u01());
      const double theta = pi * u01();
      const double nx = std::cos(theta), ny = std::sin(theta);
      const double reach = std::sqrt(0.5) + 0.5 * lw;
      const double d = (2.0 * u01() - 1.0) * reach;
      int hit = 0;
      for (int j = 0; j < S::kGrid; ++j)
        for (int i = 0; i < S::kGrid; ++i) {
          const double px = (i + 0.5) / S::kGrid - 0.5, py = (j + 0.5) / S::kGrid - 0.5;
          if (std::fabs(nx * px + ny * py - d) < 0.5 * lw) {
            ++hit;
            if (!mask[j * S::kGrid + i]) {
              mask[j * S::kGrid + i] = 1;
              ++covered;
            }
          }
        }
      if (hit == 0) continue;
      x += static_cast<double>(hit) / (S::kGrid * S::kGrid);
      if (x >= S::kMaxX) break;
      const int b = static_cast<int>(x / S::kBin);
      sim.sum[b] += static_cast<double>(covered) / (S::kGrid * S::kGrid);
      sim.count[b] += 1.0;
    }
  }
  return sim;
}

// The fit of coverage.h's form, alpha = 1 - (1 - t)^2 (1 + b1 t + b2 t^2) with
// t = min(x / x1, 1), to the bin means over x <= x1 (each bin weighted alike): linear least
// squares in b1, b2 of (1 - alpha) - (1 - t)^2 = b1 t (1 - t)^2 + b2 t^2 (1 - t)^2.
inline void fitCoverageCurve(const CoverageSimulation& sim, double x1, double* b1, double* b2) {
  double a11 = 0, a12 = 0, a22 = 0, r1 = 0, r2 = 0;
  for (int b = 0; b < sim.bins(); ++b) {
    const double xc = sim.centre(b);
    if (xc > x1 || sim.count[b] == 0.0) continue;
    const double t = xc / x1, u2 = (1.0 - t) * (1.0 - t);
    const double y = (1.0 - sim.mean(b)) - u2;
    const double f1 = t * u2, f2 = t * t * u2;
    a11 += f1 * f1;
    a12 += f1 * f2;
    a22 += f2 * f2;
    r1 += f1 * y;
    r2 += f2 * y;
  }
  const double det = a11 * a22 - a12 * a12;
  *b1 = (r1 * a22 - r2 * a12) / det;
  *b2 = (a11 * r2 - a12 * r1) / det;
}

}  // namespace clhair::test
