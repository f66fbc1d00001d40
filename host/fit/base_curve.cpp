// base_curve.cpp — see base_curve.h.
#include "fit/base_curve.h"

#include <algorithm>
#include <cmath>

namespace clhair::fit {

namespace {
glm::vec3 v3(const float* p) { return glm::vec3(p[0], p[1], p[2]); }
}  // namespace

BaseCurves::BaseCurves(const HairMesh& mesh)
    : data_(prepareGroom(mesh)),
      layers_(mesh.layerCount),
      vertices_(mesh.vertexCount),
      hasTangents_(!mesh.tangents.empty()) {}

void BaseCurves::evaluate(int face, const glm::vec2& st, const float* w, int count,
                          BaseSample* out) const {
  const gpu::ClhBundle& b = data_.bundles[face];
  const int L = layers_;
  const float s = st.x, t = st.y;
  const float wq[4] = {(1 - s) * (1 - t), s * (1 - t), s * t, (1 - s) * t};
  glm::vec3 pos[CLH_MAX_LAYERS], tan[CLH_MAX_LAYERS], du[CLH_MAX_LAYERS], dv[CLH_MAX_LAYERS];
  for (int l = 0; l < L; ++l) {
    pos[l] = tan[l] = du[l] = dv[l] = glm::vec3(0.0f);
    for (int c = 0; c < 4; ++c) {
      const gpu::ClhMeshVertex& mv =
          data_.vertices[static_cast<std::size_t>(l) * vertices_ + b.vtx[c]];
      pos[l] += wq[c] * v3(mv.pos);
      tan[l] += wq[c] * v3(mv.tan);
      du[l] += wq[c] * v3(mv.du);
      dv[l] += wq[c] * v3(mv.dv);
    }
  }
  if (!hasTangents_)
    for (int l = 0; l < L; ++l) {
      if (l == 0)
        tan[l] = pos[1] - pos[0];
      else if (l == L - 1)
        tan[l] = pos[L - 1] - pos[L - 2];
      else
        tan[l] = 0.5f * (pos[l + 1] - pos[l - 1]);
    }
  for (int k = 0; k < count; ++k) {
    const float x = std::clamp(w[k], 0.0f, 1.0f) * static_cast<float>(L - 1);
    const int i = std::max(0, std::min(static_cast<int>(std::floor(x)), L - 2));
    const float u = x - static_cast<float>(i);
    const float u2 = u * u, u3 = u2 * u;
    const float h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2,
                h11 = u3 - u2;
    const float d00 = 6 * u2 - 6 * u, d10 = 3 * u2 - 4 * u + 1, d01 = -6 * u2 + 6 * u,
                d11 = 3 * u2 - 2 * u;
    BaseSample& o = out[k];
    o.pos = h00 * pos[i] + h10 * tan[i] + h01 * pos[i + 1] + h11 * tan[i + 1];
    o.deriv = d00 * pos[i] + d10 * tan[i] + d01 * pos[i + 1] + d11 * tan[i + 1];
    o.du = du[i] + (du[i + 1] - du[i]) * u;
    o.dv = dv[i] + (dv[i + 1] - dv[i]) * u;
    o.w = w[k];
  }
}

}  // namespace clhair::fit
