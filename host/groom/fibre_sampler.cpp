// fibre_sampler.cpp — see fibre_sampler.h.
#include "groom/fibre_sampler.h"

#include <algorithm>
#include <cmath>

namespace clhair {

namespace {

namespace hb = cpu_bsdf;
constexpr float kPiF = 3.14159265358979323846f;
constexpr float kBinWidth = kPiF / FibreSampler::kBins;

float luminance(hb::clh_v3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

}  // namespace

FibreSampler::FibreSampler(const hb::clh_hair_view& hv, hb::clh_v3 tint) : hv_(hv), tint_(tint) {
  const hb::clh_v3 t = hv.t, n = hv.n;
  b_ = hb::clh_v3_make(t.y * n.z - t.z * n.y, t.z * n.x - t.x * n.z, t.x * n.y - t.y * n.x);
  float e[4], total = 0.0f;
  for (int p = 0; p < 4; ++p) {
    e[p] = std::max(luminance(hb::clh_v3_mul(tint, hv.mass[p])), 0.0f);
    total += e[p];
  }
  if (!(total > 0.0f)) {  // a black fibre: any density serves, its weights are 0
    c_[3] = 1.0f;
  } else {
    float sum = 0.0f;
    for (int p = 0; p < 4; ++p) {
      c_[p] = e[p] > 0.0f ? std::max(e[p], kLobeFloor * total) : 0.0f;
      sum += c_[p];
    }
    for (float& c : c_) c /= sum;
  }
  const float tintLum = luminance(tint);
  for (int p = 0; p < 3; ++p) {
    if (!(c_[p] > 0.0f)) continue;
    float w[kBins], sum = 0.0f;
    for (int k = 0; k < kBins; ++k) {
      const float phi = (static_cast<float>(k) + 0.5f) * kBinWidth;
      w[k] = p == 0   ? hb::clh_hair_n_r(&hv, phi) * tintLum
             : p == 1 ? luminance(hb::clh_v3_mul(tint, hb::clh_hair_n_tt(&hv, phi)))
                      : luminance(hb::clh_v3_mul(tint, hb::clh_hair_n_trt(&hv, phi)));
      w[k] = std::max(w[k], 0.0f);
      sum += w[k];
    }
    cdf_[p][0] = 0.0f;
    for (int k = 0; k < kBins; ++k) {
      // the bin's probability: the lobe's share and the uniform share
      const float q = sum > 0.0f ? (1.0f - kUniform) * w[k] / sum + kUniform / kBins : 1.0f / kBins;
      dens_[p][k] = q / (2.0f * kBinWidth);  // over phi in [-pi, pi]: both signs
      cdf_[p][k + 1] = cdf_[p][k] + q;
    }
    cdf_[p][kBins] = 1.0f;
  }
}

hb::clh_v3 FibreSampler::sample(const float u[4]) const {
  // the lobe, and what is left of u[0] inside its interval for the sign of phi
  int p = 0;
  float x = u[0];
  while (p < 3 && (x >= c_[p] || !(c_[p] > 0.0f))) {
    x -= c_[p];
    ++p;
  }
  if (!(c_[p] > 0.0f))  // rounding past the last lobe with energy
    while (p > 0 && !(c_[p] > 0.0f)) --p;
  const bool negative = x < 0.5f * c_[p];
  float sin_i, phi;
  if (p == 3) {
    // sin theta_i of density (2 / pi) sqrt(1 - s²): a uniform point of the unit disk
    sin_i = std::sqrt(u[1]) * std::cos(2.0f * kPiF * u[2]);
    phi = kPiF * (2.0f * u[3] - 1.0f);
  } else {
    // M_p (d'Eon et al. 2013; pbrt-v4 HairBxDF::Sample_f), about theta_i = -theta_o tilted
    const double v = hv_.v[p];
    const double cosT = std::clamp(
        1.0 + v * std::log(std::max(u[1] + (1.0 - u[1]) * std::exp(-2.0 / v), 1e-300)), -1.0, 1.0);
    const double sinT = std::sqrt(std::max(0.0, 1.0 - cosT * cosT));
    sin_i = static_cast<float>(-cosT * hv_.sin_o_tilt[p] +
                               sinT * std::cos(2.0 * 3.14159265358979323846 * u[2]) *
                                   hv_.cos_o_tilt[p]);
    const float* cdf = cdf_[p];
    int k = 0;
    while (k + 1 < kBins && u[3] >= cdf[k + 1]) ++k;
    const float width = cdf[k + 1] - cdf[k];
    const float frac = width > 0.0f ? std::clamp((u[3] - cdf[k]) / width, 0.0f, 1.0f) : 0.5f;
    phi = (static_cast<float>(k) + frac) * kBinWidth;
    if (negative) phi = -phi;
  }
  sin_i = std::clamp(sin_i, -1.0f, 1.0f);
  const float cos_i = std::sqrt(std::max(0.0f, 1.0f - sin_i * sin_i));
  const hb::clh_v3 across =
      hb::clh_v3_add(hb::clh_v3_scale(hv_.n, std::cos(phi)), hb::clh_v3_scale(b_, std::sin(phi)));
  return hb::clh_v3_add(hb::clh_v3_scale(hv_.t, sin_i), hb::clh_v3_scale(across, cos_i));
}

float FibreSampler::pdf(hb::clh_v3 wi) const {
  const float sin_i = std::clamp(hb::clh_v3_dot(hv_.t, wi), -1.0f, 1.0f);
  const hb::clh_v3 wp = hb::clh_v3_sub(wi, hb::clh_v3_scale(hv_.t, sin_i));
  const float cos_i = std::min(std::sqrt(hb::clh_v3_dot(wp, wp)), 1.0f);
  const float phi = std::fabs(std::atan2(hb::clh_v3_dot(wp, b_), hb::clh_v3_dot(wp, hv_.n)));
  const int k = std::clamp(static_cast<int>(phi / kBinWidth), 0, kBins - 1);
  float d = c_[3] * cos_i / (kPiF * kPiF);
  for (int p = 0; p < 3; ++p)
    if (c_[p] > 0.0f)
      d += c_[p] * dens_[p][k] *
           hb::clh_hair_mp(sin_i, cos_i, hv_.sin_o_tilt[p], hv_.cos_o_tilt[p], hv_.v[p],
                           hv_.m_norm[p]);
  return d;
}

hb::clh_v3 FibreSampler::evalCos(hb::clh_v3 wi) const {
  return hb::clh_v3_mul(tint_, hb::clh_hair_eval_cos(&hv_, wi));
}

}  // namespace clhair
