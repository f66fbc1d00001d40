// cage_solve.h — the least-squares problem of one layer of the fitted cage.
//
// Unknowns: the layer's vertex positions x_v. Each face f contributes the normal-equation
// block of its strands, B_f = sum of beta beta^T over its strands (beta: the 4 bilinear
// weights of a strand's (s, t)) and r_f = sum of beta p (p: the strand's point on the
// layer). A prior position q_v with weight lambda_v keeps vertices with few strands in
// place. The sparse symmetric positive-definite system (sum_f B_f + diag lambda) x =
// sum_f r_f + lambda q is solved by Jacobi-preconditioned conjugate gradients from x = q.
#pragma once

#include <array>
#include <vector>

#include <glm/vec3.hpp>

namespace clhair::fit {

struct FaceBlock {
  double b[4][4] = {};
  glm::dvec3 r[4] = {};
  double strands = 0.0;  // strands that contributed
};

// priorWeight: lambda_v = priorWeight * (diagonal of the data at v) + floorWeight * (mean of
// that diagonal over vertices with data).
std::vector<glm::vec3> solveCageLayer(const std::vector<std::array<int, 4>>& faces,
                                      const std::vector<FaceBlock>& blocks,
                                      const std::vector<glm::vec3>& prior, double priorWeight,
                                      double floorWeight);

}  // namespace clhair::fit
