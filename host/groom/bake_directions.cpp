// bake_directions.cpp — the visibility bake's ray directions and their projection
// (visibility_bake.h): a seeded golden-angle spiral per point, the fixed Fibonacci set of the
// transmittance study, and the L1 spherical-harmonic projection of a point's ray values.
#include <algorithm>
#include <cmath>

#include "clhair/visibility_sh.h"
#include "groom/visibility_bake.h"

namespace clhair {

namespace {
constexpr float kPi = 3.14159265358979323846f;
}  // namespace

void sphereDirections(std::uint32_t count, std::uint32_t seed, float* out) {
  // golden-angle spiral with equal-area z bands; the seed turns it about z and jitters z
  // within each band, so neighbouring points see different directions
  const float golden = kPi * (3.0f - std::sqrt(5.0f));
  const std::uint32_t h = gpu::clh_hash(seed);
  const float phi0 = 2.0f * kPi * gpu::clh_u01(h);
  const float jitter = gpu::clh_u01(gpu::clh_hash(h)) - 0.5f;
  for (std::uint32_t k = 0; k < count; ++k) {
    const float z =
        1.0f - (2.0f * (static_cast<float>(k) + 0.5f + 0.98f * jitter)) / static_cast<float>(count);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = phi0 + golden * static_cast<float>(k);
    out[3 * k] = r * std::cos(phi);
    out[3 * k + 1] = r * std::sin(phi);
    out[3 * k + 2] = z;
  }
}

void fibonacciDirections(std::uint32_t count, float* out) {
  const double golden = 3.14159265358979323846 * (3.0 - std::sqrt(5.0));
  for (std::uint32_t k = 0; k < count; ++k) {
    const double h = k + 0.5, z = 1.0 - 2.0 * h / count;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    out[3 * k] = static_cast<float>(r * std::cos(golden * h));
    out[3 * k + 1] = static_cast<float>(r * std::sin(golden * h));
    out[3 * k + 2] = static_cast<float>(z);
  }
}

void projectL1(const float* dirs, const float* values, std::uint32_t count, float out[4]) {
  double c[4] = {0.0, 0.0, 0.0, 0.0};
  for (std::uint32_t k = 0; k < count; ++k) {
    const double f = values[k];
    c[0] += f * CLH_SH_Y0;
    c[1] += f * CLH_SH_Y1 * dirs[3 * k + 1];
    c[2] += f * CLH_SH_Y1 * dirs[3 * k + 2];
    c[3] += f * CLH_SH_Y1 * dirs[3 * k];
  }
  const double w = count > 0 ? 4.0 * 3.14159265358979323846 / count : 0.0;
  for (int i = 0; i < 4; ++i) out[i] = static_cast<float>(c[i] * w);
}

}  // namespace clhair
