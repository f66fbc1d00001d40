// children.cpp — see children.h. The neighbour search buckets the roots in a uniform grid
// and walks rings of cells outward until no closer root can remain.
#include "groom/children.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace clhair {

namespace {

constexpr std::uint32_t kNone = 0xFFFFFFFFu;

glm::vec3 rootOf(const ExplicitData& d, std::uint32_t g) {
  return glm::vec3(d.points[d.strandOffsets[g]]);
}

// The basis across a guide's root direction.
void rootBasis(const ExplicitData& d, std::uint32_t g, glm::vec3& t0, glm::vec3& t1) {
  const std::uint32_t at = d.strandOffsets[g];
  glm::vec3 v = glm::vec3(d.points[at + 1]) - glm::vec3(d.points[at]);
  const float len = std::sqrt(glm::dot(v, v));
  v = len > 0.0f ? v / len : glm::vec3(0.0f, 1.0f, 0.0f);
  const glm::vec3 a = std::fabs(v.x) <= std::fabs(v.y) && std::fabs(v.x) <= std::fabs(v.z)
                          ? glm::vec3(1.0f, 0.0f, 0.0f)
                      : std::fabs(v.y) <= std::fabs(v.z) ? glm::vec3(0.0f, 1.0f, 0.0f)
                                                         : glm::vec3(0.0f, 0.0f, 1.0f);
  t0 = glm::normalize(glm::cross(v, a));
  t1 = glm::cross(v, t0);
}

// Guide g at parameter k / (n - 1) of a child of n points: linear between its own points.
glm::vec3 guideAt(const ExplicitData& d, std::uint32_t g, std::uint32_t k, std::uint32_t n) {
  const std::uint32_t first = d.strandOffsets[g], m = d.strandOffsets[g + 1] - first;
  const std::uint64_t num = std::uint64_t(k) * (m - 1);
  const auto i = static_cast<std::uint32_t>(num / (n - 1));
  const float f = static_cast<float>(num % (n - 1)) / static_cast<float>(n - 1);
  const glm::vec3 a(d.points[first + std::min(i, m - 1)]);
  if (f == 0.0f) return a;
  const glm::vec3 b(d.points[first + std::min(i + 1, m - 1)]);
  return a + (b - a) * f;
}

}  // namespace

std::vector<std::uint32_t> guideNeighbours(const ExplicitData& d) {
  const std::size_t G = d.totalStrands;
  constexpr std::uint32_t K = CLH_CHILD_NEIGHBOURS;
  std::vector<std::uint32_t> out(G * K, kNone);
  if (G < 2) return out;
  std::vector<glm::vec3> roots(G);
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (std::size_t g = 0; g < G; ++g) {
    roots[g] = rootOf(d, static_cast<std::uint32_t>(g));
    lo = glm::min(lo, roots[g]);
    hi = glm::max(hi, roots[g]);
  }
  const glm::vec3 ext = hi - lo;
  const float side = std::max(ext.x, std::max(ext.y, ext.z));
  // about as many cells along the largest side as the cube root of the guides
  const int cellsMax = std::max(1, static_cast<int>(std::cbrt(static_cast<double>(G))));
  const float cell = side > 0.0f ? side / static_cast<float>(cellsMax) : 1.0f;
  int dim[3];
  for (int a = 0; a < 3; ++a)
    dim[a] = std::min(cellsMax, std::max(1, static_cast<int>(ext[a] / cell) + 1));
  auto cellOf = [&](const glm::vec3& p, int a) {
    return std::min(dim[a] - 1, std::max(0, static_cast<int>((p[a] - lo[a]) / cell)));
  };
  const std::size_t cells = std::size_t(dim[0]) * dim[1] * dim[2];
  std::vector<std::uint32_t> start(cells + 1, 0), items(G);
  auto index = [&](int x, int y, int z) { return (std::size_t(z) * dim[1] + y) * dim[0] + x; };
  for (std::size_t g = 0; g < G; ++g)
    ++start[index(cellOf(roots[g], 0), cellOf(roots[g], 1), cellOf(roots[g], 2)) + 1];
  for (std::size_t c = 0; c < cells; ++c) start[c + 1] += start[c];
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t g = 0; g < G; ++g)
    items[fill[index(cellOf(roots[g], 0), cellOf(roots[g], 1), cellOf(roots[g], 2))]++] =
        static_cast<std::uint32_t>(g);

  const int ringMax = std::max(dim[0], std::max(dim[1], dim[2]));
  std::vector<std::pair<float, std::uint32_t>> best;
  for (std::size_t g = 0; g < G; ++g) {
    const glm::vec3 p = roots[g];
    const int c0 = cellOf(p, 0), c1 = cellOf(p, 1), c2 = cellOf(p, 2);
    best.clear();
    for (int r = 0; r <= ringMax; ++r) {
      for (int z = c2 - r; z <= c2 + r; ++z)
        for (int y = c1 - r; y <= c1 + r; ++y)
          for (int x = c0 - r; x <= c0 + r; ++x) {
            if (std::max(std::abs(x - c0), std::max(std::abs(y - c1), std::abs(z - c2))) != r)
              continue;
            if (x < 0 || y < 0 || z < 0 || x >= dim[0] || y >= dim[1] || z >= dim[2]) continue;
            const std::size_t c = index(x, y, z);
            for (std::uint32_t i = start[c]; i < start[c + 1]; ++i) {
              const std::uint32_t o = items[i];
              if (o == g) continue;
              const glm::vec3 dv = roots[o] - p;
              best.emplace_back(glm::dot(dv, dv), o);
            }
          }
      // every root outside the rings seen is at least r cells away
      if (best.size() >= K) {
        std::partial_sort(best.begin(), best.begin() + K, best.end());
        best.resize(K);
        const float reach = static_cast<float>(r) * cell;
        if (best.back().first <= reach * reach) break;
      }
    }
    std::sort(best.begin(), best.end());
    for (std::size_t i = 0; i < std::min<std::size_t>(K, best.size()); ++i)
      out[g * K + i] = best[i].second;
  }
  return out;
}

float autoChildRadius(const ExplicitData& d, const std::vector<std::uint32_t>& neighbours) {
  const std::size_t G = d.totalStrands;
  std::vector<float> nearest;
  for (std::size_t g = 0; g < G; ++g) {
    const std::uint32_t o = neighbours[g * CLH_CHILD_NEIGHBOURS];
    if (o == kNone) continue;
    nearest.push_back(glm::length(rootOf(d, o) - rootOf(d, static_cast<std::uint32_t>(g))));
  }
  if (nearest.empty()) return 0.0f;
  std::nth_element(nearest.begin(), nearest.begin() + nearest.size() / 2, nearest.end());
  return 0.5f * nearest[nearest.size() / 2];
}

ChildBlend childBlend(const glm::vec3& root, const std::vector<glm::vec3>& candidates) {
  // the four nearest, in candidate order on ties
  float dist[4] = {0, 0, 0, 0};
  std::uint32_t idx[4] = {0, 0, 0, 0};
  int have = 0;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const glm::vec3 dv = candidates[i] - root;
    const float d2 = glm::dot(dv, dv);
    int at = have;
    while (at > 0 && d2 < dist[at - 1]) --at;
    if (at >= 4) continue;
    for (int j = std::min(have, 3); j > at; --j) {
      dist[j] = dist[j - 1];
      idx[j] = idx[j - 1];
    }
    dist[at] = d2;
    idx[at] = static_cast<std::uint32_t>(i);
    have = std::min(have + 1, 4);
  }
  ChildBlend b;
  if (have == 0) return b;
  if (dist[0] < 1e-30f) {
    b.count = 1;
    b.index[0] = idx[0];
    b.weight[0] = 1.0f;
    return b;
  }
  const float far = have == 4 ? 1.0f / dist[3] : 0.0f;
  float sum = 0.0f;
  b.count = std::min(have, 3);
  for (int i = 0; i < b.count; ++i) {
    b.index[i] = idx[i];
    b.weight[i] = std::max(1.0f / dist[i] - far, 0.0f);
    sum += b.weight[i];
  }
  if (!(sum > 0.0f)) {  // three roots as far as the fourth: equal weights
    for (int i = 0; i < b.count; ++i) b.weight[i] = 1.0f / static_cast<float>(b.count);
    return b;
  }
  for (int i = 0; i < b.count; ++i) b.weight[i] /= sum;
  return b;
}

std::vector<glm::vec3> childPoints(const ExplicitData& d, const gpu::ClhChildrenGpu& kids,
                                   const std::vector<std::uint32_t>& neighbours, std::uint32_t g,
                                   std::uint32_t child) {
  const std::uint32_t first = d.strandOffsets[g], n = d.strandOffsets[g + 1] - first;
  glm::vec3 t0, t1;
  rootBasis(d, g, t0, t1);
  const std::uint32_t h = gpu::clh_hash3(kids.seed, g, child);
  const float a = (2.0f * gpu::clh_u01(h) - 1.0f) * kids.radius;
  const float b = (2.0f * gpu::clh_u01(gpu::clh_hash(h)) - 1.0f) * kids.radius;
  const glm::vec3 o = t0 * a + t1 * b;
  auto growth = [&](std::uint32_t k) {
    const float t = static_cast<float>(k) / static_cast<float>(n - 1);
    const float kappa = kids.clump >= 0.0f ? kids.clump * t : -kids.clump * (1.0f - t);
    return (1.0f + kids.tip_spread * static_cast<float>(k) / static_cast<float>(n)) *
           (1.0f - kappa);
  };
  std::vector<glm::vec3> out(n);
  if (kids.mode == CLH_CHILD_FOLLOW) {
    for (std::uint32_t k = 0; k < n; ++k) out[k] = glm::vec3(d.points[first + k]) + o * growth(k);
    return out;
  }
  const glm::vec3 root = glm::vec3(d.points[first]) + o;
  std::vector<std::uint32_t> cand = {g};
  for (std::uint32_t i = 0; i < kids.neighbours; ++i) {
    const std::uint32_t nb = neighbours[std::size_t(g) * kids.neighbours + i];
    if (nb != kNone) cand.push_back(nb);
  }
  std::vector<glm::vec3> roots;
  for (std::uint32_t c : cand) roots.push_back(rootOf(d, c));
  const ChildBlend blend = childBlend(root, roots);
  auto base = [&](std::uint32_t k) {
    glm::vec3 p(0.0f);
    for (int i = 0; i < blend.count; ++i)
      p += guideAt(d, cand[blend.index[i]], k, n) * blend.weight[i];
    return p;
  };
  const glm::vec3 lift = root - base(0);
  for (std::uint32_t k = 0; k < n; ++k) out[k] = base(k) + lift * growth(k);
  return out;
}

}  // namespace clhair
