// cage_solve.cpp — see cage_solve.h.
#include "fit/cage_solve.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/geometric.hpp>

namespace clhair::fit {

namespace {

// Row-compressed sparse symmetric matrix built from face blocks.
struct SparseRows {
  std::vector<std::vector<std::pair<int, double>>> rows;
  void add(int i, int j, double v) {
    for (auto& e : rows[i])
      if (e.first == j) {
        e.second += v;
        return;
      }
    rows[i].push_back({j, v});
  }
  void multiply(const std::vector<glm::dvec3>& x, std::vector<glm::dvec3>& y) const {
    for (std::size_t i = 0; i < rows.size(); ++i) {
      glm::dvec3 s(0.0);
      for (const auto& e : rows[i]) s += e.second * x[e.first];
      y[i] = s;
    }
  }
};

}  // namespace

std::vector<glm::vec3> solveCageLayer(const std::vector<std::array<int, 4>>& faces,
                                      const std::vector<FaceBlock>& blocks,
                                      const std::vector<glm::vec3>& prior, double priorWeight,
                                      double floorWeight) {
  const std::size_t V = prior.size();
  SparseRows a;
  a.rows.resize(V);
  std::vector<glm::dvec3> rhs(V, glm::dvec3(0.0));
  std::vector<double> dataDiag(V, 0.0);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const FaceBlock& fb = blocks[f];
    if (fb.strands <= 0.0) continue;
    for (int i = 0; i < 4; ++i) {
      const int vi = faces[f][i];
      rhs[vi] += fb.r[i];
      dataDiag[vi] += fb.b[i][i];
      for (int j = 0; j < 4; ++j) a.add(vi, faces[f][j], fb.b[i][j]);
    }
  }
  double meanDiag = 0.0;
  int withData = 0;
  for (double d : dataDiag)
    if (d > 0.0) {
      meanDiag += d;
      ++withData;
    }
  meanDiag = withData > 0 ? meanDiag / withData : 1.0;
  std::vector<glm::dvec3> x(V), r(V), z(V), p(V), ap(V);
  std::vector<double> diag(V);
  for (std::size_t v = 0; v < V; ++v) {
    const double lambda = priorWeight * dataDiag[v] + floorWeight * meanDiag;
    a.add(static_cast<int>(v), static_cast<int>(v), lambda);
    rhs[v] += lambda * glm::dvec3(prior[v]);
    x[v] = glm::dvec3(prior[v]);
  }
  for (std::size_t v = 0; v < V; ++v) {
    diag[v] = 1.0;
    for (const auto& e : a.rows[v])
      if (e.first == static_cast<int>(v)) diag[v] = e.second > 0.0 ? e.second : 1.0;
  }
  a.multiply(x, ap);
  glm::dvec3 rz(0.0), bnorm(0.0);
  for (std::size_t v = 0; v < V; ++v) {
    r[v] = rhs[v] - ap[v];
    z[v] = r[v] / diag[v];
    p[v] = z[v];
    rz += r[v] * z[v];
    bnorm += rhs[v] * rhs[v] / diag[v];
  }
  const int maxIter = static_cast<int>(std::min<std::size_t>(4 * V + 50, 2000));
  for (int it = 0; it < maxIter; ++it) {
    bool done = true;
    for (int c = 0; c < 3; ++c) done = done && rz[c] <= 1e-20 * std::max(bnorm[c], 1e-300);
    if (done) break;
    a.multiply(p, ap);
    glm::dvec3 pap(0.0);
    for (std::size_t v = 0; v < V; ++v) pap += p[v] * ap[v];
    glm::dvec3 alpha;
    for (int c = 0; c < 3; ++c) alpha[c] = pap[c] > 0.0 ? rz[c] / pap[c] : 0.0;
    glm::dvec3 rzNew(0.0);
    for (std::size_t v = 0; v < V; ++v) {
      x[v] += alpha * p[v];
      r[v] -= alpha * ap[v];
      z[v] = r[v] / diag[v];
      rzNew += r[v] * z[v];
    }
    glm::dvec3 beta;
    for (int c = 0; c < 3; ++c) beta[c] = rz[c] > 0.0 ? rzNew[c] / rz[c] : 0.0;
    for (std::size_t v = 0; v < V; ++v) p[v] = z[v] + beta * p[v];
    rz = rzNew;
  }
  std::vector<glm::vec3> out(V);
  for (std::size_t v = 0; v < V; ++v) {
    const bool finite = std::isfinite(x[v].x) && std::isfinite(x[v].y) && std::isfinite(x[v].z);
    out[v] = finite ? glm::vec3(x[v]) : prior[v];
  }
  return out;
}

}  // namespace clhair::fit
