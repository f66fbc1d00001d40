// presets.cpp — procedural hair meshes for `clhair groom --preset NAME`.
//
// Each preset builds a scalp (quads, plus triangles around the crown), grows one guide
// curve per root vertex with a small growth model (stiff near the root, bending under
// gravity, kept outside the head sphere and away from the face) and samples it at the
// layer count: layer l of every root vertex is its guide at arc length l / (L - 1).
// Neighbouring guides start close and bend alike, so each face sweeps a well-formed bundle.
// Styling and appearance parameters finish the look.
#include "groom/presets.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "clhair/error.h"
#include "clhair/gpu_types.h"

namespace clhair {

namespace {

constexpr float kPi = 3.14159265358979323846f;

struct GrowthModel {
  float headRadius = 0.095f;
  float length = 0.4f;
  float stiffness = 0.9f;  // how long the root direction persists (fraction kept per step)
  float gravity = 1.0f;    // pull toward -y per unit length
  float volume = 0.012f;   // how far the outer layers sit off the scalp
  bool avoidFace = true;
};

float hash01(std::uint32_t a, std::uint32_t b) { return gpu::clh_u01(gpu::clh_hash2(a, b)); }

// Grows a guide from `root` with initial direction `dir`; returns `layers` points evenly
// spaced in arc length.
std::vector<glm::vec3> growGuide(const GrowthModel& g, glm::vec3 root, glm::vec3 dir, float length,
                                 int layers) {
  const int steps = 160;
  const float ds = length / steps;
  std::vector<glm::vec3> path{root};
  glm::vec3 p = root, d = glm::normalize(dir);
  for (int i = 1; i <= steps; ++i) {
    float s = static_cast<float>(i) / steps;
    // gravity grows with distance from the root: stiff roots, then free fall
    glm::vec3 pull(0.0f, -g.gravity * (0.3f + 2.5f * s), 0.0f);
    d = glm::normalize(d * g.stiffness + (1.0f - g.stiffness) * glm::normalize(d + pull * 0.6f));
    p += d * ds;
    // keep outside the head: hair lies on the scalp and builds volume outward
    float shell = g.headRadius + g.volume * std::min(1.0f, s * 4.0f);
    float r = glm::length(p);
    if (r < shell) {
      glm::vec3 n = p / std::max(r, 1e-6f);
      p = n * shell;
      d = glm::normalize(d - std::min(0.0f, glm::dot(d, n)) * n);
    }
    // keep the face clear: strands in front of the face move sideways
    if (g.avoidFace && p.z > 0.0f && p.y < 0.03f && p.y > -0.17f) {
      const float half = 0.085f;
      if (std::fabs(p.x) < half) {
        float side = p.x >= 0.0f ? 1.0f : -1.0f;
        p.x = side * half;
        d.x = side * std::fabs(d.x) + side * 0.05f;
        d = glm::normalize(d);
      }
    }
    path.push_back(p);
  }
  // resample by arc length
  std::vector<float> acc(path.size(), 0.0f);
  for (std::size_t i = 1; i < path.size(); ++i)
    acc[i] = acc[i - 1] + glm::length(path[i] - path[i - 1]);
  std::vector<glm::vec3> out;
  for (int l = 0; l < layers; ++l) {
    float target = acc.back() * static_cast<float>(l) / static_cast<float>(layers - 1);
    auto it = std::lower_bound(acc.begin(), acc.end(), target);
    std::size_t i =
        std::min<std::size_t>(std::max<std::ptrdiff_t>(it - acc.begin(), 1), path.size() - 1);
    float span = acc[i] - acc[i - 1];
    float t = span > 0.0f ? (target - acc[i - 1]) / span : 0.0f;
    out.push_back(path[i - 1] + (path[i] - path[i - 1]) * std::min(std::max(t, 0.0f), 1.0f));
  }
  return out;
}

// Head scalp in azimuthal layout around the crown: a pole vertex, `rings` rings of
// `sectors` vertices, and a duplicated first column (the parting) so the two sides of the
// part are separate bundles. The hairline sits lower at the back than at the forehead.
struct Scalp {
  std::vector<glm::vec3> roots;
  std::vector<glm::vec2> uv;
  std::vector<float> side;  // +1 / -1: which way the part sends the vertex
  std::vector<float> phi;
  std::vector<std::array<int, 4>> faces;
};

Scalp headScalp(float radius, int rings, int sectors, float frontDeg, float backDeg) {
  Scalp s;
  s.roots.push_back(glm::vec3(0.0f, radius, 0.0f));
  s.uv.push_back(glm::vec2(0.5f, 0.5f));
  s.side.push_back(0.0f);
  s.phi.push_back(kPi);
  const float thetaRef = glm::radians(125.0f);
  for (int i = 1; i <= rings; ++i) {
    for (int j = 0; j <= sectors; ++j) {  // column `sectors` duplicates column 0 (the part)
      float phi = 2.0f * kPi * static_cast<float>(j) / static_cast<float>(sectors);
      float thetaMax =
          glm::radians(0.5f * (frontDeg + backDeg) - 0.5f * (backDeg - frontDeg) * std::cos(phi));
      float theta = thetaMax * static_cast<float>(i) / static_cast<float>(rings);
      s.roots.push_back(radius * glm::vec3(std::sin(theta) * std::sin(phi), std::cos(theta),
                                           std::sin(theta) * std::cos(phi)));
      float rr = 0.5f * theta / thetaRef;
      s.uv.push_back(glm::vec2(0.5f + rr * std::sin(phi), 0.5f + rr * std::cos(phi)));
      s.side.push_back(j == sectors ? -1.0f
                                    : (j == 0 ? 1.0f : (std::sin(phi) >= 0.0f ? 1.0f : -1.0f)));
      s.phi.push_back(j == sectors ? 2.0f * kPi - 1e-4f : std::max(phi, 1e-4f));
    }
  }
  auto at = [&](int ring, int col) { return 1 + (ring - 1) * (sectors + 1) + col; };
  for (int j = 0; j < sectors; ++j) s.faces.push_back({0, at(1, j), at(1, j + 1), -1});
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < sectors; ++j)
      s.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
  return s;
}

HairMesh headGroom(const std::string& name, const GrowthModel& g, int layers, int rings,
                   int sectors, float frontDeg, float backDeg, float lengthFront, float lengthBack,
                   float sideSweep, std::uint32_t seed) {
  Scalp s = headScalp(g.headRadius, rings, sectors, frontDeg, backDeg);
  HairMesh m;
  m.name = name;
  m.layerCount = layers;
  m.vertexCount = static_cast<int>(s.roots.size());
  m.faces = s.faces;
  m.uv = s.uv;
  m.positions.resize(static_cast<std::size_t>(layers) * m.vertexCount);
  m.seed = seed;
  for (int v = 0; v < m.vertexCount; ++v) {
    glm::vec3 n = glm::normalize(s.roots[v]);
    float phi = s.phi[v];
    // flow over the scalp: away from the part toward the sides near the face, down the back
    float away = std::fabs(std::cos(0.5f * phi)) * s.side[v];
    float back = 0.35f + 0.4f * 0.5f * (1.0f - std::cos(phi));
    glm::vec3 flow = glm::vec3(sideSweep * away, -0.5f, -back);
    if (v == 0) flow = glm::vec3(0.0f, -0.3f, -1.0f);  // the crown sends hair backwards
    flow -= glm::dot(flow, n) * n;
    glm::vec3 dir = glm::normalize(0.35f * n + glm::normalize(flow));
    float front = 0.5f * (1.0f + std::cos(phi));
    float length = lengthBack + (lengthFront - lengthBack) * front;
    length *= 1.0f + 0.04f * (hash01(seed, static_cast<std::uint32_t>(v)) - 0.5f);
    std::vector<glm::vec3> guide = growGuide(g, s.roots[v], dir, length, layers);
    for (int l = 0; l < layers; ++l)
      m.positions[static_cast<std::size_t>(l) * m.vertexCount + v] = guide[l];
  }
  return m;
}

HairMesh longWavy() {
  GrowthModel g;
  g.length = 0.42f;
  g.stiffness = 0.93f;
  g.gravity = 1.2f;
  g.volume = 0.014f;
  HairMesh m = headGroom("long_wavy", g, 12, 10, 36, 68.0f, 112.0f, 0.34f, 0.44f, 1.0f, 7u);
  m.strandCount = 127000;
  m.controlPoints = 65;
  m.style.clumpStrength = 0.45f;
  m.style.clumpFrequency = 14.0f;
  m.style.clumpShape = 1.2f;
  m.style.curlAmplitude = 0.009f;
  m.style.curlFrequency = 3.5f;
  m.style.curlHelix = 0.35f;
  m.style.curlPhaseJitter = 0.12f;
  m.style.frizzAmplitude = 0.0025f;
  m.style.frizzFrequency = 7.0f;
  m.style.flyawayFraction = 0.02f;
  m.style.flyawayAmplitude = 0.02f;
  m.style.lengthVariation = 0.12f;
  m.appearance.rootColor = glm::vec3(0.045f, 0.026f, 0.014f);
  m.appearance.tipColor = glm::vec3(0.20f, 0.12f, 0.06f);
  m.appearance.eumelanin[0] = 1.6f;  // brown, lighter toward the tips
  m.appearance.eumelanin[1] = 0.9f;
  m.appearance.pheomelanin[0] = m.appearance.pheomelanin[1] = 0.2f;
  m.appearance.betaM = 0.25f;
  m.appearance.strandWidth = 7.0e-5f;
  m.lod.lambda = 3.0f;
  return m;
}

HairMesh curlyMedium() {
  GrowthModel g;
  g.stiffness = 0.95f;
  g.gravity = 1.0f;
  g.volume = 0.028f;
  HairMesh m = headGroom("curly_medium", g, 9, 9, 32, 70.0f, 108.0f, 0.16f, 0.2f, 0.45f, 11u);
  m.strandCount = 100000;
  m.controlPoints = 65;
  m.style.clumpStrength = 0.8f;
  m.style.clumpFrequency = 26.0f;
  m.style.clumpShape = 0.6f;
  m.style.curlAmplitude = 0.009f;
  m.style.curlFrequency = 6.0f;
  m.style.curlHelix = 1.0f;
  m.style.curlPhaseJitter = 0.05f;
  m.style.frizzAmplitude = 0.003f;
  m.style.frizzFrequency = 12.0f;
  m.style.flyawayFraction = 0.03f;
  m.style.flyawayAmplitude = 0.012f;
  m.style.lengthVariation = 0.2f;
  m.appearance.rootColor = glm::vec3(0.035f, 0.012f, 0.006f);
  m.appearance.tipColor = glm::vec3(0.17f, 0.055f, 0.022f);
  m.appearance.eumelanin[0] = 2.2f;  // auburn: pheomelanin reddens
  m.appearance.eumelanin[1] = 1.4f;
  m.appearance.pheomelanin[0] = 1.4f;
  m.appearance.pheomelanin[1] = 1.1f;
  m.appearance.betaM = 0.35f;
  m.appearance.betaN = 0.4f;
  m.appearance.strandWidth = 8.0e-5f;
  m.lod.lambda = 5.5f;
  return m;
}

// Short fur on a sphere: a cube-sphere scalp (6 faces of n x n quads, each face its own
// uv cell of a 3 x 2 atlas), three layers along the normal combed slightly downward.
HairMesh furSphere() {
  const int n = 8, layers = 3;
  const float radius = 0.1f, length = 0.018f;
  HairMesh m;
  m.name = "fur_sphere";
  m.layerCount = layers;
  const glm::vec3 axes[6][3] = {
      {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
      {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}}};
  std::vector<glm::vec3> roots;
  for (int f = 0; f < 6; ++f) {
    const glm::vec3 &normal = axes[f][0], &ua = axes[f][1], &va = axes[f][2];
    int base = static_cast<int>(roots.size());
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        float a = 2.0f * i / n - 1.0f, b = 2.0f * j / n - 1.0f;
        // equal-angle cube map for evenly sized faces
        glm::vec3 c = normal + ua * std::tan(a * kPi / 4.0f) + va * std::tan(b * kPi / 4.0f);
        roots.push_back(radius * glm::normalize(c));
        float cu = static_cast<float>(f % 3) / 3.0f, cv = static_cast<float>(f / 3) / 2.0f;
        m.uv.push_back(glm::vec2(cu + (0.02f + 0.29f * i / n), cv + (0.03f + 0.44f * j / n)));
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        int a = base + j * (n + 1) + i;
        m.faces.push_back({a, a + 1, a + n + 2, a + n + 1});
      }
  }
  m.vertexCount = static_cast<int>(roots.size());
  m.positions.resize(static_cast<std::size_t>(layers) * m.vertexCount);
  for (int v = 0; v < m.vertexCount; ++v) {
    glm::vec3 nrm = glm::normalize(roots[v]);
    glm::vec3 comb = glm::vec3(0.0f, -1.0f, 0.0f) - nrm.y * nrm;  // down along the surface
    float combLen = glm::length(comb);
    comb = combLen > 1e-4f ? comb / combLen : glm::vec3(0.0f);
    glm::vec3 dir1 = glm::normalize(nrm + 0.35f * comb);
    glm::vec3 dir2 = glm::normalize(nrm + 0.9f * comb);
    glm::vec3 p1 = roots[v] + dir1 * (0.5f * length);
    glm::vec3 p2 = p1 + dir2 * (0.5f * length);
    m.positions[v] = roots[v];
    m.positions[static_cast<std::size_t>(m.vertexCount) + v] = p1;
    m.positions[static_cast<std::size_t>(2 * m.vertexCount) + v] = p2;
  }
  m.strandCount = 160000;
  m.controlPoints = 9;
  m.seed = 23;
  m.style.clumpStrength = 0.25f;
  m.style.clumpFrequency = 40.0f;
  m.style.clumpShape = 2.0f;
  m.style.frizzAmplitude = 0.0015f;
  m.style.frizzFrequency = 3.0f;
  m.style.lengthVariation = 0.35f;
  m.style.flyawayFraction = 0.01f;
  m.style.flyawayAmplitude = 0.004f;
  m.appearance.rootColor = glm::vec3(0.10f, 0.07f, 0.045f);
  m.appearance.tipColor = glm::vec3(0.62f, 0.46f, 0.30f);
  m.appearance.eumelanin[0] = 1.2f;  // dark underfur, light tips
  m.appearance.eumelanin[1] = 0.15f;
  m.appearance.pheomelanin[0] = 0.5f;
  m.appearance.pheomelanin[1] = 0.25f;
  m.appearance.betaM = 0.4f;
  m.appearance.strandWidth = 4.0e-5f;
  m.lod.lambda = 2.0f;
  return m;
}

// A few bundles over a small curved patch (two quads and a triangle), for fast tests.
HairMesh tinyPatch() {
  HairMesh m;
  m.name = "tiny";
  m.layerCount = 4;
  const glm::vec3 roots[7] = {{-0.02f, 0, -0.01f}, {0, 0.002f, -0.01f}, {0.02f, 0, -0.01f},
                              {-0.02f, 0, 0.01f},  {0, 0.002f, 0.01f},  {0.02f, 0, 0.01f},
                              {0.0f, 0.0f, 0.03f}};
  m.vertexCount = 7;
  m.faces = {{0, 3, 4, 1}, {1, 4, 5, 2}, {3, 6, 4, -1}};
  for (const glm::vec3& r : roots)
    m.uv.push_back(glm::vec2(0.5f + 10.0f * r.x, 0.5f + 10.0f * r.z));
  m.positions.resize(static_cast<std::size_t>(m.layerCount) * m.vertexCount);
  for (int v = 0; v < m.vertexCount; ++v)
    for (int l = 0; l < m.layerCount; ++l) {
      float s = static_cast<float>(l) / (m.layerCount - 1);
      glm::vec3 p = roots[v] + glm::vec3(0.004f * s * roots[v].x * 40.0f, 0.05f * s, 0.02f * s * s);
      m.positions[static_cast<std::size_t>(l) * m.vertexCount + v] = p;
    }
  m.strandCount = 61;
  m.controlPoints = 17;
  m.seed = 5;
  m.style.clumpStrength = 0.5f;
  m.style.clumpFrequency = 12.0f;
  m.style.curlAmplitude = 0.002f;
  m.style.curlFrequency = 2.0f;
  m.style.frizzAmplitude = 0.001f;
  m.style.flyawayFraction = 0.1f;
  m.style.flyawayAmplitude = 0.003f;
  m.style.lengthVariation = 0.2f;
  m.appearance.eumelanin[0] = 0.6f;
  m.appearance.eumelanin[1] = 0.3f;
  m.appearance.rootColor = glm::vec3(0.3f, 0.2f, 0.1f);
  m.appearance.tipColor = glm::vec3(0.8f, 0.6f, 0.3f);
  return m;
}

}  // namespace

std::vector<std::string> groomPresetNames() {
  return {"long_wavy", "curly_medium", "fur_sphere", "tiny"};
}

HairMesh makeGroomPreset(const std::string& name) {
  HairMesh m;
  if (name == "long_wavy")
    m = longWavy();
  else if (name == "curly_medium")
    m = curlyMedium();
  else if (name == "fur_sphere")
    m = furSphere();
  else if (name == "tiny")
    m = tinyPatch();
  else {
    std::string list;
    for (const std::string& n : groomPresetNames()) list += (list.empty() ? "" : ", ") + n;
    throw Error("unknown groom preset \"" + name + "\"; available: " + list);
  }
  validateHairMesh(m, "preset " + name);
  return m;
}

}  // namespace clhair
