// scalp_chart.cpp — see scalp_chart.h.
#include "fit/scalp_chart.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "fit/head_surface.h"
#include "fit/linear_algebra.h"

namespace clhair::fit {

namespace {

glm::vec3 anyPerpendicular(const glm::vec3& n) {
  glm::vec3 t = std::fabs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
  return glm::normalize(t - glm::dot(t, n) * n);
}

// Algebraic sphere fit: |p|^2 = 2 c.p + k, least squares in (c, k) (double, centred).
bool fitSphere(const std::vector<glm::dvec3>& pts, glm::dvec3& centre, double& radius) {
  double m[4][4] = {}, rhs[4] = {};
  for (const glm::dvec3& p : pts) {
    const double row[4] = {2 * p.x, 2 * p.y, 2 * p.z, 1.0};
    const double y = glm::dot(p, p);
    for (int i = 0; i < 4; ++i) {
      rhs[i] += row[i] * y;
      for (int j = 0; j < 4; ++j) m[i][j] += row[i] * row[j];
    }
  }
  double x[4];
  if (!solveDense(&m[0][0], rhs, x, 4)) return false;
  centre = glm::dvec3(x[0], x[1], x[2]);
  const double r2 = x[3] + glm::dot(centre, centre);
  if (!(r2 > 0.0) || !std::isfinite(r2)) return false;
  radius = std::sqrt(r2);
  return true;
}

}  // namespace

glm::vec2 ScalpChart::toChart(const glm::vec3& p) const {
  if (!sphere) {
    const glm::vec3 d = p - centre;
    return glm::vec2(glm::dot(d, b1), glm::dot(d, b2));
  }
  glm::vec3 q = p - centre;
  const float l = glm::length(q);
  q = l > 0.0f ? q / l : axis;
  const float cosT = std::clamp(glm::dot(q, axis), -1.0f, 1.0f);
  const float theta = std::acos(cosT);
  const glm::vec2 planar(glm::dot(q, b1), glm::dot(q, b2));
  const float s = glm::length(planar);
  if (s < 1e-7f) return glm::vec2(radius * theta, 0.0f);
  return planar * (radius * theta / s);
}

glm::vec3 ScalpChart::fromChart(const glm::vec2& c) const {
  if (!sphere) return centre + c.x * b1 + c.y * b2;
  const float r = glm::length(c);
  const float theta = std::min(r / radius, 3.14159f);
  const glm::vec2 dir = r > 0.0f ? c / r : glm::vec2(1.0f, 0.0f);
  return centre + radius * (std::cos(theta) * axis + std::sin(theta) * (dir.x * b1 + dir.y * b2));
}

void ScalpChart::frameAt(const glm::vec2& c, glm::vec3& ex, glm::vec3& ey,
                         glm::vec3& normal) const {
  if (!sphere) {
    ex = b1;
    ey = b2;
    normal = axis;
    return;
  }
  const float e = 1e-3f * radius;
  const glm::vec3 dx = fromChart(c + glm::vec2(e, 0)) - fromChart(c - glm::vec2(e, 0));
  const glm::vec3 dy = fromChart(c + glm::vec2(0, e)) - fromChart(c - glm::vec2(0, e));
  normal = glm::normalize(fromChart(c) - centre);
  ex = dx - glm::dot(dx, normal) * normal;
  ex = glm::length(ex) > 0.0f ? glm::normalize(ex) : anyPerpendicular(normal);
  ey = glm::cross(normal, ex);
  if (glm::dot(ey, dy) < 0.0f) ey = -ey;
}

ScalpChart fitScalpChart(const std::vector<glm::vec3>& roots, const std::vector<glm::vec3>& growth,
                         const HeadSurface* head) {
  ScalpChart chart;
  // Sample at most 20 000 roots (evenly) for the fits; project onto the head when given.
  const std::size_t n = roots.size();
  const std::size_t step = std::max<std::size_t>(1, n / 20000);
  std::vector<glm::dvec3> pts;
  glm::dvec3 mean(0.0), meanGrowth(0.0);
  for (std::size_t i = 0; i < n; i += step) {
    glm::vec3 p = head ? head->closest(roots[i]) : roots[i];
    pts.push_back(glm::dvec3(p));
    mean += glm::dvec3(p);
    meanGrowth += glm::dvec3(growth[i]);
  }
  mean /= static_cast<double>(pts.size());
  // principal directions of the roots
  double cov[9] = {};
  for (const glm::dvec3& p : pts) {
    const glm::dvec3 d = p - mean;
    const double v[3] = {d.x, d.y, d.z};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) cov[3 * i + j] += v[i] * v[j] / static_cast<double>(pts.size());
  }
  double evals[3];
  glm::dvec3 evecs[3];
  symmetricEigen3(cov, evals, evecs);  // descending
  const double extent = std::sqrt(std::max(evals[0], 0.0));
  const glm::vec3 g =
      glm::length(meanGrowth) > 0.0 ? glm::vec3(glm::normalize(meanGrowth)) : glm::vec3(0, 1, 0);

  // plane: the smallest principal direction, turned toward the hair
  glm::vec3 normal = glm::vec3(evecs[2]);
  if (!(glm::length(normal) > 0.5f)) normal = g;
  if (glm::dot(normal, g) < 0.0f) normal = -normal;
  double planeRms = std::sqrt(std::max(evals[2], 0.0));

  glm::dvec3 c;
  double r = 0.0;
  bool useSphere = false;
  if (pts.size() >= 8 && extent > 0.0 && evals[2] > 1e-6 * evals[0] && fitSphere(pts, c, r) &&
      r < 20.0 * extent) {
    double ss = 0.0;
    for (const glm::dvec3& p : pts) {
      const double d = glm::length(p - c) - r;
      ss += d * d;
    }
    const double sphereRms = std::sqrt(ss / static_cast<double>(pts.size()));
    useSphere = sphereRms < 0.5 * planeRms;
  }
  if (useSphere) {
    chart.sphere = true;
    chart.centre = glm::vec3(c);
    chart.radius = static_cast<float>(r);
    glm::dvec3 dirSum(0.0);
    for (const glm::dvec3& p : pts) dirSum += glm::normalize(p - c);
    glm::vec3 axis = glm::length(dirSum) > 0.1 * static_cast<double>(pts.size())
                         ? glm::vec3(glm::normalize(dirSum))
                         : glm::vec3(glm::normalize(mean - c));
    if (!(glm::length(axis) > 0.5f)) axis = g;
    chart.axis = axis;
  } else {
    chart.sphere = false;
    chart.centre = glm::vec3(mean);
    chart.axis = normal;
  }
  // b1: world x made perpendicular to the axis (z when x is nearly parallel), so charts of
  // similar grooms are laid out alike
  chart.b1 = anyPerpendicular(chart.axis);
  chart.b2 = glm::cross(chart.axis, chart.b1);
  return chart;
}

}  // namespace clhair::fit
