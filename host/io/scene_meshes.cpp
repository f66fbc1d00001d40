// scene_meshes.cpp — a scene's solid geometry: "meshes" (OBJ heads, read once per file and
// placed like strand files: scale, up axis, then transform) and the "spheres" and "planes"
// primitives.
//
// A mesh file is checked against the device's largest allocation; every error is one line
// naming the scene and the file as the entry wrote it.
#include <map>
#include <memory>
#include <string>
#include <system_error>

#include <glm/geometric.hpp>

#include "clhair/error.h"
#include "io/scene_sections.h"

namespace clhair::scene_io {

using nlohmann::json;

namespace {

// A "meshes" entry: the OBJ file (read once per scene), its placement (scale, up axis, then
// transform, as for strand files) and its colour.
MeshInstance readMesh(const JsonReader& o, const std::filesystem::path& base,
                      std::uint64_t maxBytes,
                      std::map<std::string, std::shared_ptr<const TriangleMesh>>& loaded,
                      float autoScale) {
  const std::string file = o.string("file", "");
  if (file.empty()) o.fail("file", "is missing: name the mesh's .obj file");
  const std::string label = o.file() + ": mesh \"" + file + "\"";
  std::filesystem::path p =
      std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : base / file;
  const std::string key = p.lexically_normal().string();
  std::error_code ec;
  const bool found = std::filesystem::exists(p, ec);
  if (ec) throw Error(label + ": \"" + key + "\" cannot be checked (" + ec.message() + ")");
  if (!found) throw Error(label + ": \"" + key + "\" does not exist");
  MeshInstance m;
  auto it = loaded.find(key);
  if (it != loaded.end()) {
    m.mesh = it->second;
  } else {
    MeshLimits limits;
    limits.maxBufferBytes = maxBytes;
    m.mesh = std::make_shared<const TriangleMesh>(loadTriangleMesh(key, limits, label));
    loaded[key] = m.mesh;
  }
  m.name = o.string("name", m.mesh->name);
  // "auto": the factor the grooms' "scale": "auto" chose (a head and its groom share units)
  float scale = 1.0f;
  if (o.has("scale") && o.require("scale").is_string()) {
    if (o.string("scale", "") != "auto")
      o.fail("scale", "is \"" + o.string("scale", "") + "\", expected a number or \"auto\"");
    if (!(autoScale > 0.0f))
      o.fail("scale",
             "is \"auto\", which takes the factor of a strand-file groom's \"scale\": "
             "\"auto\", and no groom has one");
    scale = autoScale;
  } else {
    scale = static_cast<float>(o.number("scale", 1.0, 1e-6, 1e6));
  }
  const UpAxis up = readUpAxis(o);
  glm::mat4 placement =
      o.has("transform") ? readTransform(o, o.require("transform")) : glm::mat4(1.0f);
  m.transform = placement * strandFileTransform(scale, up);
  m.color = o.vec3("color", m.color, 0.0, 1.0);
  o.rejectUnknown({"file", "name", "transform", "scale", "up", "color"});
  return m;
}

}  // namespace

void readSpheres(const JsonReader& r, Scene& s) {
  if (!r.has("spheres")) return;
  const json& a = r.require("spheres");
  if (!a.is_array()) r.fail("spheres", "must be an array");
  for (std::size_t i = 0; i < a.size(); ++i) {
    JsonReader o = r.object(a[i], "spheres[" + std::to_string(i) + "]");
    Sphere sp;
    sp.center = o.vec3("center", sp.center, -kBig, kBig);
    sp.radius = static_cast<float>(o.number("radius", sp.radius, 1e-6, kBig));
    sp.color = o.vec3("color", sp.color, 0.0, 1.0);
    o.rejectUnknown({"center", "radius", "color"});
    s.spheres.push_back(sp);
  }
}

void readPlanes(const JsonReader& r, Scene& s) {
  if (!r.has("planes")) return;
  const json& a = r.require("planes");
  if (!a.is_array()) r.fail("planes", "must be an array");
  for (std::size_t i = 0; i < a.size(); ++i) {
    JsonReader o = r.object(a[i], "planes[" + std::to_string(i) + "]");
    Plane pl;
    glm::vec3 n = o.vec3("normal", pl.normal, -kBig, kBig);
    if (glm::length(n) < 1e-6f) o.fail("normal", "must not be zero");
    pl.normal = glm::normalize(n);
    pl.offset = static_cast<float>(o.number("offset", pl.offset, -kBig, kBig));
    pl.color = o.vec3("color", pl.color, 0.0, 1.0);
    o.rejectUnknown({"normal", "offset", "color"});
    s.planes.push_back(pl);
  }
}

void readMeshes(const JsonReader& r, const std::filesystem::path& base,
                std::uint64_t maxStrandBytes, float autoScale, Scene& s) {
  if (!r.has("meshes")) return;
  const json& a = r.require("meshes");
  if (!a.is_array()) r.fail("meshes", "must be an array");
  std::map<std::string, std::shared_ptr<const TriangleMesh>> loadedMeshes;
  for (std::size_t i = 0; i < a.size(); ++i)
    s.meshes.push_back(readMesh(r.object(a[i], "meshes[" + std::to_string(i) + "]"), base,
                                maxStrandBytes, loadedMeshes, autoScale));
}

}  // namespace clhair::scene_io
