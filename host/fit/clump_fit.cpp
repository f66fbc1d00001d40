// clump_fit.cpp — see clump_fit.h.
#include "fit/clump_fit.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "fit/style_stats.h"

namespace clhair::fit {

namespace {

constexpr float kBinW[kClumpBins] = {0.2f, 0.35f, 0.5f, 0.65f, 0.8f, 0.95f};

float median(std::vector<float> v) {
  if (v.empty()) return 0.0f;
  const std::size_t k = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

}  // namespace

void clumpSamples(const StrandResidual& r, const StrandFit& fit, float f, const glm::vec2& uv,
                  ClumpSamples& out) {
  out.valid = false;
  out.uv = uv;
  if (r.points < 4) return;
  int k = 0;
  for (int b = 0; b < kClumpBins; ++b) {
    const float w = kBinW[b];
    if (w > r.w[r.points - 1]) return;  // the strand ends before this bin: not used
    while (k + 1 < r.points - 1 && r.w[k + 1] < w) ++k;
    const float span = r.w[k + 1] - r.w[k];
    const float t = span > 0.0f ? std::clamp((w - r.w[k]) / span, 0.0f, 1.0f) : 0.0f;
    auto lerp2 = [&](const glm::vec2* a) { return a[k] + (a[k + 1] - a[k]) * t; };
    // the strand's own curl at this w, taken out
    const float th = 6.28318530718f * f * w;
    const float ramp = r.ramp[k] + (r.ramp[k + 1] - r.ramp[k]) * t;
    const float cs = std::cos(th) * ramp, sn = std::sin(th) * ramp;
    const glm::vec2 curl(fit.a * cs + fit.b * sn, fit.c * cs + fit.d * sn);
    out.q[b] = lerp2(r.r) - curl;
    out.du[b] = lerp2(r.du);
    out.dv[b] = lerp2(r.dv);
  }
  out.valid = true;
}

ClumpEstimate estimateClumping(const std::vector<ClumpSamples>& s, const std::vector<int>& strands,
                               const std::vector<std::pair<int, int>>& pairs) {
  ClumpEstimate out;
  // the profile: median over pairs of -(q_i - q_j).g / |g|^2, g = J (uv_i - uv_j)
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, sw = 0.0;
  for (int b = 0; b < kClumpBins; ++b) {
    // per pair: the difference of the samples and the pull direction
    std::vector<glm::vec2> dq, g;
    std::vector<float> ratio;
    for (const auto& p : pairs) {
      const ClumpSamples &a = s[p.first], &q = s[p.second];
      if (!a.valid || !q.valid) continue;
      const glm::vec2 duv = a.uv - q.uv;
      const glm::vec2 du = 0.5f * (a.du[b] + q.du[b]), dv = 0.5f * (a.dv[b] + q.dv[b]);
      const glm::vec2 gp = du * duv.x + dv * duv.y;
      if (!(glm::dot(gp, gp) > 0.0f)) continue;
      dq.push_back(a.q[b] - q.q[b]);
      g.push_back(gp);
      ratio.push_back(-glm::dot(dq.back(), gp) / glm::dot(gp, gp));
    }
    if (dq.size() < 8) continue;
    // the median ratio, then least squares over the pairs that agree with it (trimmed at
    // twice the median disagreement, four times): pairs of two clumps drop out
    float pull = median(ratio);
    for (int pass = 0; pass < 4; ++pass) {
      std::vector<float> err(dq.size());
      for (std::size_t k = 0; k < dq.size(); ++k) err[k] = glm::length(dq[k] + pull * g[k]);
      const float cut = 2.0f * median(err);
      double num = 0.0, den = 0.0;
      for (std::size_t k = 0; k < dq.size(); ++k)
        if (err[k] <= cut) {
          num -= glm::dot(dq[k], g[k]);
          den += glm::dot(g[k], g[k]);
        }
      if (den > 0.0) pull = static_cast<float>(num / den);
    }
    const std::vector<float>& c = ratio;
    if (!(pull > 1e-3f)) continue;
    // log pull = log strength + shape log w, weighted by the bin's share of pairs
    const double x = std::log(kBinW[b]), y = std::log(pull), wt = static_cast<double>(c.size());
    sx += wt * x;
    sy += wt * y;
    sxx += wt * x * x;
    sxy += wt * x * y;
    sw += wt;
  }
  if (sw <= 0.0) return out;
  const double den = sw * sxx - sx * sx;
  double shape = den > 1e-12 ? (sw * sxy - sx * sy) / den : 1.0;
  shape = std::clamp(shape, 0.01, 16.0);
  const double logStrength = (sy - shape * sx) / sw;
  out.strength = static_cast<float>(std::clamp(std::exp(logStrength), 0.0, 1.0));
  out.shape = static_cast<float>(shape);
  if (out.strength < 0.02f) {
    out.strength = 0.0f;
    return out;
  }
  // each strand's offset to its centre: q_b = strength w_b^shape J_b d, least squares in d
  double dist = 0.0;
  int n = 0;
  for (int i : strands) {
    const ClumpSamples& a = s[i];
    if (!a.valid) continue;
    double m00 = 0, m01 = 0, m11 = 0, r0 = 0, r1 = 0;
    for (int b = 0; b < kClumpBins; ++b) {
      const float k = out.strength * std::pow(kBinW[b], out.shape);
      const glm::vec2 cu = k * a.du[b], cv = k * a.dv[b];
      m00 += glm::dot(cu, cu);
      m01 += glm::dot(cu, cv);
      m11 += glm::dot(cv, cv);
      r0 += glm::dot(cu, a.q[b]);
      r1 += glm::dot(cv, a.q[b]);
    }
    const double det = m00 * m11 - m01 * m01;
    if (!(std::fabs(det) > 1e-30)) continue;
    const double d0 = (m11 * r0 - m01 * r1) / det, d1 = (m00 * r1 - m01 * r0) / det;
    dist += std::sqrt(d0 * d0 + d1 * d1);
    ++n;
  }
  if (n > 0 && dist > 0.0)
    out.frequency = static_cast<float>(clumpDistanceTimesFrequency() * n / dist);
  return out;
}

}  // namespace clhair::fit
