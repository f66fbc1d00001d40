// hair_mesh_write.cpp — writing hair-mesh files (saveHairMesh, clhair/hair_mesh.h; the
// format in docs/hair-mesh-format.md): validated first, numbers to 6 significant digits,
// one top-level key per line, written atomically.
#include <cstdio>
#include <cstdlib>
#include <string>

#include <nlohmann/json.hpp>

#include "clhair/hair_mesh.h"
#include "io/json_util.h"

namespace clhair {

namespace {

using nlohmann::json;

// Rounds to 6 significant digits so files stay small and diff-friendly.
double tidy(float v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", static_cast<double>(v));
  return std::strtod(buf, nullptr);
}

json vec3Json(const glm::vec3& v) { return json::array({tidy(v.x), tidy(v.y), tidy(v.z)}); }

// One top-level key per line; per-layer arrays one layer per line; everything else compact.
std::string layout(const json& j) {
  std::string out = "{\n";
  std::size_t i = 0;
  for (auto it = j.begin(); it != j.end(); ++it, ++i) {
    out += "  " + json(it.key()).dump() + ": ";
    const json& v = it.value();
    bool perLine = v.is_array() && !v.empty() && v[0].is_array() && v[0].size() > 4;
    if (perLine) {
      out += "[\n";
      for (std::size_t k = 0; k < v.size(); ++k)
        out += "    " + v[k].dump() + (k + 1 < v.size() ? ",\n" : "\n");
      out += "  ]";
    } else {
      out += v.dump();
    }
    out += i + 1 < j.size() ? ",\n" : "\n";
  }
  return out + "}\n";
}

}  // namespace

void saveHairMesh(const HairMesh& m, const std::string& path) {
  validateHairMesh(m, "saving " + path);
  json j;
  j["format"] = "clhair-hairmesh";
  j["version"] = kHairMeshFormatVersion;
  j["name"] = m.name;
  j["layer_count"] = m.layerCount;
  j["vertex_count"] = m.vertexCount;
  j["strands"] = m.strandCount;
  j["control_points"] = m.controlPoints;
  j["seed"] = m.seed;
  json faces = json::array();
  for (const auto& f : m.faces) {
    if (f[3] < 0)
      faces.push_back({f[0], f[1], f[2]});
    else
      faces.push_back({f[0], f[1], f[2], f[3]});
  }
  j["faces"] = faces;
  json uv = json::array();
  for (const auto& t : m.uv) {
    uv.push_back(tidy(t.x));
    uv.push_back(tidy(t.y));
  }
  j["uv"] = uv;
  auto layered3 = [&](const std::vector<glm::vec3>& src) {
    json layers = json::array();
    for (int l = 0; l < m.layerCount; ++l) {
      json a = json::array();
      for (int v = 0; v < m.vertexCount; ++v) {
        const glm::vec3& p = src[static_cast<std::size_t>(l) * m.vertexCount + v];
        a.push_back(tidy(p.x));
        a.push_back(tidy(p.y));
        a.push_back(tidy(p.z));
      }
      layers.push_back(a);
    }
    return layers;
  };
  auto layered1 = [&](const std::vector<float>& src) {
    json layers = json::array();
    for (int l = 0; l < m.layerCount; ++l) {
      json a = json::array();
      for (int v = 0; v < m.vertexCount; ++v)
        a.push_back(tidy(src[static_cast<std::size_t>(l) * m.vertexCount + v]));
      layers.push_back(a);
    }
    return layers;
  };
  j["layers"] = layered3(m.positions);
  if (!m.tangents.empty()) j["tangents"] = layered3(m.tangents);
  if (!m.w.empty()) j["w"] = layered1(m.w);
  if (!m.ao.empty()) j["ao"] = layered1(m.ao);
  const StyleParams& s = m.style;
  j["style"] = {{"clump_strength", tidy(s.clumpStrength)},
                {"clump_frequency", tidy(s.clumpFrequency)},
                {"clump_shape", tidy(s.clumpShape)},
                {"curl_amplitude", tidy(s.curlAmplitude)},
                {"curl_frequency", tidy(s.curlFrequency)},
                {"curl_helix", tidy(s.curlHelix)},
                {"curl_phase_jitter", tidy(s.curlPhaseJitter)},
                {"frizz_amplitude", tidy(s.frizzAmplitude)},
                {"frizz_frequency", tidy(s.frizzFrequency)},
                {"flyaway_fraction", tidy(s.flyawayFraction)},
                {"flyaway_amplitude", tidy(s.flyawayAmplitude)},
                {"length_variation", tidy(s.lengthVariation)}};
  const AppearanceParams& a = m.appearance;
  j["appearance"] = {{"use_melanin", a.useMelanin},
                     {"eumelanin", json::array({tidy(a.eumelanin[0]), tidy(a.eumelanin[1])})},
                     {"pheomelanin", json::array({tidy(a.pheomelanin[0]), tidy(a.pheomelanin[1])})},
                     {"root_color", vec3Json(a.rootColor)},
                     {"tip_color", vec3Json(a.tipColor)},
                     {"beta_m", tidy(a.betaM)},
                     {"beta_n", tidy(a.betaN)},
                     {"cuticle_tilt", tidy(a.cuticleTiltDeg)},
                     {"ior", tidy(a.ior)},
                     {"variation", tidy(a.variation)},
                     {"strand_width", tidy(a.strandWidth)},
                     {"min_hit_diameter_px", tidy(a.minHitDiameterPx)}};
  j["lod"] = {{"enabled", m.lod.enabled},
              {"lambda", tidy(m.lod.lambda)},
              {"morph_window", tidy(m.lod.morphWindow)},
              {"strands_per_pixel", tidy(m.lod.strandsPerPixel)}};
  writeTextAtomically(path, layout(j));
}

}  // namespace clhair
