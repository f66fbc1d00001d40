// hair_mesh_io.cpp — reading and validating hair-mesh files (JSON, documented in
// docs/hair-mesh-format.md; hair_mesh_write.cpp writes them). Every rejection names the file, the
// JSON element and the values that matter; nothing is half-read into the renderer.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "clhair/error.h"
#include "clhair/gpu_types.h"
#include "clhair/hair_mesh.h"
#include "io/appearance_io.h"
#include "io/binary_file.h"
#include "io/json_util.h"

namespace clhair {

namespace {

using nlohmann::json;

constexpr std::int64_t kMaxStrands = 50'000'000;
constexpr int kMaxVertices = 4'000'000;

std::vector<float> floatArray(const JsonReader& r, const json& j, const std::string& key,
                              std::size_t expected) {
  if (!j.is_array()) r.fail(key, "must be an array of numbers");
  if (j.size() != expected)
    r.fail(key,
           "has " + std::to_string(j.size()) + " numbers, expected " + std::to_string(expected));
  std::vector<float> out(expected);
  for (std::size_t i = 0; i < expected; ++i) {
    const json& e = j[i];
    if (!e.is_number()) r.fail(key + "[" + std::to_string(i) + "]", "is not a number");
    double d = e.get<double>();
    if (!std::isfinite(d) || std::fabs(d) > 3.0e38)
      r.fail(key + "[" + std::to_string(i) + "]", "is not a finite number");
    out[i] = static_cast<float>(d);
  }
  return out;
}

// Per-layer arrays: `layers` arrays of `perLayer` numbers each, flattened layer-major.
std::vector<float> layeredArray(const JsonReader& r, const json& j, const std::string& key,
                                int layers, std::size_t perLayer) {
  if (!j.is_array()) r.fail(key, "must be an array with one array per layer");
  if (static_cast<int>(j.size()) != layers)
    r.fail(key, "has " + std::to_string(j.size()) + " layers, expected " + std::to_string(layers));
  std::vector<float> out;
  out.reserve(perLayer * layers);
  for (int l = 0; l < layers; ++l) {
    auto part = floatArray(r, j[l], key + "[" + std::to_string(l) + "]", perLayer);
    out.insert(out.end(), part.begin(), part.end());
  }
  return out;
}

std::vector<glm::vec3> toVec3(const std::vector<float>& f) {
  std::vector<glm::vec3> v(f.size() / 3);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = glm::vec3(f[3 * i], f[3 * i + 1], f[3 * i + 2]);
  return v;
}

void readStyle(const JsonReader& r, const json& j, StyleParams& s) {
  JsonReader o = r.object(j, "style");
  s.clumpStrength = o.number("clump_strength", s.clumpStrength, 0.0, 1.0);
  s.clumpFrequency = o.number("clump_frequency", s.clumpFrequency, 0.0, 10000.0);
  s.clumpShape = o.number("clump_shape", s.clumpShape, 0.01, 16.0);
  s.curlAmplitude = o.number("curl_amplitude", s.curlAmplitude, 0.0, 1e6);
  s.curlFrequency = o.number("curl_frequency", s.curlFrequency, 0.0, 1000.0);
  s.curlHelix = o.number("curl_helix", s.curlHelix, 0.0, 1.0);
  s.curlPhaseJitter = o.number("curl_phase_jitter", s.curlPhaseJitter, 0.0, 1.0);
  s.frizzAmplitude = o.number("frizz_amplitude", s.frizzAmplitude, 0.0, 1e6);
  s.frizzFrequency = o.number("frizz_frequency", s.frizzFrequency, 0.0, 1000.0);
  s.flyawayFraction = o.number("flyaway_fraction", s.flyawayFraction, 0.0, 1.0);
  s.flyawayAmplitude = o.number("flyaway_amplitude", s.flyawayAmplitude, 0.0, 1e6);
  s.lengthVariation = o.number("length_variation", s.lengthVariation, 0.0, 0.95);
  o.rejectUnknown({"clump_strength", "clump_frequency", "clump_shape", "curl_amplitude",
                   "curl_frequency", "curl_helix", "curl_phase_jitter", "frizz_amplitude",
                   "frizz_frequency", "flyaway_fraction", "flyaway_amplitude", "length_variation"});
}

void readLod(const JsonReader& r, const json& j, LodParams& lod) {
  JsonReader o = r.object(j, "lod");
  lod.enabled = o.boolean("enabled", lod.enabled);
  lod.lambda = o.number("lambda", lod.lambda, 1e-3, 1e3);
  lod.morphWindow = o.number("morph_window", lod.morphWindow, 0.0, 1.0);
  lod.strandsPerPixel = o.number("strands_per_pixel", lod.strandsPerPixel, 0.0, 1e4);
  o.rejectUnknown({"enabled", "lambda", "morph_window", "strands_per_pixel"});
}

}  // namespace

void readAppearance(const JsonReader& r, const json& j, AppearanceParams& a, bool strandFile) {
  JsonReader o = r.object(j, "appearance");
  a.rootColor = o.vec3("root_color", a.rootColor, 0.0, 1.0);
  a.tipColor = o.vec3("tip_color", a.tipColor, 0.0, 1.0);
  if (o.has("eumelanin") || o.has("pheomelanin"))
    a.useMelanin = true;
  else if (o.has("root_color") || o.has("tip_color"))
    a.useMelanin = false;
  a.useMelanin = o.boolean("use_melanin", a.useMelanin);
  auto pair = [&](const char* key, float* v) {
    if (!o.has(key)) return;
    const json& e = o.require(key);
    if (e.is_number()) {
      v[0] = v[1] = static_cast<float>(o.number(key, v[0], 0.0, 100.0));
      return;
    }
    if (!e.is_array() || e.size() != 2 || !e[0].is_number() || !e[1].is_number())
      o.fail(key, "must be a number or [root, tip]");
    for (int i = 0; i < 2; ++i) {
      double d = e[i].get<double>();
      if (!std::isfinite(d) || d < 0.0 || d > 100.0) o.fail(key, "values must lie in 0..100");
      v[i] = static_cast<float>(d);
    }
  };
  pair("eumelanin", a.eumelanin);
  pair("pheomelanin", a.pheomelanin);
  a.betaM = static_cast<float>(o.number("beta_m", a.betaM, 0.02, 1.0));
  a.betaN = static_cast<float>(o.number("beta_n", a.betaN, 0.02, 1.0));
  a.cuticleTiltDeg = static_cast<float>(o.number("cuticle_tilt", a.cuticleTiltDeg, -10.0, 10.0));
  a.ior = static_cast<float>(o.number("ior", a.ior, 1.01, 3.0));
  a.variation = static_cast<float>(o.number("variation", a.variation, 0.0, 0.9));
  a.strandWidth = o.number("strand_width", a.strandWidth, 1e-9, 1e3);
  a.minHitDiameterPx = o.number("min_hit_diameter_px", a.minHitDiameterPx, 0.0, 3.0);
  if (strandFile) {
    // the file's look per key: a key the scene gives wins over the file's
    a.transparency = static_cast<float>(o.number("transparency", a.transparency, 0.0, 0.99));
    if (o.has("root_color") || o.has("tip_color") || o.has("use_melanin") || o.has("eumelanin") ||
        o.has("pheomelanin"))
      a.useFileColor = false;
    if (o.has("strand_width")) a.useFileThickness = false;
    if (o.has("transparency")) a.useFileTransparency = false;
    // all three at once (true: the file's even over the keys above)
    if (o.has("use_file_color"))
      a.useFileColor = a.useFileThickness = a.useFileTransparency =
          o.boolean("use_file_color", true);
    o.rejectUnknown({"root_color", "tip_color", "use_melanin", "eumelanin", "pheomelanin", "beta_m",
                     "beta_n", "cuticle_tilt", "ior", "variation", "strand_width",
                     "min_hit_diameter_px", "use_file_color", "transparency"});
    return;
  }
  o.rejectUnknown({"root_color", "tip_color", "use_melanin", "eumelanin", "pheomelanin", "beta_m",
                   "beta_n", "cuticle_tilt", "ior", "variation", "strand_width",
                   "min_hit_diameter_px"});
}

std::vector<std::uint32_t> bundleStrandCounts(const HairMesh& m) {
  const std::size_t F = m.faces.size();
  std::vector<double> area(F, 0.0);
  double total = 0.0;
  for (std::size_t f = 0; f < F; ++f) {
    const auto& face = m.faces[f];
    bool inside = true;
    for (int c = 0; c < (face[3] < 0 ? 3 : 4); ++c)
      inside = inside && face[c] >= 0 && static_cast<std::size_t>(face[c]) < m.positions.size();
    if (!inside) continue;
    // in float, as the areas have always been computed (the same strands per bundle)
    const glm::vec3 &a = m.positions[face[0]], &b = m.positions[face[1]], &c = m.positions[face[2]];
    float s = 0.5f * glm::length(glm::cross(b - a, c - a));
    if (face[3] >= 0) s += 0.5f * glm::length(glm::cross(c - a, m.positions[face[3]] - a));
    area[f] = std::isfinite(s) ? s : 0.0;
    total += area[f];
  }
  std::vector<std::uint32_t> counts(F, 0);
  if (m.strandCount <= 0) return counts;
  const double strands = static_cast<double>(std::min<std::int64_t>(m.strandCount, kMaxStrands));
  const bool spread = total > 0.0 && std::isfinite(total);  // else one each, in face order
  std::vector<std::pair<double, std::size_t>> remainders;
  std::uint64_t assigned = 0;
  for (std::size_t f = 0; f < F; ++f) {
    const double exact = spread ? strands * area[f] / total : 0.0;
    counts[f] = static_cast<std::uint32_t>(std::floor(exact));
    assigned += counts[f];
    remainders.push_back({exact - std::floor(exact), f});
  }
  std::stable_sort(remainders.begin(), remainders.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t i = 0; assigned < static_cast<std::uint64_t>(strands) && i < F; ++i) {
    ++counts[remainders[i].second];
    ++assigned;
  }
  return counts;
}

void validateHairMesh(const HairMesh& m, const std::string& where) {
  auto fail = [&](const std::string& what) { throw Error(where + ": " + what); };
  if (m.layerCount < 2)
    fail("layer_count is " + std::to_string(m.layerCount) +
         ", a hair mesh needs at least 2 layers");
  if (m.layerCount > CLH_MAX_LAYERS)
    fail("layer_count is " + std::to_string(m.layerCount) + ", at most " +
         std::to_string(CLH_MAX_LAYERS) + " layers are supported");
  if (m.vertexCount < 3 || m.vertexCount > kMaxVertices)
    fail("vertex_count is " + std::to_string(m.vertexCount) + ", expected 3.." +
         std::to_string(kMaxVertices));
  const std::size_t n = static_cast<std::size_t>(m.layerCount) * m.vertexCount;
  if (m.positions.size() != n)
    fail("positions hold " + std::to_string(m.positions.size()) + " vertices, expected " +
         std::to_string(n));
  if (m.uv.size() != static_cast<std::size_t>(m.vertexCount))
    fail("uv holds " + std::to_string(m.uv.size()) + " entries, expected vertex_count " +
         std::to_string(m.vertexCount));
  if (!m.tangents.empty() && m.tangents.size() != n)
    fail("tangents must have one entry per layer vertex");
  if (!m.w.empty() && m.w.size() != n) fail("w must have one entry per layer vertex");
  if (!m.ao.empty() && m.ao.size() != n) fail("ao must have one entry per layer vertex");
  if (m.faces.empty()) fail("faces is empty: the scalp needs at least one face");
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3& p = m.positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      fail("layer " + std::to_string(i / m.vertexCount) + " vertex " +
           std::to_string(i % m.vertexCount) + " has a non-finite position");
    if (std::fabs(p.x) > kMaxCoordinate || std::fabs(p.y) > kMaxCoordinate ||
        std::fabs(p.z) > kMaxCoordinate)
      fail("layer " + std::to_string(i / m.vertexCount) + " vertex " +
           std::to_string(i % m.vertexCount) + " is at (" + showFloat(p.x) + ", " + showFloat(p.y) +
           ", " + showFloat(p.z) + "), beyond the +-1e6 coordinates allowed");
    if (!m.tangents.empty() && !(std::isfinite(m.tangents[i].x) && std::isfinite(m.tangents[i].y) &&
                                 std::isfinite(m.tangents[i].z)))
      fail("tangent of layer vertex " + std::to_string(i) + " is not finite");
    if (!m.w.empty() && !(std::isfinite(m.w[i]) && m.w[i] >= 0.0f && m.w[i] <= 1.0f))
      fail("w of layer vertex " + std::to_string(i) + " must be a finite number in [0, 1]");
    if (!m.ao.empty() && !(std::isfinite(m.ao[i]) && m.ao[i] >= 0.0f && m.ao[i] <= 1.0f))
      fail("ao of layer vertex " + std::to_string(i) + " must be a finite number in [0, 1]");
  }
  for (std::size_t v = 0; v < m.uv.size(); ++v)
    if (!std::isfinite(m.uv[v].x) || !std::isfinite(m.uv[v].y))
      fail("uv of vertex " + std::to_string(v) + " is not finite");
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    const auto& face = m.faces[f];
    int corners = face[3] < 0 ? 3 : 4;
    for (int c = 0; c < corners; ++c)
      if (face[c] < 0 || face[c] >= m.vertexCount)
        fail("faces[" + std::to_string(f) + "] vertex index " + std::to_string(face[c]) +
             " is out of range (vertex_count " + std::to_string(m.vertexCount) + ")");
    for (int a = 0; a < corners; ++a)
      for (int b = a + 1; b < corners; ++b)
        if (face[a] == face[b])
          fail("faces[" + std::to_string(f) + "] repeats vertex " + std::to_string(face[a]));
    glm::vec2 e1 = m.uv[face[1]] - m.uv[face[0]], e2 = m.uv[face[2]] - m.uv[face[0]];
    if (std::fabs(e1.x * e2.y - e2.x * e1.y) < 1e-12f)
      fail("faces[" + std::to_string(f) + "] has zero uv area: styling frames need a uv layout");
  }
  if (m.strandCount < 0 || m.strandCount > kMaxStrands)
    fail("strands is " + std::to_string(m.strandCount) + ", expected 0.." +
         std::to_string(kMaxStrands));
  const std::vector<std::uint32_t> counts = bundleStrandCounts(m);
  const auto most = std::max_element(counts.begin(), counts.end());
  if (most != counts.end() && *most > kMaxBundleStrands) {
    const std::size_t f = static_cast<std::size_t>(most - counts.begin());
    const double fit = static_cast<double>(m.strandCount) * kMaxBundleStrands / *most;
    fail("strands is " + std::to_string(m.strandCount) + ": bundle " + std::to_string(f) +
         " (faces[" + std::to_string(f) + "], the largest scalp face) gets " +
         std::to_string(*most) + " of them, and a bundle holds at most " +
         std::to_string(kMaxBundleStrands) +
         " (docs/hair-mesh-format.md); split that face or ask for at most " +
         std::to_string(static_cast<long long>(fit)) + " strands");
  }
  bool pow2plus1 = false;
  for (int k = 1; k <= 7; ++k) pow2plus1 |= m.controlPoints == (1 << k) + 1;
  if (!pow2plus1)
    fail("control_points is " + std::to_string(m.controlPoints) +
         ", expected 3, 5, 9, 17, 33, 65 or 129");
}

HairMesh loadHairMesh(const std::string& path) {
  json root = readJsonFile(path, "hair mesh");
  JsonReader r(path, root);
  HairMesh m;
  m.lod.enabled = true;  // a file draws with LOD unless it says otherwise
  // the keys the format requires (docs/hair-mesh-format.md) must be there, not defaulted
  for (const char* key :
       {"format", "version", "layer_count", "vertex_count", "faces", "uv", "layers"})
    r.require(key);
  std::string format = r.string("format", "");
  if (format != "clhair-hairmesh")
    r.fail("format", "is \"" + format + "\", expected \"clhair-hairmesh\"");
  int version = r.integer("version", 1, 1, 1000);
  if (version != kHairMeshFormatVersion)
    r.fail("version", std::to_string(version) + " is not supported (this build reads version 1)");
  m.name = r.string("name", std::filesystem::path(path).stem().string());
  m.layerCount = r.integer("layer_count", 0, 0, 1 << 20);
  if (m.layerCount < 2)
    r.fail("layer_count",
           "is " + std::to_string(m.layerCount) + ", a hair mesh needs at least 2 layers");
  if (m.layerCount > CLH_MAX_LAYERS)
    r.fail("layer_count", "is " + std::to_string(m.layerCount) + ", at most " +
                              std::to_string(CLH_MAX_LAYERS) + " layers are supported");
  m.vertexCount = r.integer("vertex_count", 0, 3, kMaxVertices);
  m.strandCount = r.integer64("strands", 0, 0, kMaxStrands);
  m.controlPoints = r.integer("control_points", m.controlPoints, 2, CLH_MAX_CONTROL_POINTS);
  m.seed = static_cast<std::uint32_t>(r.integer64("seed", 1, 0, 0xFFFFFFFFll));

  const json& faces = r.require("faces");
  if (!faces.is_array()) r.fail("faces", "must be an array of 3- or 4-index arrays");
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const json& face = faces[f];
    std::string key = "faces[" + std::to_string(f) + "]";
    if (!face.is_array() || (face.size() != 3 && face.size() != 4))
      r.fail(key, "must list 3 (triangle) or 4 (quad) vertex indices");
    std::array<int, 4> idx{-1, -1, -1, -1};
    for (std::size_t c = 0; c < face.size(); ++c) {
      if (!face[c].is_number_integer()) r.fail(key, "holds a non-integer index");
      long long v = face[c].get<long long>();
      if (v < 0 || v >= m.vertexCount)
        r.fail(key, "vertex index " + std::to_string(v) + " is out of range (vertex_count " +
                        std::to_string(m.vertexCount) + ")");
      idx[c] = static_cast<int>(v);
    }
    m.faces.push_back(idx);
  }
  auto uv = floatArray(r, r.require("uv"), "uv", 2 * static_cast<std::size_t>(m.vertexCount));
  m.uv.resize(m.vertexCount);
  for (int v = 0; v < m.vertexCount; ++v) m.uv[v] = glm::vec2(uv[2 * v], uv[2 * v + 1]);
  m.positions = toVec3(layeredArray(r, r.require("layers"), "layers", m.layerCount,
                                    3 * static_cast<std::size_t>(m.vertexCount)));
  if (root.contains("tangents"))
    m.tangents = toVec3(layeredArray(r, root["tangents"], "tangents", m.layerCount,
                                     3 * static_cast<std::size_t>(m.vertexCount)));
  if (root.contains("w")) m.w = layeredArray(r, root["w"], "w", m.layerCount, m.vertexCount);
  if (root.contains("ao")) m.ao = layeredArray(r, root["ao"], "ao", m.layerCount, m.vertexCount);
  if (root.contains("style")) readStyle(r, root["style"], m.style);
  if (root.contains("appearance")) readAppearance(r, root["appearance"], m.appearance);
  if (root.contains("lod")) readLod(r, root["lod"], m.lod);
  r.rejectUnknown({"format", "version", "name", "layer_count", "vertex_count", "strands",
                   "control_points", "seed", "faces", "uv", "layers", "tangents", "w", "ao",
                   "style", "appearance", "lod"});
  validateHairMesh(m, path);
  return m;
}

}  // namespace clhair
