// curl_detect.cpp — see curl_detect.h.
#include "fit/curl_detect.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "fit/linear_algebra.h"
#include "fit/parallel.h"

namespace clhair::fit {

namespace {

constexpr std::size_t kSample = 1000;
constexpr float kMinTurns = 1.5f, kMaxTurns = 20.0f, kStep = 0.25f;

// Energy left after fitting the points of one coordinate with `cols` basis columns.
double leftover(const std::vector<double>& basis, int cols, const double* y, int n) {
  double ata[36] = {}, atb[6] = {}, total = 0.0;
  for (int k = 0; k < n; ++k) {
    const double* x = &basis[static_cast<std::size_t>(k) * 6];
    total += y[k] * y[k];
    for (int a = 0; a < cols; ++a) {
      atb[a] += x[a] * y[k];
      for (int b = 0; b < cols; ++b) ata[a * cols + b] += x[a] * x[b];
    }
  }
  double trace = 0.0;
  for (int a = 0; a < cols; ++a) trace += ata[a * cols + a];
  for (int a = 0; a < cols; ++a) ata[a * cols + a] += 1e-9 * trace + 1e-30;
  double sol[6];
  if (!solveDense(ata, atb, sol, cols)) return total;
  double e = 0.0;
  for (int k = 0; k < n; ++k) {
    const double* x = &basis[static_cast<std::size_t>(k) * 6];
    double r = y[k];
    for (int a = 0; a < cols; ++a) r -= sol[a] * x[a];
    e += r * r;
  }
  return e;
}

}  // namespace

float detectCurlTurns(const FitStrands& s, int threads) {
  const int M = s.samples;
  std::vector<std::size_t> sample;
  const std::size_t step = std::max<std::size_t>(1, s.count() / kSample);
  for (std::size_t i = 0; i < s.count(); i += step)
    if (s.length[i] > 0.0f) sample.push_back(i);
  std::vector<float> grid;
  for (float f = kMinTurns; f <= kMaxTurns + 1e-3f; f += kStep) grid.push_back(f);
  // energy after the cubic alone (index 0), then after cubic + sinusoid at each grid f
  std::vector<double> energy(grid.size() + 1, 0.0);
  std::vector<std::vector<double>> part(sample.size(), std::vector<double>(grid.size() + 1));
  parallelFor(
      sample.size(), threads,
      [&](std::size_t b, std::size_t e) {
        std::vector<double> basis(static_cast<std::size_t>(M) * 6), y(M);
        for (std::size_t j = b; j < e; ++j) {
          const glm::vec3* p = s.strand(sample[j]);
          for (std::size_t g = 0; g <= grid.size(); ++g) {
            const double f = g == 0 ? 0.0 : grid[g - 1];
            for (int k = 0; k < M; ++k) {
              const double u = static_cast<double>(k) / (M - 1);
              double* x = &basis[static_cast<std::size_t>(k) * 6];
              x[0] = 1.0;
              x[1] = u;
              x[2] = u * u;
              x[3] = u * u * u;
              x[4] = std::cos(6.283185307179586 * f * u);
              x[5] = std::sin(6.283185307179586 * f * u);
            }
            double sum = 0.0;
            for (int c = 0; c < 3; ++c) {
              for (int k = 0; k < M; ++k) y[k] = p[k][c];
              sum += leftover(basis, g == 0 ? 4 : 6, y.data(), M);
            }
            part[j][g] = sum;
          }
        }
      },
      8);
  for (const auto& v : part)
    for (std::size_t g = 0; g < v.size(); ++g) energy[g] += v[g];
  if (!(energy[0] > 0.0)) return 0.0f;
  std::size_t best = 1;
  for (std::size_t g = 1; g < energy.size(); ++g)
    if (energy[g] < energy[best]) best = g;
  std::vector<double> gains;
  for (std::size_t g = 1; g < energy.size(); ++g) gains.push_back(energy[0] - energy[g]);
  std::nth_element(gains.begin(), gains.begin() + gains.size() / 2, gains.end());
  const double typical = gains[gains.size() / 2], gain = energy[0] - energy[best];
  if (gain < 0.5 * energy[0] || gain < 2.0 * typical) return 0.0f;
  // a curl is a peak: the lowest frequency of the grid winning is bending the cubic missed,
  // and a turn away on either side the sinusoid must explain much less
  if (best == 1) return 0.0f;
  const std::size_t away = static_cast<std::size_t>(std::lround(1.0f / kStep));
  for (std::size_t g : {best > away ? best - away : std::size_t{0}, best + away})
    if (g >= 1 && g < energy.size() && energy[0] - energy[g] > 0.5 * gain) return 0.0f;
  return grid[best - 1];
}

FitStrands smoothOverTurn(const FitStrands& s, float turns, int threads) {
  FitStrands out = s;
  if (!(turns > 0.0f)) return out;
  const int M = s.samples;
  const int half = std::max(1, static_cast<int>(std::lround(0.5 * (M - 1) / turns)));
  parallelFor(s.count(), threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const glm::vec3* p = s.strand(i);
      glm::vec3* q = out.points.data() + i * M;
      for (int k = 0; k < M; ++k) {
        const int h = std::min({half, k, M - 1 - k});
        glm::vec3 sum(0.0f);
        for (int j = k - h; j <= k + h; ++j) sum += p[j];
        q[k] = sum / static_cast<float>(2 * h + 1);
      }
    }
  });
  resampleInPlace(out, threads);
  return out;
}

}  // namespace clhair::fit
