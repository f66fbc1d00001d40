// children.h — children grown from the guides of an explicit groom: their device record,
// the guide-neighbour table of interpolated children, and a CPU reference of the rules that
// kernels/common/children.h draws (written apart from the kernel, for clarity).
//
// Guide g is stored strand g of ExplicitData (LOD order), with n points g_0 .. g_{n-1}. Child
// c >= 1 of guide g draws n points too, point k at t_k = k / (n - 1):
//   offset  o = a t0 + b t1, a and b uniform in [-R, R] from clh_hash3(seed, g, c), t0 and t1
//           a basis across the guide's root direction (g_1 - g_0), as TressFX's follow hairs;
//   growth  F_k = (1 + s k / n) (1 - kappa_k): s the tip spread (TressFX's tip separation
//           factor), kappa_k = clump t_k for clump >= 0 (tips gather, Blender's clump),
//           -clump (1 - t_k) below 0 (roots gather);
//   follow        p_k = g_k + o F_k;
//   interpolated  the child's root r = g_0 + o; among guide g and its neighbours (the
//           CLH_CHILD_NEIGHBOURS guides with the nearest roots) the three roots nearest r, at
//           squared distances d_i, weigh w_i = 1/d_i - 1/d_4 (d_4: the fourth nearest, or 0
//           when there is none), normalised, or 1 for a root at r itself; with q_i(t) guide i
//           at parameter t (linear between its points) and B(t) = sum w_i q_i(t),
//           p_k = B(t_k) + (r - B(0)) F_k.
// A child whose root is a guide's root follows that guide; one equally far from three guides
// follows their average (Blender's interpolated children blend the nearest guides the same
// way; the taper by d_4 keeps the blend continuous where the nearest three change).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "clhair/gpu_types.h"
#include "groom/explicit_data.h"

namespace clhair {

// For each guide (ExplicitData order) the CLH_CHILD_NEIGHBOURS other guides with the
// nearest roots, nearest first (ties: lower index), padded with 0xFFFFFFFF.
std::vector<std::uint32_t> guideNeighbours(const ExplicitData& d);

// Half the median distance from a guide's root to the nearest other root (0 for one guide):
// the interpolated children's default radius.
float autoChildRadius(const ExplicitData& d, const std::vector<std::uint32_t>& neighbours);

// The n points of child `child` (1 ..) of guide g by the rules above (d.points must still be
// there; neighbours: empty for follow children).
std::vector<glm::vec3> childPoints(const ExplicitData& d, const gpu::ClhChildrenGpu& kids,
                                   const std::vector<std::uint32_t>& neighbours, std::uint32_t g,
                                   std::uint32_t child);

// The interpolation weights of a child rooted at `root` among candidate guides (their roots;
// the first is the child's own guide): up to three (index into candidates, weight) pairs,
// weights summing to 1. Exposed for tests of the rule.
struct ChildBlend {
  int count = 0;
  std::uint32_t index[3] = {0, 0, 0};
  float weight[3] = {0.0f, 0.0f, 0.0f};
};
ChildBlend childBlend(const glm::vec3& root, const std::vector<glm::vec3>& candidates);

}  // namespace clhair
