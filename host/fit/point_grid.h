// point_grid.h — the k nearest points of a fixed point set, from a uniform grid whose cell
// size is chosen for about 8 points per occupied cell (so volumes, surfaces and curves of
// points all work). Used for nearest generated strands and for root neighbours.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace clhair::fit {

class PointGrid {
 public:
  explicit PointGrid(std::vector<glm::vec3> pts) : pts_(std::move(pts)) {
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const glm::vec3& p : pts_) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    lo_ = lo;
    const float ext = std::max(glm::length(hi - lo), 1e-9f);
    // about 8 points per occupied cell, whether the points fill a volume, a surface or a
    // curve: the spacing is adjusted from the occupied count (surface-like: square root)
    const std::size_t n = std::max<std::size_t>(pts_.size(), 1);
    cell_ = ext / std::max(1.0f, std::cbrt(static_cast<float>(n) / 8.0f));
    for (int it = 0; it < 6; ++it) {
      cells_.clear();
      for (std::size_t i = 0; i < pts_.size(); ++i)
        cells_[key(cellOf(pts_[i]))].push_back(static_cast<std::uint32_t>(i));
      const double perCell =
          static_cast<double>(n) / static_cast<double>(std::max<std::size_t>(cells_.size(), 1));
      if (perCell > 4.0 && perCell < 16.0) break;
      cell_ = std::max(cell_ * static_cast<float>(std::sqrt(8.0 / perCell)), ext * 1e-6f);
      if (it == 5) {  // the last adjustment: rebuild with it
        cells_.clear();
        for (std::size_t i = 0; i < pts_.size(); ++i)
          cells_[key(cellOf(pts_[i]))].push_back(static_cast<std::uint32_t>(i));
      }
    }
  }
  // Up to k nearest indices to p.
  void nearest(const glm::vec3& p, int k, std::vector<std::pair<float, std::uint32_t>>& out) const {
    out.clear();
    const glm::ivec3 c = cellOf(p);
    for (int r = 0; r < 64; ++r) {
      if (static_cast<int>(out.size()) >= k &&
          static_cast<float>(r - 1) * cell_ > std::sqrt(out[k - 1].first))
        break;
      for (int z = -r; z <= r; ++z)
        for (int y = -r; y <= r; ++y)
          for (int x = -r; x <= r; ++x) {
            if (std::max({std::abs(x), std::abs(y), std::abs(z)}) != r) continue;
            auto it = cells_.find(key(c + glm::ivec3(x, y, z)));
            if (it == cells_.end()) continue;
            for (std::uint32_t i : it->second) {
              const glm::vec3 d = pts_[i] - p;
              out.push_back({glm::dot(d, d), i});
            }
          }
      std::sort(out.begin(), out.end());
      if (static_cast<int>(out.size()) > k) out.resize(k);
    }
    if (static_cast<int>(out.size()) < k && out.size() < pts_.size()) {  // far away: every point
      out.clear();
      for (std::size_t i = 0; i < pts_.size(); ++i) {
        const glm::vec3 d = pts_[i] - p;
        out.push_back({glm::dot(d, d), static_cast<std::uint32_t>(i)});
      }
      std::sort(out.begin(), out.end());
      if (static_cast<int>(out.size()) > k) out.resize(k);
    }
  }

 private:
  glm::ivec3 cellOf(const glm::vec3& p) const { return glm::ivec3(glm::floor((p - lo_) / cell_)); }
  static std::int64_t key(const glm::ivec3& c) {
    return (static_cast<std::int64_t>(c.x & 0x1FFFFF) << 42) |
           (static_cast<std::int64_t>(c.y & 0x1FFFFF) << 21) | (c.z & 0x1FFFFF);
  }
  std::vector<glm::vec3> pts_;
  glm::vec3 lo_{0.0f};
  float cell_ = 1.0f;
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> cells_;
};

}  // namespace clhair::fit
