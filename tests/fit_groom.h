// fit_groom.h — grooms for the fitting tests: hair meshes with known cages and styling, and
// their strands generated on the CPU (the generator's reference, host/groom/reference.h),
// as the StrandGroom a strand file would give the fitter.
#pragma once

#include <cmath>

#include <glm/geometric.hpp>

#include "clhair/hair_mesh.h"
#include "clhair/strand_groom.h"
#include "fit/fit_error.h"

namespace clhair::test {

// A square patch of cells x cells quads, `size` metres across in x and z at y = 0, uv
// [0, 1]^2, its strands `length` long growing up +y and bending toward +z along an arc.
// `twist` turns layer l about the patch's vertical axis by l * twist radians (a rope),
// `spread` bends them toward +x, a patch moved to the left (`xShift` < 0) toward -x: two
// such patches side by side part at x = 0.
struct PatchShape {
  int cells = 8, layers = 5;
  float size = 0.1f, length = 0.1f;
  float twist = 0.0f, spread = 0.0f, xShift = 0.0f;
};

inline HairMesh patchMesh(const PatchShape& p) {
  HairMesh m;
  m.name = "patch";
  m.layerCount = p.layers;
  const int n = p.cells + 1;
  m.vertexCount = n * n;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) m.uv.push_back(glm::vec2(i, j) / static_cast<float>(p.cells));
  for (int j = 0; j < p.cells; ++j)
    for (int i = 0; i < p.cells; ++i) {
      const int a = j * n + i;
      m.faces.push_back({a, a + 1, a + n + 1, a + n});
    }
  m.positions.resize(static_cast<std::size_t>(p.layers) * m.vertexCount);
  for (int l = 0; l < p.layers; ++l) {
    const float s = static_cast<float>(l) / static_cast<float>(p.layers - 1);
    const float R = 1.2f * p.length, a = s * p.length / R;  // arc length s * length
    const float c = std::cos(l * p.twist), sn = std::sin(l * p.twist);
    for (int v = 0; v < m.vertexCount; ++v) {
      const glm::vec2 uv = m.uv[v];
      const float x0 = p.size * (uv.x - 0.5f), z0 = p.size * (uv.y - 0.5f);
      const float x = c * x0 + sn * z0, z = -sn * x0 + c * z0;
      // a shifted patch is one side of a parting; a centred one parts at its middle
      const float side =
          p.xShift != 0.0f ? (p.xShift > 0.0f ? 1.0f : -1.0f) : (x0 >= 0.0f ? 1.0f : -1.0f);
      m.positions[static_cast<std::size_t>(l) * m.vertexCount + v] = glm::vec3(
          x + p.xShift + side * p.spread * s * s, R * std::sin(a), z + R * (1.0f - std::cos(a)));
    }
  }
  m.strandCount = 20000;
  m.controlPoints = 33;
  m.seed = 3;
  m.appearance.strandWidth = 7e-5f;
  return m;
}

// The known cage's point on layer l for a root at (x, z) of a patch made by patchMesh (its
// bilinear interpolation at the root's cell and (s, t)).
inline glm::vec3 patchCagePoint(const HairMesh& m, const PatchShape& p, float x, float z, int l) {
  const float u = std::clamp((x - p.xShift) / p.size + 0.5f, 0.0f, 1.0f) * p.cells;
  const float v = std::clamp(z / p.size + 0.5f, 0.0f, 1.0f) * p.cells;
  const int i = std::min(static_cast<int>(u), p.cells - 1),
            j = std::min(static_cast<int>(v), p.cells - 1);
  const float s = u - i, t = v - j;
  const int n = p.cells + 1, a = j * n + i;
  return (1 - s) * (1 - t) * m.position(l, a) + s * (1 - t) * m.position(l, a + 1) +
         s * t * m.position(l, a + n + 1) + (1 - s) * t * m.position(l, a + n);
}

// The strands the generator makes for `mesh`, as a strand file would hold them.
inline StrandGroom strandsOf(const HairMesh& mesh) {
  const fit::GeneratedStrands g = fit::generateStrandsCpu(mesh, 0);
  StrandGroom s;
  s.name = mesh.name;
  s.pointCounts.assign(g.count(), static_cast<std::uint32_t>(g.points));
  s.points = g.data;
  s.appearance = mesh.appearance;
  return s;
}

inline void append(StrandGroom& to, const StrandGroom& from) {
  to.pointCounts.insert(to.pointCounts.end(), from.pointCounts.begin(), from.pointCounts.end());
  to.points.insert(to.points.end(), from.points.begin(), from.points.end());
}

}  // namespace clhair::test
