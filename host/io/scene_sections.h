// scene_sections.h — the readers of a JSON scene's sections (docs/scene-format.md), shared
// by the files that implement them and by loadScene (scene_io.cpp), which calls them in
// the order the scene's keys are checked.
//
// Every reader takes the scene object's JsonReader (or an entry's) and fails with one line
// naming the scene file and the element. Files named by a scene are relative to `base`,
// the scene's folder. Layout: camera and animation (scene_camera.cpp, scene_keys.cpp,
// scene_framing.cpp), lights and environment (scene_lights.cpp), grooms and appearance
// (scene_grooms.cpp, scene_strand_groom.cpp), meshes and primitives (scene_meshes.cpp),
// render settings (scene_render.cpp).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "clhair/animation.h"
#include "clhair/scene.h"
#include "clhair/scene_json.h"
#include "io/json_util.h"

namespace clhair::scene_io {

// The bound of positions, directions and colours a scene may give.
constexpr double kBig = 1e6;

// --- camera and animation ---------------------------------------------------------------

// One keyed property: `width` numbers (1 or 3) within lo..hi.
struct KeyField {
  const char* name;
  int width;
  double lo, hi;
};

// The "keys" array and "interpolation" of the object `o`: every key holds "frame" (strictly
// increasing) and any of `fields`; a field a key leaves out takes its value from `defaults`
// (the object's still values, field by field in order).
KeyTrack readKeys(const JsonReader& o, const std::vector<KeyField>& fields,
                  const std::vector<double>& defaults);

// A "transform" object: translate / rotate_y / scale or a row-major matrix. With `keys`
// (grooms), "keys" and "interpolation" animate translate, rotate_y and scale.
glm::mat4 readTransform(const JsonReader& parent, const nlohmann::json& j,
                        KeyTrack* keys = nullptr);

// An entry's "up" ("x", "y" or "z"; "y" when left out): the file's up axis.
UpAxis readUpAxis(const JsonReader& o);

// The box that camera presets frame (scene_framing.cpp); outlying points are described in
// *warnings when given, each line starting with `where`.
void framingBounds(const Scene& s, glm::vec3& lo, glm::vec3& hi, std::vector<std::string>* warnings,
                   const std::string& where);

// "camera": a preset framing the scene as read so far, or an explicit camera; either may
// be keyed. Without it, the "mid" preset.
void readCamera(const JsonReader& r, Scene& s);

// "cameras": the extra named views.
void readViews(const JsonReader& r, Scene& s);

// --- lights and environment -------------------------------------------------------------

// "background", "background_image" and "ambient".
void readBackground(const JsonReader& r, const std::filesystem::path& base, Scene& s);
void readLights(const JsonReader& r, Scene& s);
void readShadows(const JsonReader& r, Scene& s);
void readEnvironment(const JsonReader& r, const std::filesystem::path& base, Scene& s);

// --- grooms and appearance --------------------------------------------------------------

// "max_strands" and "grooms" of the scene `path`; returns the factor of the first
// "scale": "auto" groom (0 when none), which meshes may take. `memory`: strand grooms held in
// memory, named by the "strands_file" value that stands for them (clhair/scene_json.h).
float readGrooms(const JsonReader& r, const std::string& path, const std::filesystem::path& base,
                 std::uint64_t maxStrandBytes, Scene& s, const MemoryGrooms* memory = nullptr);

// A groom entry with "strands_file" (scene_strand_groom.cpp).
GroomInstance readStrandGroom(
    const JsonReader& o, const std::filesystem::path& base, const FilterParams& sceneFilter,
    std::uint64_t maxBytes, std::map<std::string, std::shared_ptr<const StrandGroom>>& loaded,
    std::map<std::string, std::shared_ptr<const StrandGroom>>& variants,
    std::map<std::string, std::shared_ptr<const VisibilityBake>>& loadedVisibility,
    std::uint64_t sceneCap, std::vector<std::string>& warnings, float autoScale);

// "scale": "auto" for the whole scene (scene_strand_groom.cpp): one factor from the roots of
// every strand-file groom entry with "auto" together, so the files of one groom (a ponytail's
// back, front, sides and tail) stay together; their files are read once into `loaded`. One
// note line names the files and the factor. 0 when no entry has "auto".
float sceneAutoScale(const JsonReader& r, const std::filesystem::path& base, std::uint64_t maxBytes,
                     std::map<std::string, std::shared_ptr<const StrandGroom>>& loaded,
                     std::vector<std::string>& warnings, std::vector<std::string>& notes);

// A groom entry's "visibility": {"file": a baked visibility file, "absorption"}, read once
// per file and checked against the groom it was baked for (`strands` at full detail).
void readVisibilityEntry(const JsonReader& o, const std::filesystem::path& base,
                         std::uint64_t strands, bool fileColor,
                         std::map<std::string, std::shared_ptr<const VisibilityBake>>& loaded,
                         GroomInstance& g);

// --- meshes and primitives --------------------------------------------------------------

void readSpheres(const JsonReader& r, Scene& s);
void readPlanes(const JsonReader& r, Scene& s);
// "meshes", after the grooms: a mesh's "scale": "auto" takes `autoScale`.
void readMeshes(const JsonReader& r, const std::filesystem::path& base,
                std::uint64_t maxStrandBytes, float autoScale, Scene& s);

// --- render settings --------------------------------------------------------------------

void readResolution(const JsonReader& r, Scene& s);
// A "filter" object over the values `f` (the scene's, for a groom's own filter).
FilterParams readFilter(const JsonReader& parent, const nlohmann::json& j, FilterParams f);
// The scene's "quality": a level name, or {"level": name, "spp": passes of final}.
QualityParams readQuality(const JsonReader& r);
void readRaster(const JsonReader& r, Scene& s);
void readTemporal(const JsonReader& r, Scene& s);

}  // namespace clhair::scene_io
