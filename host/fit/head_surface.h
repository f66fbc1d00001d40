// head_surface.h — closest points on a head mesh, for fitting a hair mesh with `--head`.
//
// The triangles are binned into a uniform grid over their bounds; a query visits cells in
// growing shells around the point until no nearer triangle can remain. Used to place the
// fitted root layer on the scalp and to orient the scalp chart by the surface.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "clhair/triangle_mesh.h"

namespace clhair::fit {

class HeadSurface {
 public:
  explicit HeadSurface(const TriangleMesh& mesh);
  // The closest point of the surface to p and the unit normal of its triangle (oriented
  // away from the mesh's centroid).
  glm::vec3 closest(const glm::vec3& p, glm::vec3* normal = nullptr) const;

 private:
  std::vector<glm::vec3> a_, b_, c_;  // triangle corners
  glm::vec3 lo_{0.0f}, centroid_{0.0f};
  float cell_ = 1.0f;
  int nx_ = 1, ny_ = 1, nz_ = 1;
  std::vector<std::uint32_t> start_, items_;  // CSR: cell -> triangles
  int cellIndex(int x, int y, int z) const { return (z * ny_ + y) * nx_ + x; }
};

}  // namespace clhair::fit
