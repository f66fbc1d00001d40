// base_curve.h — a fitted bundle's base curve at any root (s, t) and styling w, as the
// strand generator builds it (docs/hair-mesh-format.md, "How strands are generated", steps
// 2-3): the bilinear layer samples of the face, finite-difference layer tangents unless the
// mesh stores them, cubic Hermite between layers, and the styling frame directions du, dv
// interpolated linearly between layers. Only styling is left out: the fitter compares input
// strands with these curves to find what the styling has to add.
#pragma once

#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "clhair/hair_mesh.h"
#include "groom/groom_data.h"

namespace clhair::fit {

struct BaseSample {
  glm::vec3 pos, deriv, du, dv;
  float w = 0.0f;
};

class BaseCurves {
 public:
  explicit BaseCurves(const HairMesh& mesh);
  // Samples of face `face`'s base curve at root (s, t) for each styling w in `w` (0..1).
  void evaluate(int face, const glm::vec2& st, const float* w, int count, BaseSample* out) const;
  const GroomData& data() const { return data_; }
  int vertexCount() const { return vertices_; }
  int layerCount() const { return layers_; }

 private:
  GroomData data_;
  int layers_ = 0, vertices_ = 0;
  bool hasTangents_ = false;
};

}  // namespace clhair::fit
