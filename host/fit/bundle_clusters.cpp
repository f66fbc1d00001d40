// bundle_clusters.cpp — see bundle_clusters.h.
#include "fit/bundle_clusters.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "fit/parallel.h"

namespace clhair::fit {

namespace {

constexpr int kIterations = 6;

// The two cell coordinates' bit patterns side by side (unsigned: a negative x shifted left is
// undefined before C++20).
std::int64_t cellKey(int x, int y) {
  const std::uint64_t key = static_cast<std::uint64_t>(static_cast<std::uint32_t>(x)) << 32 |
                            static_cast<std::uint32_t>(y);
  return static_cast<std::int64_t>(key);
}

// A lattice coordinate, clamped to what an int holds (a spacing far below the roots' spread
// would otherwise convert a value beyond the int range).
int cellCoordinate(float offset, float h) {
  const double c = std::floor(static_cast<double>(offset) / static_cast<double>(h));
  constexpr double kMost = 1 << 30;
  return static_cast<int>(std::clamp(c, -kMost, kMost));
}

glm::ivec2 cellOf(const glm::vec2& p, const glm::vec2& lo, float h) {
  return glm::ivec2(cellCoordinate(p.x - lo.x, h), cellCoordinate(p.y - lo.y, h));
}

std::size_t occupiedCells(const std::vector<glm::vec2>& pts, const glm::vec2& lo, float h) {
  std::vector<std::int64_t> keys(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const glm::ivec2 c = cellOf(pts[i], lo, h);
    keys[i] = cellKey(c.x, c.y);
  }
  std::sort(keys.begin(), keys.end());
  return static_cast<std::size_t>(std::unique(keys.begin(), keys.end()) - keys.begin());
}

}  // namespace

std::vector<float> shapeFeatures(const FitStrands& s, int threads) {
  std::vector<float> f(s.count() * kShapeDims);
  parallelFor(s.count(), threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      for (int k = 0; k < 4; ++k) {
        // scaled to the median length: strands of one shape but different lengths (length
        // variation) stay together
        const float scale =
            s.length[i] > 0.0f ? static_cast<float>(s.medianLength) / s.length[i] : 0.0f;
        const glm::vec3 d =
            (s.atFraction(i, 0.25f * static_cast<float>(k + 1)) - s.root(i)) * scale;
        f[i * kShapeDims + 3 * k] = d.x;
        f[i * kShapeDims + 3 * k + 1] = d.y;
        f[i * kShapeDims + 3 * k + 2] = d.z;
      }
  });
  return f;
}

Clusters clusterStrands(const std::vector<glm::vec2>& roots, const std::vector<float>& shape,
                        int target, float shapeWeight, float shapeScale, int threads) {
  const std::size_t n = roots.size();
  Clusters c;
  c.label.assign(n, 0);
  glm::vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const glm::vec2& p : roots) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::vec2 ext = hi - lo;
  const float diag = glm::length(ext);
  auto single = [&]() {
    c.count = 1;
    c.spacing = 0.0f;
    std::fill(c.label.begin(), c.label.end(), 0);
    return c;
  };
  if (target <= 1 || n < 2 || !(diag > 0.0f)) return single();

  // lattice spacing: about `target` occupied cells
  float h = std::sqrt(std::max(ext.x, diag * 1e-3f) * std::max(ext.y, diag * 1e-3f) /
                      static_cast<float>(target));
  float bestH = h;
  double bestErr = 1e300;
  for (int it = 0; it < 12; ++it) {
    const std::size_t occ = occupiedCells(roots, lo, h);
    const double err = std::fabs(std::log(static_cast<double>(occ) / target));
    if (err < bestErr) {
      bestErr = err;
      bestH = h;
    }
    if (err < 0.02) break;
    h *= static_cast<float>(std::sqrt(static_cast<double>(occ) / target));
  }
  h = bestH;
  c.spacing = h;
  // lo snapped so that the lattice is centred on the roots' box
  const glm::vec2 cells = glm::ceil(ext / h + 1e-3f);
  lo -= 0.5f * (cells * h - ext);

  // initial centres: the occupied lattice cells. A centre's root part stays at its cell's
  // centre (its anchor), so the clusters keep tiling the scalp like the cells; only the
  // shape part moves, and with it strands whose shape belongs to a neighbour.
  std::unordered_map<std::int64_t, int> cellCluster;
  std::vector<glm::vec2> anchor;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::ivec2 g = cellOf(roots[i], lo, h);
    auto it = cellCluster.find(cellKey(g.x, g.y));
    int k;
    if (it == cellCluster.end()) {
      k = static_cast<int>(cellCluster.size());
      cellCluster.emplace(cellKey(g.x, g.y), k);
      anchor.push_back(lo + (glm::vec2(g) + 0.5f) * h);
    } else {
      k = it->second;
    }
    c.label[i] = k;
  }
  const float wShape = shapeScale > 0.0f ? shapeWeight / shapeScale : 0.0f;
  const float invH = 1.0f / h;
  std::vector<double> sumX, sumS;
  std::vector<int> count;
  auto updateCentres = [&](int k) {
    sumX.assign(2 * k, 0.0);
    sumS.assign(static_cast<std::size_t>(kShapeDims) * k, 0.0);
    count.assign(k, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const int l = c.label[i];
      ++count[l];
      sumX[2 * l] += roots[i].x;
      sumX[2 * l + 1] += roots[i].y;
      for (int d = 0; d < kShapeDims; ++d) sumS[l * kShapeDims + d] += shape[i * kShapeDims + d];
    }
    c.centre.clear();
    c.shape.clear();
    std::vector<int> remap(k, -1);
    std::vector<glm::vec2> kept;
    for (int l = 0; l < k; ++l) {
      if (count[l] == 0) continue;
      remap[l] = static_cast<int>(c.centre.size());
      kept.push_back(anchor[l]);
      c.centre.push_back(glm::vec2(sumX[2 * l] / count[l], sumX[2 * l + 1] / count[l]));
      for (int d = 0; d < kShapeDims; ++d)
        c.shape.push_back(static_cast<float>(sumS[l * kShapeDims + d] / count[l]));
    }
    for (int& l : c.label) l = remap[l];
    anchor = kept;
    c.count = static_cast<int>(c.centre.size());
  };
  updateCentres(static_cast<int>(cellCluster.size()));

  auto distance2 = [&](std::size_t i, int k) {
    const glm::vec2 d = (roots[i] - anchor[k]) * invH;
    float s = 0.0f;
    for (int j = 0; j < kShapeDims; ++j) {
      const float e = shape[i * kShapeDims + j] - c.shape[k * kShapeDims + j];
      s += e * e;
    }
    return glm::dot(d, d) + wShape * wShape * s;
  };
  // k-means: each strand looks at the centres within two lattice cells of its own
  for (int iter = 0; iter < kIterations; ++iter) {
    std::unordered_map<std::int64_t, std::vector<int>> grid;
    for (int k = 0; k < c.count; ++k) {
      const glm::ivec2 g = cellOf(anchor[k], lo, h);
      grid[cellKey(g.x, g.y)].push_back(k);
    }
    parallelFor(n, threads, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        const glm::ivec2 g = cellOf(roots[i], lo, h);
        float best = distance2(i, c.label[i]);
        int bestK = c.label[i];
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx) {
            auto it = grid.find(cellKey(g.x + dx, g.y + dy));
            if (it == grid.end()) continue;
            for (int k : it->second) {
              const float d = distance2(i, k);
              if (d < best) {
                best = d;
                bestK = k;
              }
            }
          }
        c.label[i] = bestK;
      }
    });
    updateCentres(c.count);
  }
  // merge clusters too small to fit a quad into their nearest neighbour (by centre)
  const int minCount = std::max(2, static_cast<int>(0.25 * static_cast<double>(n) / c.count));
  for (int pass = 0; pass < 3; ++pass) {
    std::vector<int> sizes(c.count, 0);
    for (int l : c.label) ++sizes[l];
    bool merged = false;
    std::vector<int> into(c.count);
    for (int k = 0; k < c.count; ++k) into[k] = k;
    for (int k = 0; k < c.count; ++k) {
      if (sizes[k] >= minCount || c.count == 1) continue;
      float best = std::numeric_limits<float>::max();
      int bestK = -1;
      for (int j = 0; j < c.count; ++j) {
        if (j == k || into[j] != j || sizes[j] < minCount) continue;
        const glm::vec2 d = (anchor[j] - anchor[k]) * invH;
        float ds = 0.0f;
        for (int q = 0; q < kShapeDims; ++q) {
          const float e = c.shape[j * kShapeDims + q] - c.shape[k * kShapeDims + q];
          ds += e * e;
        }
        const float dist = glm::dot(d, d) + wShape * wShape * ds;
        if (dist < best) {
          best = dist;
          bestK = j;
        }
      }
      if (bestK < 0) continue;
      into[k] = bestK;
      merged = true;
    }
    if (!merged) break;
    for (int& l : c.label) l = into[l];
    updateCentres(c.count);
  }
  c.members.assign(c.count, 0);
  for (int l : c.label) ++c.members[l];
  return c;
}

}  // namespace clhair::fit
