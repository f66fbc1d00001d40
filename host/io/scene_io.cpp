// scene_io.cpp — the JSON scene format (docs/scene-format.md): loadScene reads a scene file
// section by section (io/scene_sections.h) in a fixed order, so that the first error a scene
// holds is the one reported, and rejects keys it does not know.
//
// A groom entry names a hair mesh ("file") or a strand file ("strands_file": cyHair .hair
// or USC-HairSalon .data, read with a byte limit before anything is allocated); each file
// is read once per scene however many entries use it. A mesh entry names an OBJ file (a
// head), read and checked the same way: once per file, against the device's largest
// allocation, every error one line naming the scene and the file as the entry wrote it.
// Meshes are read after the grooms (a mesh's "scale": "auto" takes the grooms' factor),
// and the camera after both (a preset frames them).
#include <cstdint>
#include <filesystem>
#include <string>

#include "clhair/error.h"
#include "clhair/scene.h"
#include "clhair/scene_json.h"
#include "io/json_util.h"
#include "io/scene_sections.h"

namespace clhair {

using nlohmann::json;
using namespace scene_io;

namespace {

// Every file a scene names ("file", "strands_file", "background_image", at any depth), as the
// readers resolve it: relative to the scene's folder. Frame patterns ("bob.####.hair") stay
// patterns.
void collectFiles(const json& j, const std::filesystem::path& base, std::vector<std::string>& out) {
  if (j.is_array()) {
    for (const json& e : j) collectFiles(e, base, out);
    return;
  }
  if (!j.is_object()) return;
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string& k = it.key();
    if ((k == "file" || k == "strands_file" || k == "background_image") && it.value().is_string() &&
        !it.value().get<std::string>().empty()) {
      std::filesystem::path p = it.value().get<std::string>();
      if (!p.is_absolute()) p = base / p;
      out.push_back(p.lexically_normal().string());
    } else {
      collectFiles(it.value(), base, out);
    }
  }
}

Scene readScene(const json& root, const std::string& path, const std::filesystem::path& base,
                std::uint64_t maxStrandBytes, const MemoryGrooms* memory) {
  JsonReader r(path, root);
  Scene s;

  readResolution(r, s);
  readBackground(r, base, s);

  readLights(r, s);
  readSpheres(r, s);
  readPlanes(r, s);

  readShadows(r, s);
  if (r.has("filter")) s.filter = readFilter(r, r.require("filter"), s.filter);
  readEnvironment(r, base, s);

  if (r.has("segment_budget"))
    s.segmentBudget = static_cast<std::uint64_t>(
        r.integer64("segment_budget", 0, 0, static_cast<long long>(kMaxSegmentBudget)));
  const float autoScale = readGrooms(r, path, base, maxStrandBytes, s, memory);

  // meshes after the grooms: a mesh's "scale": "auto" takes the grooms' factor
  readMeshes(r, base, maxStrandBytes, autoScale, s);

  if (!s.grooms.empty()) {
    glm::vec3 lo, hi;
    framingBounds(s, lo, hi, &s.warnings, path);
  }
  readCamera(r, s);
  readViews(r, s);
  s.frameRate = r.number("frame_rate", s.frameRate, 1e-3, 1e6);
  readRaster(r, s);
  if (r.has("quality")) s.quality = readQuality(r);
  readTemporal(r, s);
  r.rejectUnknown({"resolution",     "camera",      "cameras",     "background",       "ambient",
                   "lights",         "spheres",     "planes",      "meshes",           "grooms",
                   "shadows",        "filter",      "environment", "background_image", "frame_rate",
                   "segment_budget", "max_strands", "raster",      "temporal",         "quality"});
  s.files.push_back(path);
  collectFiles(root, base, s.files);
  return s;
}

}  // namespace

Scene loadScene(const std::string& path, std::uint64_t maxStrandBytes) {
  json root = readJsonFile(path, "scene");
  return readScene(root, path, std::filesystem::path(path).parent_path(), maxStrandBytes, nullptr);
}

Scene loadSceneJson(const std::string& text, const std::string& where, const std::string& baseDir,
                    const MemoryGrooms& memoryGrooms, std::uint64_t maxStrandBytes) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    throw Error(where + ": not valid JSON (" + e.what() + ")");
  }
  if (!root.is_object()) throw Error(where + ": the scene must be a JSON object");
  return readScene(root, where, std::filesystem::path(baseDir), maxStrandBytes, &memoryGrooms);
}

}  // namespace clhair
