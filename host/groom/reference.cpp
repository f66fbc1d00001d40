// reference.cpp — serial strand generation for tests (see reference.h).
#include "groom/reference.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

namespace clhair {

namespace {

using gpu::clh_hash2;
using gpu::clh_hash3;
using gpu::clh_u01;

constexpr float kPi = 3.14159265358979323846f;

glm::vec3 v3(const float* p) { return glm::vec3(p[0], p[1], p[2]); }

struct LayerSample {
  glm::vec3 pos, tangent, du, dv;
  float w = 0.0f, ao = 1.0f;
};

float smooth01(float x) {
  x = std::min(std::max(x, 0.0f), 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

glm::vec3 normalizeOr(const glm::vec3& v, const glm::vec3& fallback) {
  float l2 = glm::dot(v, v);
  return (l2 > 1e-30f && l2 < 1e30f) ? v / std::sqrt(l2) : fallback;
}

float valueNoise(std::uint32_t key, std::uint32_t channel, float x) {
  float fl = std::floor(x);
  int i = static_cast<int>(fl);
  float a = clh_u01(clh_hash3(key, static_cast<std::uint32_t>(i), channel)) * 2.0f - 1.0f;
  float b = clh_u01(clh_hash3(key, static_cast<std::uint32_t>(i + 1), channel)) * 2.0f - 1.0f;
  return a + (b - a) * smooth01(x - fl);
}

// Nearest jittered clump center in uv (3x3 cells around the strand's cell).
glm::vec2 clumpCenter(std::uint32_t seed, float freq, glm::vec2 uv, std::uint32_t& id) {
  glm::vec2 g = uv * freq;
  int cx0 = static_cast<int>(std::floor(g.x)), cy0 = static_cast<int>(std::floor(g.y));
  float best = 1e30f;
  glm::vec2 bestCenter = uv;
  id = 0;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      int cx = cx0 + dx, cy = cy0 + dy;
      std::uint32_t key =
          clh_hash3(seed ^ 0x5c1u, static_cast<std::uint32_t>(cx), static_cast<std::uint32_t>(cy));
      glm::vec2 jitter(clh_u01(clh_hash2(key, 0u)), clh_u01(clh_hash2(key, 1u)));
      glm::vec2 center = glm::vec2(cx, cy) + 0.5f + (jitter - 0.5f) * 0.8f;
      glm::vec2 d = g - center;
      float d2 = glm::dot(d, d);
      if (d2 < best) {
        best = d2;
        bestCenter = center / freq;
        id = key;
      }
    }
  }
  return bestCenter;
}

}  // namespace

ReferenceStrand referenceStrand(const GroomData& data, const gpu::ClhGroomGpu& g,
                                const RootSets& roots, std::uint32_t bundle,
                                std::uint32_t localIndex, std::uint32_t C) {
  const gpu::ClhBundle& b = data.bundles[bundle];
  const int L = static_cast<int>(g.layer_count);
  const int V = static_cast<int>(g.vertex_count);

  // 1. Root sample and the strand's constants.
  std::uint32_t r = std::min(localIndex, roots.size() - 1);
  glm::vec2 st = b.triangle ? roots.triangle[r] : roots.quad[r];
  float wq[4] = {(1 - st.x) * (1 - st.y), st.x * (1 - st.y), st.x * st.y, (1 - st.x) * st.y};
  ReferenceStrand out;
  for (int c = 0; c < 4; ++c) out.uv += wq[c] * glm::vec2(b.uv[2 * c], b.uv[2 * c + 1]);
  const std::uint32_t id = clh_hash3(g.seed, bundle, localIndex);
  std::uint32_t clumpId = 0;
  glm::vec2 clumpDuv(0.0f);
  if (g.clump_frequency > 0.0f)
    clumpDuv = clumpCenter(g.seed, g.clump_frequency, out.uv, clumpId) - out.uv;
  const float phase = 2.0f * kPi *
                      (clh_u01(clh_hash2(clumpId, CLH_RNG_PHASE)) +
                       g.curl_phase_jitter * clh_u01(clh_hash2(id, CLH_RNG_PHASE)));
  const bool flyaway = clh_u01(clh_hash2(id, CLH_RNG_FLYAWAY)) < g.flyaway_fraction;
  const float frizz = g.frizz_amplitude + (flyaway ? g.flyaway_amplitude : 0.0f);
  const float lengthFraction = 1.0f - g.length_variation * clh_u01(clh_hash2(id, CLH_RNG_LENGTH));

  // 2. The strand's sample on every layer: bilinear in the layer's quad.
  std::vector<LayerSample> layer(L);
  for (int l = 0; l < L; ++l) {
    LayerSample& s = layer[l];
    s.pos = s.tangent = s.du = s.dv = glm::vec3(0.0f);
    s.w = s.ao = 0.0f;
    for (int c = 0; c < 4; ++c) {
      int vi = std::min(std::max(b.vtx[c], 0), V - 1);
      const gpu::ClhMeshVertex& mv = data.vertices[static_cast<std::size_t>(l) * V + vi];
      s.pos += wq[c] * v3(mv.pos);
      s.w += wq[c] * mv.pos[3];
      s.tangent += wq[c] * v3(mv.tan);
      s.ao += wq[c] * mv.tan[3];
      s.du += wq[c] * v3(mv.du);
      s.dv += wq[c] * v3(mv.dv);
    }
  }
  // 3. Layer tangents by finite differences unless the mesh gives them.
  if (!g.has_tangents) {
    for (int l = 0; l < L; ++l) {
      if (l == 0)
        layer[l].tangent = layer[1].pos - layer[0].pos;
      else if (l == L - 1)
        layer[l].tangent = layer[L - 1].pos - layer[L - 2].pos;
      else
        layer[l].tangent = 0.5f * (layer[l + 1].pos - layer[l - 1].pos);
    }
  }

  // 4. C points on the Hermite base spline, styled.
  for (std::uint32_t k = 0; k < C; ++k) {
    float x = (static_cast<float>(k) / static_cast<float>(C - 1)) * lengthFraction *
              static_cast<float>(L - 1);
    int i = std::max(0, std::min(static_cast<int>(std::floor(x)), L - 2));
    float t = x - static_cast<float>(i);
    const LayerSample& a = layer[i];
    const LayerSample& c = layer[i + 1];
    float h00 = 2 * t * t * t - 3 * t * t + 1, h10 = t * t * t - 2 * t * t + t;
    float h01 = -2 * t * t * t + 3 * t * t, h11 = t * t * t - t * t;
    float d00 = 6 * t * t - 6 * t, d10 = 3 * t * t - 4 * t + 1;
    float d01 = -6 * t * t + 6 * t, d11 = 3 * t * t - 2 * t;
    glm::vec3 base = h00 * a.pos + h10 * a.tangent + h01 * c.pos + h11 * c.tangent;
    glm::vec3 deriv = d00 * a.pos + d10 * a.tangent + d01 * c.pos + d11 * c.tangent;
    glm::vec3 du = a.du + (c.du - a.du) * t;
    glm::vec3 dv = a.dv + (c.dv - a.dv) * t;
    float w = a.w + (c.w - a.w) * t;

    // Styling frame: strand direction, the u direction made perpendicular to it, and their cross.
    glm::vec3 et = normalizeOr(deriv, glm::vec3(0, 1, 0));
    glm::vec3 e1 = normalizeOr(du - glm::dot(du, et) * et,
                               normalizeOr(dv - glm::dot(dv, et) * et, glm::vec3(1, 0, 0)));
    glm::vec3 e2 = glm::cross(et, e1);
    float wc = std::min(std::max(w, 0.0f), 1.0f);
    glm::vec3 offset(0.0f);
    if (g.clump_strength > 0.0f)
      offset +=
          g.clump_strength * std::pow(wc, g.clump_shape) * (du * clumpDuv.x + dv * clumpDuv.y);
    if (g.curl_amplitude > 0.0f) {
      float ramp = smooth01(wc / 0.15f);
      float theta = 2.0f * kPi * g.curl_frequency * wc + phase;
      offset +=
          g.curl_amplitude * ramp * (std::cos(theta) * e1 + g.curl_helix * std::sin(theta) * e2);
    }
    if (frizz > 0.0f) {
      float xn = wc * g.frizz_frequency;
      offset +=
          frizz * wc * wc *
          (valueNoise(id, CLH_RNG_FRIZZ, xn) * e1 + valueNoise(id, CLH_RNG_FRIZZ + 16u, xn) * e2);
    }
    out.points.push_back(base + offset);
    out.w.push_back(w);
  }

  // 5. Tangents: central differences inside, reflected neighbours at the ends (Bhokare Eq. 5-6).
  const std::size_t n = out.points.size();
  out.tangents.assign(n, glm::vec3(0, 1, 0));
  for (std::size_t k = 1; k + 1 < n; ++k)
    out.tangents[k] = normalizeOr(out.points[k + 1] - out.points[k - 1], glm::vec3(0, 1, 0));
  glm::vec3 q0 = normalizeOr(out.points[1] - out.points[0], glm::vec3(0, 1, 0));
  glm::vec3 qn = normalizeOr(out.points[n - 1] - out.points[n - 2], glm::vec3(0, 1, 0));
  glm::vec3 t1 = n == 2 ? q0 : out.tangents[1];
  glm::vec3 tm = n == 2 ? qn : out.tangents[n - 2];
  out.tangents[0] = normalizeOr(2.0f * q0 * glm::dot(t1, q0) - t1, q0);
  out.tangents[n - 1] = normalizeOr(2.0f * qn * glm::dot(tm, qn) - tm, qn);
  return out;
}

}  // namespace clhair
