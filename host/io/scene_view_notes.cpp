// scene_view_notes.cpp — what a scene will look like that its author may not expect, said
// before the render as note lines (view_notes.h): a strand-file groom whose
// fibres are far thinner than a pixel and whose drawn hair covers a small share of its
// screen box (it draws as a faint ghost; the note names "min_hit_diameter_px"), and a scene
// without lights (the hair is lit by the ambient term alone).
//
// The share is estimated on the host from the strands as the camera sees them: each
// segment's projected length times the fibre's projected width, summed (children counted
// by their guides), over the area of the groom's projected bounding box clipped to the
// image. At most kMaxSampled strands are projected (an even stride over the rest).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "io/view_notes.h"

namespace clhair {

namespace {

constexpr std::size_t kMaxSampled = 20000;
// Fibres under a quarter of a pixel whose hair covers under 5 % of its screen box: a scan
// subset of 100 strands, a guides-only export. Dense grooms cover most of their box.
constexpr float kThinPx = 0.25f;
constexpr double kSparseShare = 0.05;

}  // namespace

std::vector<std::string> viewNotes(const Scene& scene, const std::string& where) {
  std::vector<std::string> out;
  const Camera& c = scene.camera;
  const glm::vec3 f = glm::normalize(c.target - c.position);
  const glm::vec3 right = glm::normalize(glm::cross(f, c.up)), up = glm::cross(right, f);
  const float fy =
      0.5f * static_cast<float>(scene.height) / std::tan(glm::radians(c.fovYDegrees) * 0.5f);
  const float w = static_cast<float>(scene.width), h = static_cast<float>(scene.height);
  for (std::size_t gi = 0; gi < scene.grooms.size(); ++gi) {
    const GroomInstance& g = scene.grooms[gi];
    if (!g.strands || g.strands->pointCounts.empty()) continue;
    const StrandGroom& s = *g.strands;
    if (s.appearance.minHitDiameterPx > 0.0f || !s.thickness.empty()) continue;
    const std::size_t strands = s.pointCounts.size();
    const std::size_t stride = (strands + kMaxSampled - 1) / kMaxSampled;
    double area = 0.0, widthSum = 0.0;
    std::size_t widthCount = 0;
    glm::vec2 lo(w, h), hi(0.0f);
    std::size_t at = 0;
    for (std::size_t i = 0; i < strands; at += s.pointCounts[i], ++i) {
      if (i % stride != 0) continue;
      glm::vec3 prev(0.0f);
      bool prevOk = false;
      for (std::uint32_t k = 0; k < s.pointCounts[i]; ++k) {
        const glm::vec3 p = glm::vec3(g.transform * glm::vec4(s.points[at + k], 1.0f));
        const glm::vec3 d = p - c.position;
        const float z = glm::dot(d, f);
        const bool ok = z > 1e-4f;
        glm::vec3 q(0.0f);  // pixel x, y and the fibre's width in pixels
        if (ok) {
          q = glm::vec3(0.5f * w + fy * glm::dot(d, right) / z, 0.5f * h - fy * glm::dot(d, up) / z,
                        fy * s.appearance.strandWidth / z);
          lo = glm::min(lo, glm::vec2(q));
          hi = glm::max(hi, glm::vec2(q));
          widthSum += q.z;
          ++widthCount;
        }
        if (ok && prevOk)
          area += static_cast<double>(glm::length(glm::vec2(q) - glm::vec2(prev))) * 0.5 *
                  static_cast<double>(q.z + prev.z);
        prev = q;
        prevOk = ok;
      }
    }
    lo = glm::max(lo, glm::vec2(0.0f));
    hi = glm::min(hi, glm::vec2(w, h));
    if (widthCount == 0 || !(hi.x > lo.x && hi.y > lo.y)) continue;
    const double box = static_cast<double>(hi.x - lo.x) * static_cast<double>(hi.y - lo.y);
    const double copies = static_cast<double>(stride) * (1.0 + s.children.count);
    const double share = std::min(area * copies / box, 1.0);
    const double widthPx = widthSum / static_cast<double>(widthCount);
    if (widthPx >= kThinPx || share >= kSparseShare) continue;
    char buf[400];
    std::snprintf(buf, sizeof(buf),
                  "grooms[%zu] (\"%s\"): its fibres are %.2g pixels wide and its hair covers "
                  "about %.2g %% of its %.0fx%.0f-pixel screen box, so it draws faint; "
                  "\"appearance\": {\"min_hit_diameter_px\": 1} draws each strand at least a "
                  "pixel wide",
                  gi, g.name.c_str(), widthPx, 100.0 * share, static_cast<double>(hi.x - lo.x),
                  static_cast<double>(hi.y - lo.y));
    out.push_back(where + ": " + buf);
  }
  if (scene.lights.empty() && !scene.environment.enabled && !scene.grooms.empty()) {
    char buf[200];
    std::snprintf(buf, sizeof(buf),
                  "the scene has no lights, so the hair is lit by the ambient [%g, %g, %g] "
                  "alone (dim and flat); add \"lights\" or an \"environment\"",
                  static_cast<double>(scene.ambient.x), static_cast<double>(scene.ambient.y),
                  static_cast<double>(scene.ambient.z));
    out.push_back(where + ": " + buf);
  }
  return out;
}

}  // namespace clhair
