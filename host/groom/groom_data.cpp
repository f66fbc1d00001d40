// groom_data.cpp — styling frames, strand distribution and bounds of a hair mesh.
#include "groom/groom_data.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>

namespace clhair {

namespace {

void store3(float* dst, const glm::vec3& v, float w) {
  dst[0] = v.x;
  dst[1] = v.y;
  dst[2] = v.z;
  dst[3] = w;
}

int cornerCount(const std::array<int, 4>& f) { return f[3] < 0 ? 3 : 4; }

}  // namespace

std::uint32_t fullDetailControlPoints(const HairMesh& mesh) {
  // at least one point per layer, snapped up to 2^k + 1 like every LOD level (Lipp Eq. 5)
  int c = 3;
  while (c < std::max(mesh.controlPoints, mesh.layerCount)) c = 2 * (c - 1) + 1;
  return static_cast<std::uint32_t>(std::min(c, CLH_MAX_CONTROL_POINTS));
}

GroomData prepareGroom(const HairMesh& m) {
  GroomData out;
  const int L = m.layerCount, V = m.vertexCount;
  const std::size_t n = static_cast<std::size_t>(L) * V;
  out.vertices.resize(n);

  // Bhokare Eq. 1-3: for each corner of each face, the triangle (corner, next, previous)
  // maps texture-space u and v to object space through [p1-p0 p2-p0] T^-1; the vertex
  // direction is the average of those maps weighted by the triangles' uv areas.
  std::vector<glm::vec3> du(n, glm::vec3(0.0f)), dv(n, glm::vec3(0.0f));
  std::vector<float> weight(V, 0.0f);
  for (const auto& f : m.faces) {
    const int k = cornerCount(f);
    for (int c = 0; c < k; ++c) {
      int i0 = f[c], i1 = f[(c + 1) % k], i2 = f[(c + k - 1) % k];
      glm::vec2 e1 = m.uv[i1] - m.uv[i0], e2 = m.uv[i2] - m.uv[i0];
      float det = e1.x * e2.y - e2.x * e1.y;
      if (std::fabs(det) < 1e-12f) continue;
      float area = 0.5f * std::fabs(det);
      weight[i0] += area;
      for (int l = 0; l < L; ++l) {
        glm::vec3 p1 = m.position(l, i1) - m.position(l, i0);
        glm::vec3 p2 = m.position(l, i2) - m.position(l, i0);
        glm::vec3 u = (p1 * e2.y - p2 * e1.y) / det;
        glm::vec3 v = (p2 * e1.x - p1 * e2.x) / det;
        std::size_t idx = static_cast<std::size_t>(l) * V + i0;
        du[idx] += area * u;
        dv[idx] += area * v;
      }
    }
  }

  float maxJacobian = 0.0f;
  for (int l = 0; l < L; ++l) {
    for (int v = 0; v < V; ++v) {
      std::size_t idx = static_cast<std::size_t>(l) * V + v;
      gpu::ClhMeshVertex& mv = out.vertices[idx];
      float wsum = weight[v] > 0.0f ? weight[v] : 1.0f;
      glm::vec3 u = du[idx] / wsum, w3 = dv[idx] / wsum;
      maxJacobian = std::max({maxJacobian, glm::length(u), glm::length(w3)});
      float wcoord = m.w.empty() ? static_cast<float>(l) / static_cast<float>(L - 1) : m.w[idx];
      float ao = m.ao.empty() ? 1.0f : m.ao[idx];
      store3(mv.pos, m.positions[idx], wcoord);
      store3(mv.tan, m.tangents.empty() ? glm::vec3(0.0f) : m.tangents[idx], ao);
      store3(mv.du, u, 0.0f);
      store3(mv.dv, w3, 0.0f);
    }
  }

  // Strands spread over the bundles by root-face area (largest remainder keeps the total), as
  // the file's validation counted them against kMaxBundleStrands.
  const std::size_t F = m.faces.size();
  const std::vector<std::uint32_t> counts = bundleStrandCounts(m);
  out.bundles.resize(F);
  for (std::size_t f = 0; f < F; ++f) {
    const auto& face = m.faces[f];
    gpu::ClhBundle& b = out.bundles[f];
    std::memset(&b, 0, sizeof(b));
    const bool tri = cornerCount(face) == 3;
    for (int c = 0; c < 4; ++c) {
      int vi = tri && c == 3 ? face[2] : face[c];
      b.vtx[c] = vi;
      b.uv[2 * c] = m.uv[vi].x;
      b.uv[2 * c + 1] = m.uv[vi].y;
    }
    b.triangle = tri ? 1u : 0u;
    b.strand_count = counts[f];
    b.first_strand = static_cast<std::uint32_t>(out.totalStrands);
    b.lod_delta =
        gpu::clh_u01(gpu::clh_hash3(m.seed, static_cast<std::uint32_t>(f), CLH_RNG_LOD_DELTA));
    out.maxBundleStrands = std::max(out.maxBundleStrands, counts[f]);
    out.totalStrands += counts[f];
  }

  // Bounds: the mesh, plus the largest styling offset, plus a margin for Hermite overshoot.
  const StyleParams& s = m.style;
  float clumpReach =
      s.clumpFrequency > 0.0f ? s.clumpStrength * maxJacobian * 1.2f / s.clumpFrequency : 0.0f;
  out.styleMargin = s.curlAmplitude + s.frizzAmplitude + s.flyawayAmplitude + clumpReach;
  glm::vec3 lo(1e30f), hi(-1e30f);
  float maxStep = 0.0f;
  for (int v = 0; v < V; ++v) {
    for (int l = 0; l < L; ++l) {
      lo = glm::min(lo, m.position(l, v));
      hi = glm::max(hi, m.position(l, v));
      if (l > 0) maxStep = std::max(maxStep, glm::length(m.position(l, v) - m.position(l - 1, v)));
    }
  }
  float margin = out.styleMargin + 0.25f * maxStep;
  out.boundsMin = lo - glm::vec3(margin);
  out.boundsMax = hi + glm::vec3(margin);
  return out;
}

void fillGroomParams(const HairMesh& m, const GroomData& data, gpu::ClhGroomGpu& p) {
  p.bundle_count = static_cast<std::uint32_t>(data.bundles.size());
  p.layer_count = static_cast<std::uint32_t>(m.layerCount);
  p.vertex_count = static_cast<std::uint32_t>(m.vertexCount);
  p.has_tangents = m.tangents.empty() ? 0u : 1u;
  p.control_points = fullDetailControlPoints(m);
  p.lod_enabled = m.lod.enabled ? 1u : 0u;
  p.seed = m.seed;
  p.lod_lambda = m.lod.lambda;
  p.lod_morph_window = m.lod.morphWindow;
  p.strand_width = m.appearance.strandWidth;
  p.hit_diameter_px = m.appearance.minHitDiameterPx;
  const StyleParams& s = m.style;
  p.clump_strength = s.clumpStrength;
  p.clump_frequency = s.clumpStrength > 0.0f ? s.clumpFrequency : 0.0f;
  p.clump_shape = s.clumpShape;
  p.curl_amplitude = s.curlAmplitude;
  p.curl_frequency = s.curlFrequency;
  p.curl_helix = s.curlHelix;
  p.curl_phase_jitter = s.curlPhaseJitter;
  p.frizz_amplitude = s.frizzAmplitude;
  p.frizz_frequency = s.frizzFrequency;
  p.flyaway_fraction = s.flyawayFraction;
  p.flyaway_amplitude = s.flyawayAmplitude;
  p.length_variation = s.lengthVariation;
  const AppearanceParams& a = m.appearance;
  store3(p.root_color, a.rootColor, 1.0f);
  store3(p.tip_color, a.tipColor, 1.0f);
  p.melanin[0] = a.eumelanin[0];
  p.melanin[1] = a.eumelanin[1];
  p.melanin[2] = a.pheomelanin[0];
  p.melanin[3] = a.pheomelanin[1];
  p.bsdf[0] = a.betaM;
  p.bsdf[1] = a.betaN;
  p.bsdf[2] = a.cuticleTiltDeg * 3.14159265358979f / 180.0f;
  p.bsdf[3] = a.ior;
  p.look[0] = a.variation;
  p.look[1] = a.useMelanin ? 1.0f : 0.0f;
}

}  // namespace clhair
