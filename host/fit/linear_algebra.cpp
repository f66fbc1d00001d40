// linear_algebra.cpp — see linear_algebra.h.
#include "fit/linear_algebra.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace clhair::fit {

bool solveDense(double* a, const double* b, double* x, int n) {
  std::vector<double> rhs(b, b + n);
  double scale = 0.0;
  for (int i = 0; i < n * n; ++i) scale = std::max(scale, std::fabs(a[i]));
  if (!(scale > 0.0) || !std::isfinite(scale)) return false;
  for (int col = 0; col < n; ++col) {
    int piv = col;
    for (int r = col + 1; r < n; ++r)
      if (std::fabs(a[r * n + col]) > std::fabs(a[piv * n + col])) piv = r;
    if (std::fabs(a[piv * n + col]) < 1e-13 * scale) return false;
    if (piv != col) {
      for (int k = 0; k < n; ++k) std::swap(a[piv * n + k], a[col * n + k]);
      std::swap(rhs[piv], rhs[col]);
    }
    for (int r = col + 1; r < n; ++r) {
      const double f = a[r * n + col] / a[col * n + col];
      if (f == 0.0) continue;
      for (int k = col; k < n; ++k) a[r * n + k] -= f * a[col * n + k];
      rhs[r] -= f * rhs[col];
    }
  }
  for (int r = n - 1; r >= 0; --r) {
    double s = rhs[r];
    for (int k = r + 1; k < n; ++k) s -= a[r * n + k] * x[k];
    x[r] = s / a[r * n + r];
    if (!std::isfinite(x[r])) return false;
  }
  return true;
}

void symmetricEigen3(const double* cov, double evals[3], glm::dvec3 evecs[3]) {
  double a[3][3], v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a[i][j] = cov[3 * i + j];
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    if (off < 1e-30) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (std::fabs(a[p][q]) < 1e-300) continue;
        const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double t =
            (theta >= 0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1.0 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < 3; ++k) {  // a = J^T a J
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
  }
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3, [&](int x, int y) { return a[x][x] > a[y][y]; });
  for (int i = 0; i < 3; ++i) {
    evals[i] = a[order[i]][order[i]];
    evecs[i] = glm::dvec3(v[0][order[i]], v[1][order[i]], v[2][order[i]]);
  }
}

void symmetricEigen2(double xx, double xy, double yy, double evals[2], glm::dvec2 evecs[2]) {
  const double tr = 0.5 * (xx + yy), det = xx * yy - xy * xy;
  const double disc = std::sqrt(std::max(tr * tr - det, 0.0));
  evals[0] = tr + disc;
  evals[1] = tr - disc;
  glm::dvec2 e0;
  if (std::fabs(xy) > 1e-300)
    e0 = glm::dvec2(evals[0] - yy, xy);
  else
    e0 = xx >= yy ? glm::dvec2(1, 0) : glm::dvec2(0, 1);
  const double l = std::sqrt(e0.x * e0.x + e0.y * e0.y);
  e0 = l > 0 ? e0 / l : glm::dvec2(1, 0);
  evecs[0] = e0;
  evecs[1] = glm::dvec2(-e0.y, e0.x);
}

}  // namespace clhair::fit
