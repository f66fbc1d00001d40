// cage_layers.cpp — see cage_layers.h.
#include "fit/cage_layers.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <glm/geometric.hpp>

#include "fit/arc_model.h"
#include "fit/cage_solve.h"
#include "fit/head_surface.h"
#include "fit/linear_algebra.h"
#include "fit/parallel.h"

namespace clhair::fit {

namespace {

constexpr float kLengthQuantile = 0.95f;
constexpr double kPriorWeight = 0.01;   // relative to a vertex's own data
constexpr double kPriorFloor = 1e-3;    // relative to the mean data of a vertex
constexpr float kReachSlack = 0.02f;    // a strand still counts on a layer this far past its tip

void bilinearWeights(const glm::vec2& st, float w[4]) {
  w[0] = (1 - st.x) * (1 - st.y);
  w[1] = st.x * (1 - st.y);
  w[2] = st.x * st.y;
  w[3] = (1 - st.x) * st.y;
}

float quantile(std::vector<float>& v, float q) {
  if (v.empty()) return 0.0f;
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5f));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

glm::vec3 unitOr(const glm::vec3& v, const glm::vec3& fallback) {
  const float l = glm::length(v);
  return l > 1e-12f ? v / l : fallback;
}

}  // namespace

StrandPlacement placeStrands(const FitStrands& s, const Clusters& cl, const CageTopology& topo,
                             const std::vector<glm::vec2>& chartRoots, int threads) {
  const std::size_t n = s.count();
  StrandPlacement pl;
  pl.face = cl.label;
  pl.st.resize(n);
  parallelFor(n, threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const auto& f = topo.faces[pl.face[i]];
      const std::array<glm::vec2, 4> q = {topo.vertexChart[f[0]], topo.vertexChart[f[1]],
                                          topo.vertexChart[f[2]], topo.vertexChart[f[3]]};
      pl.st[i] = glm::clamp(inverseBilinear(q, chartRoots[i]), glm::vec2(0.0f), glm::vec2(1.0f));
    }
  });
  // full length at every vertex: a high quantile of the strands near it
  const std::size_t V = topo.vertexChart.size();
  std::vector<std::vector<float>> near(V);
  std::vector<std::vector<float>> faceLengths(topo.faces.size());
  for (std::size_t i = 0; i < n; ++i) {
    float w[4];
    bilinearWeights(pl.st[i], w);
    const auto& f = topo.faces[pl.face[i]];
    for (int c = 0; c < 4; ++c)
      if (w[c] >= 0.2f) near[f[c]].push_back(s.length[i]);
    faceLengths[pl.face[i]].push_back(s.length[i]);
  }
  std::vector<float> faceQ(topo.faces.size());
  for (std::size_t f = 0; f < faceQ.size(); ++f) faceQ[f] = quantile(faceLengths[f], kLengthQuantile);
  pl.vertexLength.assign(V, 0.0f);
  for (std::size_t v = 0; v < V; ++v) {
    if (near[v].size() >= 3) {
      pl.vertexLength[v] = quantile(near[v], kLengthQuantile);
    } else {
      float m = 0.0f;
      for (int id : topo.vertexCorners[v]) m = std::max(m, faceQ[id / 4]);
      pl.vertexLength[v] = m;
    }
  }
  pl.fullLength.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    float w[4];
    bilinearWeights(pl.st[i], w);
    const auto& f = topo.faces[pl.face[i]];
    float l = 0.0f;
    for (int c = 0; c < 4; ++c) l += w[c] * pl.vertexLength[f[c]];
    pl.fullLength[i] = std::max(l, s.length[i]);
  }
  return pl;
}

std::vector<float> linearLayerArcs(const FitStrands& s, const StrandPlacement& pl, int L) {
  std::vector<float> arcs(s.count() * static_cast<std::size_t>(L));
  for (std::size_t i = 0; i < s.count(); ++i)
    for (int l = 0; l < L; ++l) {
      const float arc = static_cast<float>(l) / static_cast<float>(L - 1) * pl.fullLength[i];
      arcs[i * L + l] = arc > s.length[i] + kReachSlack * pl.fullLength[i] ? -1.0f : arc;
    }
  return arcs;
}

std::vector<float> modelLayerArcs(const FitStrands& s, StrandPlacement& pl, const BaseCurves& base,
                                  const FittedStyle& curl, int L, int threads) {
  std::vector<float> arcs(s.count() * static_cast<std::size_t>(L));
  parallelFor(s.count(), threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const ArcMap m = arcMap(base, pl.face[i], pl.st[i], curl);
      const float tip = m.wAt(s.length[i]);  // where along the base curve the strand ends
      // a strand longer than the model's full curve is stretched onto it (it reaches w = 1)
      const float stretch = tip > 1.0f && m.full() > 0.0f ? s.length[i] / m.full() : 1.0f;
      for (int l = 0; l < L; ++l) {
        const float w = static_cast<float>(l) / static_cast<float>(L - 1);
        arcs[i * L + l] = w > tip + kReachSlack ? -1.0f : m.arcAt(w) * stretch;
      }
      pl.fullLength[i] = m.full() * stretch;
    }
  });
  return arcs;
}

std::vector<glm::vec3> fitCageLayers(const FitStrands& s, const Clusters& cl,
                                     const CageTopology& topo, const ScalpChart& chart,
                                     const StrandPlacement& pl, const std::vector<float>& layerArc,
                                     int L, const HeadSurface* head, int threads) {
  const int F = static_cast<int>(topo.faces.size());
  const std::size_t V = topo.vertexChart.size();
  const std::size_t n = s.count();
  std::vector<std::vector<int>> members(F);
  for (std::size_t i = 0; i < n; ++i) members[pl.face[i]].push_back(static_cast<int>(i));
  auto layerPoint = [&](std::size_t i, int l, glm::vec3& p) {
    const float arc = layerArc[i * L + l];
    if (arc < 0.0f) return false;
    p = s.atArc(i, arc);
    return true;
  };

  // 1. every cluster's principal-axis quad on every layer (corner priors)
  std::vector<glm::vec3> cornerPrior(static_cast<std::size_t>(F) * 4 * L);
  parallelFor(static_cast<std::size_t>(F), threads, [&](std::size_t fb, std::size_t fe) {
    for (std::size_t f = fb; f < fe; ++f) {
      const glm::vec2 centreChart = cl.centre[f];
      glm::vec3 ex, ey, nrm;
      chart.frameAt(centreChart, ex, ey, nrm);
      const glm::vec2 c0 = topo.axes[f][0], c1 = topo.axes[f][1];
      glm::vec3 e1 = unitOr(c0.x * ex + c0.y * ey, ex), e2 = unitOr(c1.x * ex + c1.y * ey, ey);
      // own corner offsets along the chart axes: half extents a, b
      const glm::vec2 d2 = topo.ownCorners[f][2] - centreChart;
      const float a0 = std::fabs(glm::dot(d2, c0)), b0 = std::fabs(glm::dot(d2, c1));
      const float sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
      std::vector<glm::vec3> centres(L);
      glm::vec3 prevCentre(0.0f), prevTangent = nrm;
      float prevA = a0, prevB = b0;
      for (int l = 0; l < L; ++l) {
        glm::dvec3 sum(0.0);
        std::vector<glm::vec3> pts;
        for (int i : members[f]) {
          glm::vec3 p;
          if (layerPoint(static_cast<std::size_t>(i), l, p)) pts.push_back(p);
        }
        glm::vec3 centre;
        if (!pts.empty()) {
          for (const glm::vec3& p : pts) sum += glm::dvec3(p);
          centre = glm::vec3(sum / static_cast<double>(pts.size()));
        } else if (l >= 2) {
          centre = centres[l - 1] + (centres[l - 1] - centres[l - 2]);
        } else {
          centre = prevCentre + prevTangent * (0.01f * static_cast<float>(s.medianLength));
        }
        centres[l] = centre;
        float a = a0, b = b0;
        if (l > 0) {
          const glm::vec3 t = unitOr(centre - centres[l - 1], prevTangent);
          // carry the frame across: project, then Gram-Schmidt, keeping the handedness
          glm::vec3 u = unitOr(e1 - glm::dot(e1, t) * t, e2);
          glm::vec3 v = e2 - glm::dot(e2, t) * t - glm::dot(e2, u) * u;
          v = unitOr(v, glm::cross(t, u));
          a = prevA;
          b = prevB;
          if (pts.size() >= 3) {
            double cuu = 0, cuv = 0, cvv = 0;
            for (const glm::vec3& p : pts) {
              const glm::vec3 d = p - centre;
              const double pu = glm::dot(d, u), pv = glm::dot(d, v);
              cuu += pu * pu;
              cuv += pu * pv;
              cvv += pv * pv;
            }
            const double m = static_cast<double>(pts.size());
            double ev[2];
            glm::dvec2 evec[2];
            symmetricEigen2(cuu / m, cuv / m, cvv / m, ev, evec);
            glm::vec2 ax0(1, 0), ax1(0, 1);  // in (u, v)
            if (std::sqrt(std::max(ev[0], 0.0) / std::max(ev[1], 1e-30)) > 1.3) {
              // the principal axis nearest to u (of four signed choices) becomes e1
              const glm::vec2 p0(evec[0]), p1(evec[1]);
              const glm::vec2 cand[4] = {p0, -p0, p1, -p1};
              int best = 0;
              for (int k = 1; k < 4; ++k)
                if (cand[k].x > cand[best].x) best = k;
              ax0 = cand[best];
              ax1 = glm::vec2(-ax0.y, ax0.x);  // keeps (u, v) handedness
            }
            const double va = (cuu * ax0.x * ax0.x + 2 * cuv * ax0.x * ax0.y + cvv * ax0.y * ax0.y) / m;
            const double vb = (cuu * ax1.x * ax1.x + 2 * cuv * ax1.x * ax1.y + cvv * ax1.y * ax1.y) / m;
            a = std::max(static_cast<float>(std::sqrt(3.0 * std::max(va, 0.0))), s.fibreWidth);
            b = std::max(static_cast<float>(std::sqrt(3.0 * std::max(vb, 0.0))), s.fibreWidth);
            e1 = unitOr(ax0.x * u + ax0.y * v, u);
            e2 = unitOr(ax1.x * u + ax1.y * v, v);
          } else {
            e1 = u;
            e2 = v;
          }
          prevTangent = t;
        }
        for (int k = 0; k < 4; ++k)
          cornerPrior[(static_cast<std::size_t>(f) * L + l) * 4 + k] =
              centre + sx[k] * a * e1 + sy[k] * b * e2;
        prevCentre = centre;
        prevA = a;
        prevB = b;
      }
    }
  });

  // 2. welded vertices start at the mean of their clusters' corners; then least squares
  std::vector<glm::vec3> positions(static_cast<std::size_t>(L) * V);
  for (int l = 0; l < L; ++l) {
    std::vector<glm::vec3> prior(V, glm::vec3(0.0f));
    for (std::size_t v = 0; v < V; ++v) {
      for (int id : topo.vertexCorners[v])
        prior[v] += cornerPrior[(static_cast<std::size_t>(id / 4) * L + l) * 4 + id % 4];
      prior[v] /= static_cast<float>(topo.vertexCorners[v].size());
    }
    std::vector<FaceBlock> blocks(F);
    parallelFor(static_cast<std::size_t>(F), threads, [&](std::size_t fb, std::size_t fe) {
      for (std::size_t f = fb; f < fe; ++f) {
        FaceBlock& blk = blocks[f];
        for (int i : members[f]) {
          glm::vec3 p;
          if (!layerPoint(static_cast<std::size_t>(i), l, p)) continue;
          float w[4];
          bilinearWeights(pl.st[i], w);
          for (int a = 0; a < 4; ++a) {
            blk.r[a] += static_cast<double>(w[a]) * glm::dvec3(p);
            for (int b = 0; b < 4; ++b) blk.b[a][b] += static_cast<double>(w[a]) * w[b];
          }
          blk.strands += 1.0;
        }
      }
    }, 16);
    std::vector<glm::vec3> layer = solveCageLayer(topo.faces, blocks, prior, kPriorWeight, kPriorFloor);
    if (std::getenv("CLHAIR_FIT_DEBUG") && l == L - 1) {
      for (int f = 0; f < 3; ++f) {
        std::vector<float> ls;
        for (int i : members[f]) ls.push_back(s.length[i]);
        std::sort(ls.begin(), ls.end());
        std::fprintf(stderr, "  lengths min %g p50 %g p95 %g max %g; fullLength of first %g\n", ls.front(), ls[ls.size()/2], ls[ls.size()*95/100], ls.back(), pl.fullLength[members[f][0]]);
        int reach = 0;
        for (int i : members[f]) { glm::vec3 p; reach += layerPoint(i, l, p); }
        std::fprintf(stderr, "face %d: members %zu reach %d  Lv %g %g %g %g  strands %g prior %g %g %g  solved %g %g %g\n", f, members[f].size(), reach,
          pl.vertexLength[topo.faces[f][0]], pl.vertexLength[topo.faces[f][1]], pl.vertexLength[topo.faces[f][2]], pl.vertexLength[topo.faces[f][3]], blocks[f].strands,
          prior[topo.faces[f][0]].x, prior[topo.faces[f][0]].y, prior[topo.faces[f][0]].z, layer[topo.faces[f][0]].x, layer[topo.faces[f][0]].y, layer[topo.faces[f][0]].z);
      }
    }
    if (l == 0 && head)
      for (glm::vec3& p : layer) p = head->closest(p);
    std::copy(layer.begin(), layer.end(), positions.begin() + static_cast<std::ptrdiff_t>(l) * V);
  }
  return positions;
}

}  // namespace clhair::fit
