// scene_view_notes.cpp — what a scene will look like that its author may not expect, said
// before the render as note lines (view_notes.h): a strand-file groom whose
// fibres are far thinner than a pixel and whose drawn hair covers a small share of its
// screen box where the render does not widen it (it draws as a faint ghost; the note names
// "min_hit_diameter_px"), and a scene without lights (the hair is lit by the ambient term
// alone).
//
// The share is estimated on the host from the strands as the camera sees them
// (faint_groom.h). A render whose filter runs draws such a groom at least a pixel wide with
// the alpha of its true width itself, so the note is for the renders that cannot (MSAA
// above 1, the filter off).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "io/faint_groom.h"
#include "io/view_notes.h"

namespace clhair {

std::vector<std::string> viewNotes(const Scene& scene, const std::string& where, bool widensFaint) {
  std::vector<std::string> out;
  const Camera& c = scene.camera;
  const glm::vec3 f = glm::normalize(c.target - c.position);
  const glm::vec3 right = glm::normalize(glm::cross(f, c.up)), up = glm::cross(right, f);
  glm::mat4 worldToView(1.0f);
  for (int k = 0; k < 3; ++k) {
    worldToView[k][0] = right[k];
    worldToView[k][1] = up[k];
    worldToView[k][2] = f[k];
  }
  worldToView[3] = glm::vec4(-glm::dot(right, c.position), -glm::dot(up, c.position),
                             -glm::dot(f, c.position), 1.0f);
  FaintView view;
  view.fy = view.fx =
      0.5f * static_cast<float>(scene.height) / std::tan(glm::radians(c.fovYDegrees) * 0.5f);
  view.cx = 0.5f * static_cast<float>(scene.width);
  view.cy = 0.5f * static_cast<float>(scene.height);
  view.width = static_cast<std::uint32_t>(scene.width);
  view.height = static_cast<std::uint32_t>(scene.height);
  for (std::size_t gi = 0; gi < scene.grooms.size() && !widensFaint; ++gi) {
    const GroomInstance& g = scene.grooms[gi];
    if (!g.strands || g.strands->pointCounts.empty()) continue;
    const StrandGroom& s = *g.strands;
    if (s.appearance.minHitDiameterPx > 0.0f || !s.thickness.empty()) continue;
    const FaintEstimate e = estimateFaint(s, worldToView * g.transform, view);
    if (!e.faint()) continue;
    char buf[400];
    std::snprintf(buf, sizeof(buf),
                  "grooms[%zu] (\"%s\"): its fibres are %.2g pixels wide and its hair covers "
                  "about %.2g %% of its %.0fx%.0f-pixel screen box, so it draws faint at this "
                  "sample count; \"appearance\": {\"min_hit_diameter_px\": 1} draws each strand "
                  "at least a pixel wide",
                  gi, g.name.c_str(), e.widthPx, 100.0 * e.share, static_cast<double>(e.boxW),
                  static_cast<double>(e.boxH));
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
