// blue_noise.cpp — weighted sample elimination (Yuksel 2015) with progressive ordering.
#include "groom/blue_noise.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "clhair/gpu_types.h"

namespace clhair {

namespace {

// Deterministic uniform floats from the shared integer hash.
struct HashRng {
  std::uint32_t key;
  std::uint32_t counter = 0;
  float next() { return gpu::clh_u01(gpu::clh_hash2(key, counter++)); }
};

// Removes samples from `pts` until `target` remain; returns the removed indices in the
// order they were eliminated. Weights follow Yuksel 2015 (alpha = 8, beta = 0.65,
// gamma = 1.5) with r_max for `target` samples in a domain of area `area`.
std::vector<std::size_t> eliminate(const std::vector<glm::vec2>& pts, std::size_t target,
                                   float area) {
  const std::size_t n = pts.size();
  std::vector<std::size_t> removedOrder;
  if (n <= target) return removedOrder;
  const float rmax = std::sqrt(area / (2.0f * std::sqrt(3.0f) * static_cast<float>(target)));
  const float rmin = rmax * (1.0f - std::pow(static_cast<float>(target) / n, 1.5f)) * 0.65f;
  const float cell = 2.0f * rmax;
  const int grid = std::max(1, static_cast<int>(std::ceil(1.0f / cell)));
  std::vector<std::vector<std::size_t>> cells(static_cast<std::size_t>(grid) * grid);
  auto cellOf = [&](const glm::vec2& p) {
    int cx = std::min(grid - 1, std::max(0, static_cast<int>(p.x / cell)));
    int cy = std::min(grid - 1, std::max(0, static_cast<int>(p.y / cell)));
    return std::make_pair(cx, cy);
  };
  for (std::size_t i = 0; i < n; ++i) {
    auto [cx, cy] = cellOf(pts[i]);
    cells[static_cast<std::size_t>(cy) * grid + cx].push_back(i);
  }
  auto weight = [&](float d) {
    d = std::max(d, rmin);
    float x = 1.0f - d / (2.0f * rmax);
    return std::pow(std::max(x, 0.0f), 8.0f);
  };
  auto forNeighbours = [&](std::size_t i, auto&& f) {
    auto [cx, cy] = cellOf(pts[i]);
    for (int y = std::max(0, cy - 1); y <= std::min(grid - 1, cy + 1); ++y)
      for (int x = std::max(0, cx - 1); x <= std::min(grid - 1, cx + 1); ++x)
        for (std::size_t j : cells[static_cast<std::size_t>(y) * grid + x]) {
          if (j == i) continue;
          glm::vec2 d = pts[i] - pts[j];
          float dist = std::sqrt(d.x * d.x + d.y * d.y);
          if (dist < 2.0f * rmax) f(j, dist);
        }
  };
  std::vector<float> w(n, 0.0f);
  std::vector<char> alive(n, 1);
  for (std::size_t i = 0; i < n; ++i)
    forNeighbours(i, [&](std::size_t, float d) { w[i] += weight(d); });
  std::set<std::pair<float, std::size_t>> heap;
  for (std::size_t i = 0; i < n; ++i) heap.insert({w[i], i});
  while (heap.size() > target) {
    auto top = std::prev(heap.end());
    std::size_t i = top->second;
    heap.erase(top);
    alive[i] = 0;
    removedOrder.push_back(i);
    forNeighbours(i, [&](std::size_t j, float d) {
      if (!alive[j]) return;
      heap.erase({w[j], j});
      w[j] -= weight(d);
      heap.insert({w[j], j});
    });
  }
  return removedOrder;
}

}  // namespace

std::vector<glm::vec2> progressiveBlueNoise(std::uint32_t count, bool triangle,
                                            std::uint32_t seed) {
  HashRng rng{gpu::clh_hash2(seed, triangle ? 2u : 1u)};
  const float area = triangle ? 0.5f : 1.0f;
  std::vector<glm::vec2> candidates;
  candidates.reserve(static_cast<std::size_t>(count) * 5);
  while (candidates.size() < static_cast<std::size_t>(count) * 5) {
    glm::vec2 p(rng.next(), rng.next());
    if (triangle && p.x + p.y >= 1.0f) continue;
    candidates.push_back(p);
  }
  // Level 0: candidates -> count samples. Then halve repeatedly; the samples removed at a
  // level come after every sample that survives it.
  std::vector<glm::vec2> current;
  {
    auto removed = eliminate(candidates, count, area);
    std::vector<char> gone(candidates.size(), 0);
    for (std::size_t i : removed) gone[i] = 1;
    for (std::size_t i = 0; i < candidates.size(); ++i)
      if (!gone[i]) current.push_back(candidates[i]);
  }
  std::vector<glm::vec2> tail;  // built back to front
  while (current.size() > 1) {
    std::size_t target = current.size() / 2;
    auto removed = eliminate(current, target, area);
    std::vector<char> gone(current.size(), 0);
    for (auto it = removed.rbegin(); it != removed.rend(); ++it) tail.push_back(current[*it]);
    // the last eliminated is the best of the removed: reverse order puts it first
    for (std::size_t i : removed) gone[i] = 1;
    std::vector<glm::vec2> next;
    for (std::size_t i = 0; i < current.size(); ++i)
      if (!gone[i]) next.push_back(current[i]);
    // tail segments must be ordered level by level, finest last: prepend this level
    std::rotate(tail.begin(), tail.end() - static_cast<std::ptrdiff_t>(removed.size()), tail.end());
    current.swap(next);
  }
  std::vector<glm::vec2> out(current);
  out.insert(out.end(), tail.begin(), tail.end());
  return out;
}

RootSets makeRootSets(std::uint32_t count, std::uint32_t seed) {
  RootSets sets;
  sets.quad = progressiveBlueNoise(count, false, seed);
  std::vector<glm::vec2> tri = progressiveBlueNoise(count, true, seed);
  sets.triangle.reserve(tri.size());
  for (const glm::vec2& p : tri) {
    float t = p.y;
    float s = t < 1.0f ? p.x / (1.0f - t) : 0.0f;
    sets.triangle.emplace_back(std::min(std::max(s, 0.0f), 1.0f), t);
  }
  return sets;
}

}  // namespace clhair
