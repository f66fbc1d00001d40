// arc_model.cpp — see arc_model.h.
#include "fit/arc_model.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

namespace clhair::fit {

namespace {
float smooth01(float x) {
  x = std::clamp(x, 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}
}  // namespace

float ArcMap::wAt(float a) const {
  if (!(a > 0.0f)) return 0.0f;
  if (a >= arc[kArcSteps]) {
    const float last = arc[kArcSteps] - arc[kArcSteps - 1];
    const float extra = last > 0.0f ? (a - arc[kArcSteps]) / last / kArcSteps : 0.0f;
    return 1.0f + extra;
  }
  const float* hi = std::upper_bound(arc, arc + kArcSteps + 1, a);
  const int j = std::max(static_cast<int>(hi - arc) - 1, 0);
  const float span = arc[j + 1] - arc[j];
  const float t = span > 0.0f ? (a - arc[j]) / span : 0.0f;
  return (static_cast<float>(j) + t) / kArcSteps;
}

float ArcMap::arcAt(float w) const {
  const float x = std::clamp(w, 0.0f, 1.0f) * kArcSteps;
  const int j = std::min(static_cast<int>(x), kArcSteps - 1);
  return arc[j] + (arc[j + 1] - arc[j]) * (x - static_cast<float>(j));
}

ArcMap arcMap(const BaseCurves& base, int face, const glm::vec2& st, const FittedStyle& curl,
              int points) {
  // the speed at the midpoints of kArcSteps intervals (midpoint rule)
  float w[kArcSteps];
  BaseSample bs[kArcSteps];
  for (int j = 0; j < kArcSteps; ++j) w[j] = (static_cast<float>(j) + 0.5f) / kArcSteps;
  base.evaluate(face, st, w, kArcSteps, bs);
  const float layers = static_cast<float>(base.layerCount());
  const float pi = 3.14159265f;
  const float dw = points >= 2 ? 1.0f / static_cast<float>(points - 1) : 0.0f;
  const float c = dw > 0.0f && curl.curlFrequency * dw < 0.5f
                      ? 2.0f * curl.curlAmplitude * std::sin(pi * curl.curlFrequency * dw) / dw
                      : 2.0f * pi * curl.curlFrequency * curl.curlAmplitude;
  const float h2 = 0.5f * (1.0f + curl.curlHelix * curl.curlHelix);
  ArcMap m;
  m.arc[0] = 0.0f;
  for (int j = 0; j < kArcSteps; ++j) {
    const glm::vec3 d = bs[j].deriv * (layers - 1.0f);  // dP/dw
    // the curl's offset changes with its phase and, over the first 15 %, with its ramp
    const float x = std::clamp(w[j] / 0.15f, 0.0f, 1.0f);
    const float r = c * smooth01(w[j] / 0.15f);
    const float ramp = curl.curlAmplitude * 6.0f * x * (1.0f - x) / 0.15f;
    m.arc[j + 1] = m.arc[j] + std::sqrt(glm::dot(d, d) + (r * r + ramp * ramp) * h2) / kArcSteps;
  }
  return m;
}

float strandW(const FitStrands& s, std::size_t i, int face, const glm::vec2& st,
              const BaseCurves& base, const FittedStyle& curl, float* w) {
  const int M = s.samples;
  const ArcMap m = arcMap(base, face, st, curl, s.medianPoints);
  const float tip = m.wAt(s.length[i]);
  const float stretch = tip > 1.0f && m.full() > 0.0f ? s.length[i] / m.full() : 1.0f;
  const glm::vec3* p = s.strand(i);
  const float L1 = static_cast<float>(base.layerCount() - 1);
  std::vector<float> guess(M);
  std::vector<BaseSample> bs(M);
  for (int k = 0; k < M; ++k)
    guess[k] = m.wAt(s.length[i] * static_cast<float>(k) / static_cast<float>(M - 1) / stretch);
  // points past the end of the base curve keep the guess (extrapolated in arc length)
  for (int it = 0; it < 3; ++it) {
    for (int k = 0; k < M; ++k) w[k] = std::min(guess[k], 1.0f);
    base.evaluate(face, st, w, M, bs.data());
    for (int k = 1; k < M; ++k) {
      if (guess[k] >= 1.0f) continue;
      const glm::vec3 d = bs[k].deriv * L1;  // dB/dw
      const float d2 = glm::dot(d, d);
      if (!(d2 > 0.0f)) continue;
      const float step = glm::dot(p[k] - bs[k].pos, d) / d2;
      // a step of at most a fortieth of the curve: the guess is close, a far projection is
      // a different part of a strongly bent curve
      guess[k] = std::clamp(guess[k] + std::clamp(step, -0.025f, 0.025f), 0.0f, 1.0f);
    }
  }
  w[0] = 0.0f;
  for (int k = 1; k < M; ++k) w[k] = std::max(guess[k], w[k - 1]);
  return w[M - 1];
}

}  // namespace clhair::fit
