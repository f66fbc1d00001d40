// arc_model.cpp — see arc_model.h.
#include "fit/arc_model.h"

#include <algorithm>
#include <cmath>

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

ArcMap arcMap(const BaseCurves& base, int face, const glm::vec2& st, const FittedStyle& curl) {
  // the speed at the midpoints of kArcSteps intervals (midpoint rule)
  float w[kArcSteps];
  BaseSample bs[kArcSteps];
  for (int j = 0; j < kArcSteps; ++j) w[j] = (static_cast<float>(j) + 0.5f) / kArcSteps;
  base.evaluate(face, st, w, kArcSteps, bs);
  const float layers = static_cast<float>(base.layerCount());
  const float c = 2.0f * 3.14159265f * curl.curlFrequency * curl.curlAmplitude;
  const float h2 = 0.5f * (1.0f + curl.curlHelix * curl.curlHelix);
  ArcMap m;
  m.arc[0] = 0.0f;
  for (int j = 0; j < kArcSteps; ++j) {
    const glm::vec3 d = bs[j].deriv * (layers - 1.0f);  // dP/dw
    const float r = c * smooth01(w[j] / 0.15f);
    m.arc[j + 1] = m.arc[j] + std::sqrt(glm::dot(d, d) + r * r * h2) / kArcSteps;
  }
  return m;
}

}  // namespace clhair::fit
