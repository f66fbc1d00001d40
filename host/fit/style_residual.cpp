// style_residual.cpp — see style_residual.h.
#include "fit/style_residual.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "fit/arc_model.h"
#include "fit/linear_algebra.h"

namespace clhair::fit {

namespace {

constexpr float kTwoPi = 6.28318530717958647692f;

float smooth01(float x) {
  x = std::clamp(x, 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

glm::vec3 normalizeOr(const glm::vec3& v, const glm::vec3& fallback) {
  const float l2 = glm::dot(v, v);
  return (l2 > 1e-30f && l2 < 1e30f) ? v / std::sqrt(l2) : fallback;
}

}  // namespace

void strandResidual(const FitStrands& s, const StrandPlacement& pl, const BaseCurves& base,
                    std::size_t i, const FittedStyle* curl, StrandResidual& out) {
  const int M = s.samples;
  const float full = pl.fullLength[i];
  const glm::vec3* p = s.strand(i);
  float w[kFitSamples] = {};
  BaseSample bs[kFitSamples];
  int n = 0;
  if (curl) {
    float all[kFitSamples];
    out.rho = std::min(strandW(s, i, pl.face[i], pl.st[i], base, *curl, all), 1.0f);
    for (int k = 1; k < M && n < kFitSamples; ++k) w[n++] = std::min(all[k], 1.0f);
  } else {
    out.rho = full > 0.0f ? std::min(s.length[i] / full, 1.0f) : 1.0f;
    for (int k = 1; k < M && n < kFitSamples; ++k) {
      const float arc = s.length[i] * static_cast<float>(k) / static_cast<float>(M - 1);
      w[n++] = full > 0.0f ? std::min(arc / full, 1.0f) : 0.0f;
    }
  }
  base.evaluate(pl.face[i], pl.st[i], w, n, bs);
  out.points = n;
  out.dw = out.rho / static_cast<float>(M - 1);
  for (int k = 0; k < n; ++k) {
    const glm::vec3 et = normalizeOr(bs[k].deriv, glm::vec3(0, 1, 0));
    const glm::vec3 e1 =
        normalizeOr(bs[k].du - glm::dot(bs[k].du, et) * et,
                    normalizeOr(bs[k].dv - glm::dot(bs[k].dv, et) * et, glm::vec3(1, 0, 0)));
    const glm::vec3 e2 = glm::cross(et, e1);
    const glm::vec3 r = p[k + 1] - bs[k].pos;
    out.w[k] = w[k];
    out.r[k] = glm::vec2(glm::dot(r, e1), glm::dot(r, e2));
    out.du[k] = glm::vec2(glm::dot(bs[k].du, e1), glm::dot(bs[k].du, e2));
    out.dv[k] = glm::vec2(glm::dot(bs[k].dv, e1), glm::dot(bs[k].dv, e2));
    out.ramp[k] = smooth01(w[k] / 0.15f);
    out.e1[k] = e1;
    out.e2[k] = e2;
  }
}

StrandFit fitStrandStyle(const StrandResidual& r, float f, float shape, bool leftover) {
  StrandFit out;
  double ata[36] = {}, atb[6] = {};
  double total = 0.0;
  // rows: e1 component then e2 component of each point
  auto row = [&](int k, int comp, double* x) {
    const float wk = std::max(r.w[k], 0.0f);
    const float ws = wk > 0.0f ? std::pow(wk, shape) : 0.0f;
    const float th = kTwoPi * f * wk;
    const float cs = std::cos(th) * r.ramp[k], sn = std::sin(th) * r.ramp[k];
    x[0] = ws * (comp == 0 ? r.du[k].x : r.du[k].y);
    x[1] = ws * (comp == 0 ? r.dv[k].x : r.dv[k].y);
    x[2] = comp == 0 ? cs : 0.0;
    x[3] = comp == 0 ? sn : 0.0;
    x[4] = comp == 1 ? cs : 0.0;
    x[5] = comp == 1 ? sn : 0.0;
  };
  for (int k = 0; k < r.points; ++k)
    for (int comp = 0; comp < 2; ++comp) {
      double x[6];
      row(k, comp, x);
      const double y = comp == 0 ? r.r[k].x : r.r[k].y;
      total += y * y;
      for (int a = 0; a < 6; ++a) {
        atb[a] += x[a] * y;
        for (int b = 0; b < 6; ++b) ata[6 * a + b] += x[a] * x[b];
      }
    }
  out.total = total;
  double trace = 0.0;
  for (int a = 0; a < 6; ++a) trace += ata[7 * a];
  for (int a = 0; a < 6; ++a) ata[7 * a] += 1e-6 * trace / 6.0 + 1e-30;
  double sol[6] = {};
  double m[36];
  std::copy(ata, ata + 36, m);
  if (!solveDense(m, atb, sol, 6)) {
    out.energy = total;
    return out;
  }
  out.delta = glm::vec2(static_cast<float>(sol[0]), static_cast<float>(sol[1]));
  out.a = static_cast<float>(sol[2]);
  out.b = static_cast<float>(sol[3]);
  out.c = static_cast<float>(sol[4]);
  out.d = static_cast<float>(sol[5]);
  double energy = 0.0;
  glm::dvec2 left[kFitSamples];
  int first = r.points;  // w rises along the strand: frizz is measured from here on
  for (int k = 0; k < r.points; ++k) {
    glm::dvec2 e;
    for (int comp = 0; comp < 2; ++comp) {
      double x[6];
      row(k, comp, x);
      double pred = 0.0;
      for (int a = 0; a < 6; ++a) pred += x[a] * sol[a];
      e[comp] = (comp == 0 ? r.r[k].x : r.r[k].y) - pred;
    }
    energy += glm::dot(e, e);
    left[k] = e;
    if (first == r.points && r.w[k] >= 0.3f) first = k;
  }
  if (leftover)
    for (int k = first; k < r.points; ++k) {
      const double wk = r.w[k];
      out.frizzEnergy += glm::dot(left[k], left[k]);
      out.frizzW4 += wk * wk * wk * wk;
      for (int j = 0; j < kFrizzLagCount; ++j)
        if (k + kFrizzLags[j] < r.points) out.lag[j] += glm::dot(left[k], left[k + kFrizzLags[j]]);
    }
  out.energy = energy;
  return out;
}

}  // namespace clhair::fit
