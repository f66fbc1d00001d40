// scene_grooms.cpp — a scene's "grooms": each entry names a hair mesh ("file") or a strand
// file ("strands_file", scene_strand_groom.cpp). A hair-mesh entry may override strand
// count, control points and LOD, cap its strands, move its cage ("cage_animation", "wind")
// and look up baked visibility; each file is read once per scene, and entries with the same
// overrides share one device form.
#include <map>
#include <memory>
#include <string>
#include <system_error>

#include <glm/geometric.hpp>

#include "clhair/error.h"
#include "clhair/gpu_types.h"
#include "io/scene_sections.h"

namespace clhair::scene_io {

namespace {

using nlohmann::json;

// A hair-mesh groom entry's "cage_animation" (a cage-animation file whose vertex count must
// be the mesh's layer vertices, read once per entry) and "wind".
void readCageMotion(const JsonReader& o, const std::filesystem::path& base, std::uint64_t maxBytes,
                    GroomInstance& g) {
  if (o.has("cage_animation")) {
    JsonReader c = o.object(o.require("cage_animation"), "cage_animation");
    const std::string file = c.string("file", "");
    if (file.empty()) c.fail("file", "is missing: name a cage-animation file (.cage)");
    std::filesystem::path p =
        std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : base / file;
    const std::string key = p.lexically_normal().string();
    std::error_code ec;
    if (!std::filesystem::exists(p, ec)) c.fail("file", "\"" + key + "\" does not exist");
    auto cage = std::make_shared<CageAnimation>();
    try {
      *cage = loadCageAnimation(key, maxBytes);
    } catch (const Error& e) {
      c.fail("file", e.what());
    }
    const HairMesh& m = *g.mesh;
    const std::uint64_t expected = static_cast<std::uint64_t>(m.layerCount) * m.vertexCount;
    if (cage->vertices != expected)
      c.fail("file", key + " holds " + std::to_string(cage->vertices) +
                         " vertices per frame, but the groom's cage has " +
                         std::to_string(expected) + " (" + std::to_string(m.layerCount) +
                         " layers of " + std::to_string(m.vertexCount) + " vertices)");
    g.cageStartFrame = c.number("start_frame", 1.0, -1e7, 1e7);
    c.rejectUnknown({"file", "start_frame"});
    g.cage = std::move(cage);
  }
  if (o.has("wind")) {
    JsonReader w = o.object(o.require("wind"), "wind");
    WindParams& wind = g.wind;
    wind.strength = static_cast<float>(w.number("strength", wind.strength, 0.0, kBig));
    const glm::vec3 d = w.vec3("direction", wind.direction, -kBig, kBig);
    if (glm::length(d) < 1e-6f) w.fail("direction", "must not be zero");
    wind.direction = glm::normalize(d);
    wind.frequency = static_cast<float>(w.number("frequency", wind.frequency, 0.0, 1000.0));
    wind.wavelength = static_cast<float>(w.number("wavelength", wind.wavelength, 1e-6, kBig));
    w.rejectUnknown({"strength", "direction", "frequency", "wavelength"});
  }
}

}  // namespace

// A groom entry's "visibility": {"file": a baked visibility file, "absorption"}, read once
// per file and checked against the groom it was baked for (`strands` at full detail).
void readVisibilityEntry(const JsonReader& o, const std::filesystem::path& base,
                         std::uint64_t strands, bool fileColor,
                         std::map<std::string, std::shared_ptr<const VisibilityBake>>& loaded,
                         GroomInstance& g) {
  if (!o.has("visibility")) return;
  JsonReader v = o.object(o.require("visibility"), "visibility");
  const std::string file = v.string("file", "");
  if (file.empty()) v.fail("file", "is missing: name a baked visibility file (.clhvis)");
  if (fileColor)
    v.fail("file",
           "a groom drawn with its file colours keeps no styling uv in the G-buffer, so it "
           "cannot look up baked visibility");
  std::filesystem::path p =
      std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : base / file;
  const std::string key = p.lexically_normal().string();
  auto it = loaded.find(key);
  if (it == loaded.end()) {
    try {
      it = loaded.emplace(key, std::make_shared<const VisibilityBake>(readVisibility(key))).first;
    } catch (const Error& e) {
      v.fail("file", e.what());
    }
  }
  if (it->second->strands != strands)
    v.fail("file", key + " was baked for a groom of " + std::to_string(it->second->strands) +
                       " strands, this groom has " + std::to_string(strands) +
                       " (bake it again with clhair bake-visibility)");
  g.visibility = it->second;
  g.visibilityAbsorption = static_cast<float>(v.number("absorption", 0.5, 0.0, 100.0));
  v.rejectUnknown({"file", "absorption"});
}

float readGrooms(const JsonReader& r, const std::string& path, const std::filesystem::path& base,
                 std::uint64_t maxStrandBytes, Scene& s, const MemoryGrooms* memory) {
  std::map<std::string, std::shared_ptr<const HairMesh>> loaded, loadedVariants;
  std::map<std::string, std::shared_ptr<const StrandGroom>> loadedStrands, strandVariants;
  if (memory) loadedStrands.insert(memory->begin(), memory->end());
  const auto sceneCap = static_cast<std::uint64_t>(r.integer64("max_strands", 0, 0, 50'000'000));
  std::map<std::string, std::shared_ptr<const VisibilityBake>> loadedVisibility;
  // one "scale": "auto" factor for every groom (and mesh) that asks for it
  const float autoScale =
      sceneAutoScale(r, base, maxStrandBytes, loadedStrands, s.warnings, s.notes);
  if (!r.has("grooms")) return autoScale;
  const json& a = r.require("grooms");
  if (!a.is_array()) r.fail("grooms", "must be an array");
  for (std::size_t i = 0; i < a.size(); ++i) {
    JsonReader o = r.object(a[i], "grooms[" + std::to_string(i) + "]");
    if (o.has("file") == o.has("strands_file"))
      o.fail("file",
             "give exactly one of \"file\" (a hair mesh) and \"strands_file\" (a .hair, .data or "
             ".tfx strand file)");
    if (o.has("strands_file")) {
      s.grooms.push_back(readStrandGroom(o, base, s.filter, maxStrandBytes, loadedStrands,
                                         strandVariants, loadedVisibility, sceneCap, s.warnings,
                                         autoScale));
      continue;
    }
    std::string file = o.string("file", "");
    if (file.empty()) o.fail("file", "is missing: name the groom's hair-mesh file");
    std::filesystem::path p =
        std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : base / file;
    std::string key = p.lexically_normal().string();
    std::error_code ec;
    const bool found = std::filesystem::exists(p, ec);
    if (ec) o.fail("file", "\"" + key + "\" cannot be checked (" + ec.message() + ")");
    if (!found) o.fail("file", "\"" + key + "\" does not exist");
    std::shared_ptr<const HairMesh> mesh;
    if (loaded.count(key)) {
      mesh = loaded[key];
    } else {
      mesh = std::make_shared<const HairMesh>(loadHairMesh(key));
      loaded[key] = mesh;
    }
    GroomInstance g;
    g.name = o.string("name", mesh->name);
    if (o.has("transform"))
      g.transform = readTransform(o, o.require("transform"), &g.transformKeys);
    if (o.has("filter")) {
      g.hasFilter = true;
      g.filter = readFilter(o, o.require("filter"), s.filter);
    }
    const auto cap = static_cast<std::uint64_t>(
        o.integer64("max_strands", static_cast<long long>(sceneCap), 0, 50'000'000));
    const auto dumpOf = [&](const char* k) { return o.has(k) ? o.require(k).dump() : ""; };
    const std::string variant = key + "\n" + dumpOf("strands") + "\n" + dumpOf("lod") + "\n" +
                                dumpOf("control_points") + "\n" + std::to_string(cap);
    if (const auto same = loadedVariants.find(variant); same != loadedVariants.end()) {
      mesh = same->second;  // the same overrides and cap: one device form for all entries
    } else if (o.has("strands") || o.has("lod") || o.has("control_points") ||
               (cap > 0 && static_cast<std::uint64_t>(mesh->strandCount) > cap)) {
      HairMesh copy = *mesh;
      copy.strandCount = o.integer64("strands", copy.strandCount, 0, 50'000'000);
      copy.controlPoints =
          o.integer("control_points", copy.controlPoints, 2, CLH_MAX_CONTROL_POINTS);
      if (o.has("lod")) {
        JsonReader l = o.object(o.require("lod"), "lod");
        copy.lod.enabled = l.boolean("enabled", copy.lod.enabled);
        copy.lod.lambda = static_cast<float>(l.number("lambda", copy.lod.lambda, 1e-3, 1e3));
        copy.lod.morphWindow =
            static_cast<float>(l.number("morph_window", copy.lod.morphWindow, 0.0, 1.0));
        copy.lod.strandsPerPixel =
            static_cast<float>(l.number("strands_per_pixel", copy.lod.strandsPerPixel, 0.0, 1e4));
        l.rejectUnknown({"enabled", "lambda", "morph_window", "strands_per_pixel"});
      }
      capStrands(copy, cap);
      validateHairMesh(copy, path + ": grooms[" + std::to_string(i) + "]");
      mesh = std::make_shared<const HairMesh>(std::move(copy));
    }
    loadedVariants[variant] = mesh;
    g.mesh = mesh;
    readCageMotion(o, base, maxStrandBytes, g);
    // an animated entry deforms its own copy: entries naming one file share a device form
    if (g.cage || g.wind.strength > 0.0f) g.mesh = std::make_shared<const HairMesh>(*g.mesh);
    readVisibilityEntry(o, base, static_cast<std::uint64_t>(g.mesh->strandCount), false,
                        loadedVisibility, g);
    o.rejectUnknown({"file", "name", "transform", "strands", "lod", "control_points", "filter",
                     "cage_animation", "wind", "max_strands", "visibility"});
    s.grooms.push_back(g);
  }
  return autoScale;
}

}  // namespace clhair::scene_io
