// head_surface.cpp — see head_surface.h.
#include "fit/head_surface.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "clhair/error.h"

namespace clhair::fit {

namespace {

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
glm::vec3 closestOnTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b,
                            const glm::vec3& c) {
  const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0f && d2 <= 0.0f) return a;
  const glm::vec3 bp = p - b;
  const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0f && d4 <= d3) return b;
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return a + ab * (d1 / (d1 - d3));
  const glm::vec3 cp = p - c;
  const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0f && d5 <= d6) return c;
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return a + ac * (d2 / (d2 - d6));
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f)
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const float denom = 1.0f / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace

HeadSurface::HeadSurface(const TriangleMesh& mesh) {
  const std::size_t n = mesh.indices.size() / 3;
  if (n == 0) throw Error("head mesh \"" + mesh.name + "\" has no triangles");
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const glm::vec3& p : mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
    centroid_ += p / static_cast<float>(mesh.positions.size());
  }
  a_.resize(n);
  b_.resize(n);
  c_.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    a_[t] = mesh.positions[mesh.indices[3 * t]];
    b_[t] = mesh.positions[mesh.indices[3 * t + 1]];
    c_[t] = mesh.positions[mesh.indices[3 * t + 2]];
  }
  const glm::vec3 ext = glm::max(hi - lo, glm::vec3(1e-6f));
  // about two triangles per occupied cell on a closed surface: cells ~ n^(2/3) per axis^2
  const float volume = ext.x * ext.y * ext.z;
  cell_ = std::max(std::cbrt(volume / static_cast<float>(std::max<std::size_t>(n, 1))) * 1.5f,
                   1e-6f * glm::length(ext));
  nx_ = std::clamp(static_cast<int>(ext.x / cell_) + 1, 1, 256);
  ny_ = std::clamp(static_cast<int>(ext.y / cell_) + 1, 1, 256);
  nz_ = std::clamp(static_cast<int>(ext.z / cell_) + 1, 1, 256);
  cell_ = std::max({ext.x / nx_, ext.y / ny_, ext.z / nz_}) * 1.0001f;
  lo_ = lo;
  std::vector<std::uint32_t> count(static_cast<std::size_t>(nx_) * ny_ * nz_ + 1, 0);
  auto range = [&](std::size_t t, glm::ivec3& c0, glm::ivec3& c1) {
    const glm::vec3 tlo = glm::min(a_[t], glm::min(b_[t], c_[t])) - lo_;
    const glm::vec3 thi = glm::max(a_[t], glm::max(b_[t], c_[t])) - lo_;
    c0 = glm::clamp(glm::ivec3(tlo / cell_), glm::ivec3(0), glm::ivec3(nx_ - 1, ny_ - 1, nz_ - 1));
    c1 = glm::clamp(glm::ivec3(thi / cell_), glm::ivec3(0), glm::ivec3(nx_ - 1, ny_ - 1, nz_ - 1));
  };
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t t = 0; t < n; ++t) {
      glm::ivec3 c0, c1;
      range(t, c0, c1);
      for (int z = c0.z; z <= c1.z; ++z)
        for (int y = c0.y; y <= c1.y; ++y)
          for (int x = c0.x; x <= c1.x; ++x) {
            const int ci = cellIndex(x, y, z);
            if (pass == 0)
              ++count[ci + 1];
            else
              items_[start_[ci] + count[ci]++] = static_cast<std::uint32_t>(t);
          }
    }
    if (pass == 0) {
      start_.assign(count.size(), 0);
      for (std::size_t i = 1; i < count.size(); ++i) start_[i] = start_[i - 1] + count[i];
      items_.resize(start_.back());
      std::fill(count.begin(), count.end(), 0);
    }
  }
}

glm::vec3 HeadSurface::closest(const glm::vec3& p, glm::vec3* normal) const {
  const glm::ivec3 home = glm::clamp(glm::ivec3(glm::floor((p - lo_) / cell_)), glm::ivec3(0),
                                     glm::ivec3(nx_ - 1, ny_ - 1, nz_ - 1));
  // distance from p to the grid's box: shells nearer than that hold nothing
  const glm::vec3 boxHi = lo_ + glm::vec3(nx_, ny_, nz_) * cell_;
  const float outside = glm::length(glm::max(glm::max(lo_ - p, p - boxHi), glm::vec3(0.0f)));
  float best = 1e30f;
  glm::vec3 bestPoint = p;
  std::size_t bestTri = 0;
  const int maxShell = std::max({nx_, ny_, nz_});
  for (int r = 0; r <= maxShell; ++r) {
    if (best < 1e29f && std::max(static_cast<float>(r - 1) * cell_, outside) > std::sqrt(best))
      break;
    for (int z = home.z - r; z <= home.z + r; ++z)
      for (int y = home.y - r; y <= home.y + r; ++y)
        for (int x = home.x - r; x <= home.x + r; ++x) {
          if (std::max({std::abs(x - home.x), std::abs(y - home.y), std::abs(z - home.z)}) != r)
            continue;
          if (x < 0 || y < 0 || z < 0 || x >= nx_ || y >= ny_ || z >= nz_) continue;
          const int ci = cellIndex(x, y, z);
          for (std::uint32_t k = start_[ci]; k < start_[ci + 1]; ++k) {
            const std::uint32_t t = items_[k];
            const glm::vec3 q = closestOnTriangle(p, a_[t], b_[t], c_[t]);
            const float d = glm::dot(q - p, q - p);
            if (d < best) {
              best = d;
              bestPoint = q;
              bestTri = t;
            }
          }
        }
  }
  if (normal) {
    glm::vec3 nrm = glm::cross(b_[bestTri] - a_[bestTri], c_[bestTri] - a_[bestTri]);
    const float l = glm::length(nrm);
    nrm = l > 0.0f ? nrm / l : glm::vec3(0.0f, 1.0f, 0.0f);
    if (glm::dot(nrm, bestPoint - centroid_) < 0.0f) nrm = -nrm;
    *normal = nrm;
  }
  return bestPoint;
}

}  // namespace clhair::fit
