// cage_layers.cpp — see cage_layers.h.
#include "fit/cage_layers.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "fit/cage_solve.h"
#include "fit/head_surface.h"
#include "fit/linear_algebra.h"
#include "fit/parallel.h"

namespace clhair::fit {

namespace {

constexpr double kPriorWeight = 0.01;  // relative to a vertex's own data
constexpr double kPriorFloor = 1e-3;   // relative to the mean data of a vertex
constexpr float kReachSlack = 0.02f;   // a strand still counts on a layer this far past its tip
constexpr float kBaseSlack = 0.15f;    // ... when the last base curves carry it on

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

// The full length behind a set of lengths: for lengths uniform in ((1 - v) L, L) the 10th
// and 90th percentiles are L (1 - 0.9 v) and L (1 - 0.1 v), so L = (0.9 q90 - 0.1 q10) / 0.8
// whatever v is (equal lengths give L itself). Percentiles, not the longest strand: flyaways
// (a few per cent of strands made longer by their frizz) do not stretch the layers.
float fullLength(std::vector<float>& v) {
  const float q90 = quantile(v, 0.9f), q10 = quantile(v, 0.1f);
  return std::max((0.9f * q90 - 0.1f * q10) / 0.8f, q90);
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
  fullLengths(s, topo, pl);
  return pl;
}

void fullLengths(const FitStrands& s, const CageTopology& topo, StrandPlacement& pl) {
  const std::size_t n = s.count();
  const std::size_t V = topo.vertexChart.size();
  const std::size_t F = topo.faces.size();
  // the mean length of each face's strands, at each vertex the mean over its faces (strands
  // of one place share a length but for length variation; across a scalp the geometry
  // changes it), and the top of all strands' lengths relative to that mean
  std::vector<double> faceSum(F, 0.0), faceCount(F, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    faceSum[pl.face[i]] += s.length[i];
    faceCount[pl.face[i]] += 1.0;
  }
  std::vector<double> vSum(V, 0.0), vCount(V, 0.0);
  for (std::size_t f = 0; f < F; ++f)
    for (int c = 0; c < 4; ++c) {
      vSum[topo.faces[f][c]] += faceSum[f];
      vCount[topo.faces[f][c]] += faceCount[f];
    }
  std::vector<float> raw(V, 0.0f), mean(V, 0.0f);
  for (std::size_t v = 0; v < V; ++v)
    raw[v] = vCount[v] > 0.0 ? static_cast<float>(vSum[v] / vCount[v]) : 0.0f;
  // once more over the vertices a vertex shares a face with: less noise, as smooth a field
  std::vector<float> k(V, 0.0f);
  for (const auto& f : topo.faces)
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) {
        mean[f[a]] += raw[f[b]];
        k[f[a]] += 1.0f;
      }
  for (std::size_t v = 0; v < V; ++v) mean[v] = k[v] > 0.0f ? mean[v] / k[v] : raw[v];
  auto atStrand = [&](std::size_t i, const std::vector<float>& field) {
    float w[4];
    bilinearWeights(pl.st[i], w);
    const auto& f = topo.faces[pl.face[i]];
    float l = 0.0f;
    for (int c = 0; c < 4; ++c) l += w[c] * field[f[c]];
    return l;
  };
  std::vector<float> ratio;
  for (std::size_t i = 0; i < n; ++i) {
    const float m = atStrand(i, mean);
    if (m > 0.0f) ratio.push_back(s.length[i] / m);
  }
  const float top = ratio.empty() ? 1.0f : fullLength(ratio);
  // never past the longest input strand: a generated strand of full length is as long as
  // its layers (fit_mesh.cpp caps what the styling adds)
  const float longest = n > 0 ? *std::max_element(s.length.begin(), s.length.end()) : 0.0f;
  pl.vertexLength.resize(V);
  for (std::size_t v = 0; v < V; ++v) pl.vertexLength[v] = std::min(top * mean[v], longest);
  pl.fullLength.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    pl.fullLength[i] = std::max(atStrand(i, pl.vertexLength), s.length[i]);
}

std::vector<float> linearLayerArcs(const FitStrands& s, const StrandPlacement& pl, int L,
                                   bool carried) {
  const float slack = carried ? kBaseSlack : kReachSlack;
  std::vector<float> arcs(s.count() * static_cast<std::size_t>(L));
  for (std::size_t i = 0; i < s.count(); ++i)
    for (int l = 0; l < L; ++l) {
      const float arc = static_cast<float>(l) / static_cast<float>(L - 1) * pl.fullLength[i];
      arcs[i * L + l] = arc > s.length[i] + slack * pl.fullLength[i] ? -1.0f : arc;
    }
  return arcs;
}

std::vector<glm::vec3> fitCageLayers(const FitStrands& s, const Clusters& cl,
                                     const CageTopology& topo, const ScalpChart& chart,
                                     const StrandPlacement& pl, const std::vector<float>& layerArc,
                                     int L, const BaseCurves* previous, const HeadSurface* head,
                                     int threads) {
  const int F = static_cast<int>(topo.faces.size());
  const std::size_t V = topo.vertexChart.size();
  const std::size_t n = s.count();
  std::vector<std::vector<int>> members(F);
  for (std::size_t i = 0; i < n; ++i) members[pl.face[i]].push_back(static_cast<int>(i));
  // every strand's point on every layer; past its tip the last base curves carry the tip on
  // (the strand's offset from its base curve kept), or, in a first fit, a straight line
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<glm::vec3> points(n * static_cast<std::size_t>(L), glm::vec3(nan));
  parallelFor(n, threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      for (int l = 0; l < L; ++l) {
        const float arc = layerArc[i * L + l];
        if (arc < 0.0f) continue;
        if (arc <= s.length[i] || !previous || !(pl.fullLength[i] > 0.0f)) {
          points[i * L + l] = s.atArc(i, arc);
          continue;
        }
        const float w[2] = {s.length[i] / pl.fullLength[i], arc / pl.fullLength[i]};
        BaseSample bs[2];
        previous->evaluate(pl.face[i], pl.st[i], w, 2, bs);
        points[i * L + l] = s.atArc(i, s.length[i]) + bs[1].pos - bs[0].pos;
      }
  });
  auto layerPoint = [&](std::size_t i, int l, glm::vec3& p) {
    p = points[i * L + l];
    return !std::isnan(p.x);
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
            const double va =
                (cuu * ax0.x * ax0.x + 2 * cuv * ax0.x * ax0.y + cvv * ax0.y * ax0.y) / m;
            const double vb =
                (cuu * ax1.x * ax1.x + 2 * cuv * ax1.x * ax1.y + cvv * ax1.y * ax1.y) / m;
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
    // least squares, then twice again with strands far from the fitted quad down-weighted
    // (Huber weights beyond twice a face's typical distance): flyaways and strands of
    // another clump do not drag the corners
    std::vector<float> weight(n, 1.0f);
    std::vector<glm::vec3> layer;
    for (int pass = 0; pass < 3; ++pass) {
      std::vector<FaceBlock> blocks(F);
      parallelFor(
          static_cast<std::size_t>(F), threads,
          [&](std::size_t fb, std::size_t fe) {
            for (std::size_t f = fb; f < fe; ++f) {
              FaceBlock& blk = blocks[f];
              std::vector<float> dist;
              if (pass > 0) {  // this face's distances to the last solution, and their median
                for (int i : members[f]) {
                  glm::vec3 p;
                  if (!layerPoint(static_cast<std::size_t>(i), l, p)) continue;
                  float w[4];
                  bilinearWeights(pl.st[i], w);
                  glm::vec3 q(0.0f);
                  for (int a = 0; a < 4; ++a) q += w[a] * layer[topo.faces[f][a]];
                  dist.push_back(glm::length(p - q));
                }
                std::vector<float> sorted = dist;
                const float typical = std::max(2.0f * quantile(sorted, 0.5f), s.fibreWidth);
                std::size_t k = 0;
                for (int i : members[f]) {
                  glm::vec3 p;
                  if (!layerPoint(static_cast<std::size_t>(i), l, p)) continue;
                  weight[i] = dist[k] > typical ? typical / dist[k] : 1.0f;
                  ++k;
                }
              }
              for (int i : members[f]) {
                glm::vec3 p;
                if (!layerPoint(static_cast<std::size_t>(i), l, p)) continue;
                float w[4];
                bilinearWeights(pl.st[i], w);
                const double h = weight[i];
                for (int a = 0; a < 4; ++a) {
                  blk.r[a] += h * w[a] * glm::dvec3(p);
                  for (int b = 0; b < 4; ++b) blk.b[a][b] += h * w[a] * w[b];
                }
                blk.strands += h;
              }
            }
          },
          16);
      layer = solveCageLayer(topo.faces, blocks, prior, kPriorWeight, kPriorFloor);
    }
    if (l == 0 && head)
      for (glm::vec3& p : layer) p = head->closest(p);
    std::copy(layer.begin(), layer.end(), positions.begin() + static_cast<std::ptrdiff_t>(l) * V);
  }
  return positions;
}

}  // namespace clhair::fit
