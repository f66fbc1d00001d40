// fit_groom.h — grooms for the fitting tests: hair meshes with known cages and styling, and
// their strands generated on the CPU (the generator's reference, host/groom/reference.h),
// as the StrandGroom a strand file would give the fitter.
#pragma once

#include <cmath>

#include "clhair/hair_mesh.h"
#include "clhair/strand_groom.h"
#include "fit/fit_error.h"

namespace clhair::test {

// A square patch of cells x cells quads, `size` metres across in x and z at y = 0, uv
// [0, 1]^2, its strands `length` long growing up +y and bending toward +z. No styling.
inline HairMesh patchMesh(int cells, int layers, float size, float length) {
  HairMesh m;
  m.name = "patch";
  m.layerCount = layers;
  const int n = cells + 1;
  m.vertexCount = n * n;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) m.uv.push_back(glm::vec2(i, j) / static_cast<float>(cells));
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      const int a = j * n + i;
      m.faces.push_back({a, a + 1, a + n + 1, a + n});
    }
  m.positions.resize(static_cast<std::size_t>(layers) * m.vertexCount);
  for (int l = 0; l < layers; ++l) {
    const float s = static_cast<float>(l) / static_cast<float>(layers - 1);
    for (int v = 0; v < m.vertexCount; ++v) {
      const glm::vec2 uv = m.uv[v];
      // an arc of radius R in the y-z plane: arc length s * length from the root
      const float R = 1.2f * length, a = s * length / R;
      m.positions[static_cast<std::size_t>(l) * m.vertexCount + v] =
          glm::vec3(size * (uv.x - 0.5f), R * std::sin(a), size * (uv.y - 0.5f) + R * (1.0f - std::cos(a)));
    }
  }
  m.strandCount = 20000;
  m.controlPoints = 33;
  m.seed = 3;
  m.appearance.strandWidth = 7e-5f;
  return m;
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

}  // namespace clhair::test
