// draw_warnings.cpp — see draw_warnings.h.
#include "io/draw_warnings.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace clhair {

namespace {

// The near limit below which the renderer draws nothing of a groom (every point at a view
// depth of at most this is "behind the camera": host/stages/view_math.cpp, depthRange).
constexpr float kNearLimit = 1e-4f;

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.3g", v);
  return buf;
}

// The world-space points of an instance as this frame draws them (the cage, if moved).
template <typename F>
void forEachPoint(const GroomInstance& g, F f) {
  const std::vector<glm::vec3>* points = nullptr;
  if (g.deformed)
    points = g.deformed.get();
  else if (g.mesh)
    points = &g.mesh->positions;
  else if (g.strands)
    points = &g.strands->points;
  if (!points) return;
  for (const glm::vec3& p : *points) f(glm::vec3(g.transform * glm::vec4(p, 1.0f)));
}

std::string reason(const Scene& scene, const GroomInstance& g, const FrameStats& stats) {
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  bool finite = true;
  forEachPoint(g, [&](const glm::vec3& w) {
    finite = finite && std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z);
    lo = glm::min(lo, w);
    hi = glm::max(hi, w);
  });
  if (!finite) return "its transform takes points beyond float range";
  const glm::vec3 ext = hi - lo;
  const float size = std::max(ext.x, std::max(ext.y, ext.z));
  const Camera& c = scene.camera;
  const glm::vec3 forward = glm::normalize(c.target - c.position);
  const glm::vec3 right = glm::normalize(glm::cross(forward, c.up));
  const glm::vec3 up = glm::cross(right, forward);
  const float fy =
      0.5f * static_cast<float>(scene.height) / std::tan(glm::radians(c.fovYDegrees) * 0.5f);
  float zmin = INFINITY, zmax = -INFINITY;
  float xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
  bool allInFront = true;
  for (int k = 0; k < 8; ++k) {
    const glm::vec3 p((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
    const glm::vec3 d = p - c.position;
    const float z = glm::dot(d, forward);
    zmin = std::min(zmin, z);
    zmax = std::max(zmax, z);
    if (z <= kNearLimit) {
      allInFront = false;
      continue;
    }
    const float x = 0.5f * scene.width + fy * glm::dot(d, right) / z;
    const float y = 0.5f * scene.height - fy * glm::dot(d, up) / z;
    xmin = std::min(xmin, x);
    xmax = std::max(xmax, x);
    ymin = std::min(ymin, y);
    ymax = std::max(ymax, y);
  }
  const std::string across = fmt(size) + " units across";
  if (!(size > 0.0f))
    return "all its points lie at one place (0 units across): a collapsing transform or file?";
  if (zmax <= kNearLimit && size < kNearLimit)
    return "it is " + across + ", too small to place in front of the camera (the renderer's " +
           "near limit is " + fmt(kNearLimit) + " units; a camera preset cannot frame it): are " +
           "its units right? check its \"scale\"";
  if (zmax <= 0.0f) return "it is behind the camera";
  if (zmax <= kNearLimit)
    return "it is " + across + " and at most " + fmt(zmax) + " units in front of the camera, " +
           "inside the renderer's near limit of " + fmt(kNearLimit) + " units";
  if (allInFront) {
    if (xmax < 0.0f || ymax < 0.0f || xmin > scene.width || ymin > scene.height)
      return "it is outside the view";
    const float pixels = std::max(xmax - xmin, ymax - ymin);
    if (pixels < 1.0f)
      return "it covers " + fmt(pixels) + " pixels (" + across + ", " + fmt(0.5f * (zmin + zmax)) +
             " away): are its units right? check its \"scale\"";
  }
  if (stats.overBudget) return "the segment budget left it no strand";
  return "its LOD left it no strand (" + across + ")";
}

}  // namespace

std::vector<std::string> drawWarnings(const Scene& scene, const FrameStats& stats,
                                      const std::string& where) {
  std::vector<std::string> out;
  for (const GroomDrawStats& d : stats.grooms) {
    if (d.instance >= scene.grooms.size()) continue;
    const GroomInstance& g = scene.grooms[d.instance];
    const std::uint64_t strands =
        g.mesh      ? static_cast<std::uint64_t>(std::max<std::int64_t>(0, g.mesh->strandCount))
        : g.strands ? g.strands->pointCounts.size()
                    : 0;
    if (strands == 0 || (d.drawn && d.strands > 0)) continue;
    out.push_back(where + ": grooms[" + std::to_string(d.instance) + "] (\"" + g.name +
                  "\") draws none of its " + std::to_string(strands) +
                  " strands: " + reason(scene, g, stats));
  }
  return out;
}

}  // namespace clhair
