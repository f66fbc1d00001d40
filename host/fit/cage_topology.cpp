// cage_topology.cpp — see cage_topology.h.
#include "fit/cage_topology.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "fit/linear_algebra.h"

namespace clhair::fit {

namespace {

float cross2(const glm::vec2& a, const glm::vec2& b) { return a.x * b.y - a.y * b.x; }

float quadArea(const std::array<glm::vec2, 4>& q) {
  return 0.5f * (cross2(q[2] - q[0], q[3] - q[1]));
}

// Convex, counter-clockwise and not much smaller than `refArea`.
bool quadValid(const std::array<glm::vec2, 4>& q, float refArea) {
  for (int k = 0; k < 4; ++k)
    if (!(cross2(q[(k + 1) % 4] - q[k], q[(k + 2) % 4] - q[(k + 1) % 4]) > 0.0f)) return false;
  return quadArea(q) > 0.25f * refArea;
}

}  // namespace

glm::vec2 inverseBilinear(const std::array<glm::vec2, 4>& q, const glm::vec2& p) {
  glm::vec2 st(0.5f);
  for (int it = 0; it < 12; ++it) {
    const float s = st.x, t = st.y;
    const glm::vec2 f =
        (1 - s) * (1 - t) * q[0] + s * (1 - t) * q[1] + s * t * q[2] + (1 - s) * t * q[3] - p;
    const glm::vec2 ds = (1 - t) * (q[1] - q[0]) + t * (q[2] - q[3]);
    const glm::vec2 dt = (1 - s) * (q[3] - q[0]) + s * (q[2] - q[1]);
    const float det = cross2(ds, dt);
    if (std::fabs(det) < 1e-20f) break;
    const glm::vec2 step((f.x * dt.y - f.y * dt.x) / det, (ds.x * f.y - ds.y * f.x) / det);
    st -= step;
    st = glm::clamp(st, glm::vec2(-2.0f), glm::vec2(3.0f));
    if (glm::dot(step, step) < 1e-14f) break;
  }
  return st;
}

CageTopology buildCageTopology(const Clusters& cl, const std::vector<glm::vec2>& roots,
                               float minExtent, float shapeWeight, float shapeScale,
                               float weldShapeLimit) {
  const int F = cl.count;
  CageTopology topo;
  topo.faces.resize(F);
  topo.ownCorners.resize(F);
  topo.axes.resize(F);
  // chart second moments per cluster
  std::vector<double> sxx(F, 0.0), sxy(F, 0.0), syy(F, 0.0);
  std::vector<int> cnt(F, 0);
  for (std::size_t i = 0; i < roots.size(); ++i) {
    const int f = cl.label[i];
    const glm::vec2 d = roots[i] - cl.centre[f];
    sxx[f] += d.x * d.x;
    sxy[f] += d.x * d.y;
    syy[f] += d.y * d.y;
    ++cnt[f];
  }
  for (int f = 0; f < F; ++f) {
    const double n = std::max(cnt[f], 1);
    double ev[2];
    glm::dvec2 evec[2];
    symmetricEigen2(sxx[f] / n, sxy[f] / n, syy[f] / n, ev, evec);
    glm::vec2 e0(1, 0), e1(0, 1);
    const double aniso = std::sqrt(std::max(ev[0], 0.0) / std::max(ev[1], 1e-30));
    glm::vec2 major(evec[0]);
    // principal axes only for clusters clearly elongated across the chart axes
    const float c = std::fabs(major.x), s = std::fabs(major.y);
    if (aniso > 1.5 && std::min(c, s) > 0.26f) {  // more than 15 degrees off both axes
      if (std::fabs(major.x) >= std::fabs(major.y)) {
        e0 = major.x >= 0 ? major : -major;
      } else {  // the major axis is nearer y: keep e0 near +x
        const glm::vec2 m = major.y >= 0 ? major : -major;
        e0 = glm::vec2(m.y, -m.x);
      }
      e1 = glm::vec2(-e0.y, e0.x);
    }
    const double v0 = (sxx[f] * e0.x * e0.x + 2 * sxy[f] * e0.x * e0.y + syy[f] * e0.y * e0.y) / n;
    const double v1 = (sxx[f] * e1.x * e1.x + 2 * sxy[f] * e1.x * e1.y + syy[f] * e1.y * e1.y) / n;
    const float a = std::max(static_cast<float>(std::sqrt(3.0 * std::max(v0, 0.0))), minExtent);
    const float b = std::max(static_cast<float>(std::sqrt(3.0 * std::max(v1, 0.0))), minExtent);
    const glm::vec2 m = cl.centre[f];
    topo.axes[f] = {e0, e1};
    topo.ownCorners[f] = {m - a * e0 - b * e1, m + a * e0 - b * e1, m + a * e0 + b * e1,
                          m - a * e0 + b * e1};
  }

  // union-find over the 4F corners
  const int N = 4 * F;
  std::vector<int> parent(N);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<std::vector<int>> groupOf(N);
  for (int i = 0; i < N; ++i) groupOf[i] = {i};
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  auto cornerPos = [&](int id) { return topo.ownCorners[id / 4][id % 4]; };
  const float wShape = shapeScale > 0.0f ? shapeWeight / shapeScale : 0.0f;
  const float h = cl.spacing;
  auto compatible = [&](int fa, int fb) {
    if (fa == fb) return false;
    float ds = 0.0f;
    for (int q = 0; q < kShapeDims; ++q) {
      const float e = cl.shape[fa * kShapeDims + q] - cl.shape[fb * kShapeDims + q];
      ds += e * e;
    }
    return wShape * wShape * ds <= weldShapeLimit * weldShapeLimit;
  };
  if (h > 0.0f && F > 1) {
    const float tau = h / 3.0f;
    std::unordered_map<std::int64_t, std::vector<int>> grid;
    auto key = [&](const glm::vec2& p) {
      const glm::ivec2 g(static_cast<int>(std::floor(p.x / tau)),
                         static_cast<int>(std::floor(p.y / tau)));
      return std::pair<int, int>(g.x, g.y);
    };
    auto pack = [](int x, int y) {
      // from the bit patterns (a negative x shifted left is undefined)
      const std::uint64_t hi = static_cast<std::uint64_t>(static_cast<std::uint32_t>(x)) << 32;
      return static_cast<std::int64_t>(hi ^ static_cast<std::uint32_t>(y));
    };
    for (int i = 0; i < N; ++i) {
      const auto g = key(cornerPos(i));
      grid[pack(g.first, g.second)].push_back(i);
    }
    struct Pair {
      float d;
      int a, b;
    };
    std::vector<Pair> pairs;
    for (int i = 0; i < N; ++i) {
      const auto g = key(cornerPos(i));
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          auto it = grid.find(pack(g.first + dx, g.second + dy));
          if (it == grid.end()) continue;
          for (int j : it->second) {
            if (j <= i || j / 4 == i / 4) continue;
            const float d = glm::length(cornerPos(i) - cornerPos(j));
            if (d < tau && compatible(i / 4, j / 4)) pairs.push_back({d, i, j});
          }
        }
    }
    std::sort(pairs.begin(), pairs.end(), [](const Pair& x, const Pair& y) { return x.d < y.d; });
    for (const Pair& p : pairs) {
      const int ra = find(p.a), rb = find(p.b);
      if (ra == rb) continue;
      const std::vector<int>& ga = groupOf[ra];
      const std::vector<int>& gb = groupOf[rb];
      bool ok = true;
      glm::vec2 centroid(0.0f);
      for (int x : ga) centroid += cornerPos(x);
      for (int x : gb) centroid += cornerPos(x);
      centroid /= static_cast<float>(ga.size() + gb.size());
      for (int x : ga)
        for (int y : gb) ok = ok && compatible(x / 4, y / 4);
      for (int x : ga) ok = ok && glm::length(cornerPos(x) - centroid) < 0.75f * tau;
      for (int x : gb) ok = ok && glm::length(cornerPos(x) - centroid) < 0.75f * tau;
      if (!ok) continue;
      parent[rb] = ra;
      groupOf[ra].insert(groupOf[ra].end(), gb.begin(), gb.end());
      groupOf[rb].clear();
    }
  }

  // vertices from groups; a face whose welded quad folds or shrinks takes its corners back
  // (each pass only detaches, so this ends)
  auto detach = [&](int id) {
    const int r = find(id);
    std::vector<int>& g = groupOf[r];
    if (g.size() <= 1) return;
    g.erase(std::remove(g.begin(), g.end(), id), g.end());
    if (r == id) {  // the group moves to a new root
      const int nr = g.front();
      groupOf[nr] = g;
      g.clear();
      for (int x : groupOf[nr]) parent[x] = nr;
    }
    parent[id] = id;
    groupOf[id] = {id};
  };
  std::vector<int> root(N);
  for (;;) {
    for (int i = 0; i < N; ++i) root[i] = find(i);
    std::vector<glm::vec2> pos(N, glm::vec2(0.0f));
    for (int i = 0; i < N; ++i)
      if (root[i] == i) {
        for (int x : groupOf[i]) pos[i] += cornerPos(x);
        pos[i] /= static_cast<float>(groupOf[i].size());
      }
    std::vector<int> bad;
    for (int f = 0; f < F; ++f) {
      std::array<glm::vec2, 4> q;
      for (int k = 0; k < 4; ++k) q[k] = pos[root[4 * f + k]];
      if (!quadValid(q, quadArea(topo.ownCorners[f]))) bad.push_back(f);
    }
    if (bad.empty()) break;
    for (int f : bad)
      for (int k = 0; k < 4; ++k) detach(4 * f + k);
  }
  for (int i = 0; i < N; ++i) root[i] = find(i);
  std::vector<int> vertexOf(N, -1);
  for (int i = 0; i < N; ++i) {
    if (root[i] != i) continue;
    vertexOf[i] = static_cast<int>(topo.vertexChart.size());
    glm::vec2 p(0.0f);
    for (int x : groupOf[i]) p += cornerPos(x);
    topo.vertexChart.push_back(p / static_cast<float>(groupOf[i].size()));
    topo.vertexCorners.push_back(groupOf[i]);
    if (groupOf[i].size() > 1) ++topo.weldedVertices;
  }
  for (int f = 0; f < F; ++f)
    for (int k = 0; k < 4; ++k) topo.faces[f][k] = vertexOf[root[4 * f + k]];
  return topo;
}

}  // namespace clhair::fit
