// scalp_chart.h — a flat map of the scalp on which the fitter lays out bundles and uv.
//
// The roots (or, with a head mesh, their closest points on it) are fitted by a sphere when
// they curve like a head or a ball and by a plane when they are nearly flat. A sphere is
// mapped azimuthally about the roots' mean direction (equidistant: chart distance from the
// pole is arc length on the sphere), a plane by its two principal directions. Chart units
// are metres; the chart's +x, +y and the surface normal form a right-handed frame, so a
// face counter-clockwise in the chart is counter-clockwise seen from outside.
// Roots opposite the pole of a sphere (a scalp covering the whole ball) are distorted: the
// map is singular there (docs/fitting.md, "What it cannot fit").
#pragma once

#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace clhair::fit {

class HeadSurface;

struct ScalpChart {
  bool sphere = false;
  glm::vec3 centre{0.0f};            // sphere centre, or a point of the plane
  float radius = 0.0f;               // sphere only
  glm::vec3 axis{0.0f, 1.0f, 0.0f};  // sphere: the pole; plane: the normal (toward the hair)
  glm::vec3 b1{1.0f, 0.0f, 0.0f}, b2{0.0f, 0.0f, -1.0f};  // b1 x b2 = axis

  glm::vec2 toChart(const glm::vec3& p) const;
  glm::vec3 fromChart(const glm::vec2& c) const;  // onto the sphere or plane
  // Unit 3D directions of chart +x and +y at chart point c, and the outward normal there.
  void frameAt(const glm::vec2& c, glm::vec3& ex, glm::vec3& ey, glm::vec3& normal) const;
};

// `roots` and `growth` (each strand's direction near its root) per strand; `head` optional.
ScalpChart fitScalpChart(const std::vector<glm::vec3>& roots, const std::vector<glm::vec3>& growth,
                         const HeadSurface* head);

}  // namespace clhair::fit
