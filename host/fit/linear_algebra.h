// linear_algebra.h — the small dense solvers the fitter needs, in double precision.
//
// solveDense: Gaussian elimination with partial pivoting of an n x n system (row-major a,
// destroyed), false when singular. symmetricEigen3 / symmetricEigen2: eigenvalues in
// descending order with unit eigenvectors (Jacobi rotations), for principal axes.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace clhair::fit {

bool solveDense(double* a, const double* b, double* x, int n);

// cov: 3x3 row-major symmetric.
void symmetricEigen3(const double* cov, double evals[3], glm::dvec3 evecs[3]);

// [[xx, xy], [xy, yy]]
void symmetricEigen2(double xx, double xy, double yy, double evals[2], glm::dvec2 evecs[2]);

}  // namespace clhair::fit
