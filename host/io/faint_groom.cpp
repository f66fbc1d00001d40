// faint_groom.cpp — the faint-groom estimate of faint_groom.h, from the strands as the view
// sees them.
#include "io/faint_groom.h"

#include <algorithm>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace clhair {

FaintEstimate estimateFaint(const StrandGroom& s, const glm::mat4& objToView,
                            const FaintView& view) {
  FaintEstimate e;
  const std::size_t strands = s.pointCounts.size();
  if (strands == 0 || view.width == 0 || view.height == 0) return e;
  const float w = static_cast<float>(view.width), h = static_cast<float>(view.height);
  const std::size_t stride = (strands + kFaintMaxSampled - 1) / kFaintMaxSampled;
  double area = 0.0, widthSum = 0.0;
  std::size_t widthCount = 0;
  glm::vec2 lo(w, h), hi(0.0f);
  std::size_t at = 0;
  for (std::size_t i = 0; i < strands; at += s.pointCounts[i], ++i) {
    if (i % stride != 0) continue;
    glm::vec3 prev(0.0f);
    bool prevOk = false;
    for (std::uint32_t k = 0; k < s.pointCounts[i]; ++k) {
      const glm::vec4 p = objToView * glm::vec4(s.points[at + k], 1.0f);
      const bool ok = p.z > 1e-4f;
      glm::vec3 q(0.0f);  // pixel x, y and the fibre's width in pixels
      if (ok) {
        const float iz = 1.0f / p.z;
        q = glm::vec3(view.cx + view.fx * p.x * iz, view.cy - view.fy * p.y * iz,
                      view.fy * s.appearance.strandWidth * iz);
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
  if (widthCount == 0 || !(hi.x > lo.x && hi.y > lo.y)) return e;
  const double box = static_cast<double>(hi.x - lo.x) * static_cast<double>(hi.y - lo.y);
  const double copies = static_cast<double>(stride) * (1.0 + s.children.count);
  e.seen = true;
  e.share = std::min(area * copies / box, 1.0);
  e.widthPx = widthSum / static_cast<double>(widthCount);
  e.boxW = hi.x - lo.x;
  e.boxH = hi.y - lo.y;
  return e;
}

}  // namespace clhair
