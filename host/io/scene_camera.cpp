// scene_camera.cpp — a scene's "camera" (a preset framing the grooms and meshes read so
// far, or an explicit position / target / up; either may be keyed over frames) and its
// extra named "cameras" (views rendered beside the main one, explicit or offset from it).
//
// Every camera, and every key of a keyed explicit one, must be a camera on its own: a
// target apart from the position and an up not along the viewing direction.
#include <string>

#include <glm/geometric.hpp>

#include "clhair/error.h"
#include "io/scene_sections.h"

namespace clhair::scene_io {

using nlohmann::json;

void readCamera(const JsonReader& r, Scene& s) {
  if (r.has("camera")) {
    JsonReader c = r.object(r.require("camera"), "camera");
    float fov = static_cast<float>(c.number("fov", 35.0, 1.0, 170.0));
    const bool keyed = c.has("keys") || c.has("interpolation");
    CameraAnimation& anim = s.cameraAnimation;
    if (c.has("preset")) {
      std::string name = c.string("preset", "mid");
      CameraPreset preset;
      try {
        preset = parseCameraPreset(name);
      } catch (const Error& e) {
        c.fail("preset", e.what());
      }
      const double azimuth = c.number("azimuth", 0.0, -360.0, 360.0);
      const double elevation = c.number("elevation", 10.0, -89.0, 89.0);
      s.camera =
          framePreset(s, preset, static_cast<float>(azimuth), static_cast<float>(elevation), fov);
      if (keyed) {
        anim.preset = true;
        anim.framing = preset;
        anim.keys = readKeys(c,
                             {{"azimuth", 1, -36000.0, 36000.0},
                              {"elevation", 1, -89.0, 89.0},
                              {"fov", 1, 1.0, 170.0}},
                             {azimuth, elevation, fov});
      }
      c.rejectUnknown({"preset", "azimuth", "elevation", "fov", "keys", "interpolation"});
    } else {
      s.camera.position = c.vec3("position", s.camera.position, -kBig, kBig);
      s.camera.target = c.vec3("target", s.camera.target, -kBig, kBig);
      s.camera.up = c.vec3("up", s.camera.up, -kBig, kBig);
      s.camera.fovYDegrees = fov;
      if (glm::length(s.camera.target - s.camera.position) < 1e-9f)
        c.fail("target", "must differ from position");
      if (glm::length(glm::cross(s.camera.target - s.camera.position, s.camera.up)) < 1e-9f)
        c.fail("up", "must not be parallel to the viewing direction");
      if (keyed) {
        const Camera& k = s.camera;
        anim.keys = readKeys(c,
                             {{"position", 3, -kBig, kBig},
                              {"target", 3, -kBig, kBig},
                              {"up", 3, -kBig, kBig},
                              {"fov", 1, 1.0, 170.0}},
                             {k.position.x, k.position.y, k.position.z, k.target.x, k.target.y,
                              k.target.z, k.up.x, k.up.y, k.up.z, k.fovYDegrees});
        // every key must be a camera on its own (between keys sceneAtFrame checks again)
        for (std::size_t i = 0; i < anim.keys.frames.size(); ++i) {
          const double* v = &anim.keys.values[i * 10];
          const glm::vec3 pos(v[0], v[1], v[2]), target(v[3], v[4], v[5]), up(v[6], v[7], v[8]);
          const std::string where = "keys[" + std::to_string(i) + "]";
          if (glm::length(target - pos) < 1e-9f) c.fail(where, "target must differ from position");
          if (glm::length(glm::cross(target - pos, up)) < 1e-9f)
            c.fail(where, "up must not be parallel to the viewing direction");
        }
      }
      c.rejectUnknown({"position", "target", "up", "fov", "keys", "interpolation"});
    }
  } else {
    s.camera = framePreset(s, CameraPreset::Mid);
  }
}

void readViews(const JsonReader& r, Scene& s) {
  if (!r.has("cameras")) return;
  const json& cams = r.require("cameras");
  if (!cams.is_array() || cams.empty() || cams.size() > static_cast<std::size_t>(kMaxViews))
    r.fail("cameras", "must be an array of 1 to " + std::to_string(kMaxViews) + " views");
  for (std::size_t i = 0; i < cams.size(); ++i) {
    JsonReader c = r.object(cams[i], "cameras[" + std::to_string(i) + "]");
    View v;
    v.name = c.string("name", "");
    if (v.name.empty() || v.name.find_first_of("/\\%#") != std::string::npos)
      c.fail("name", "a view needs a name without / \\ % or #");
    for (const View& o : s.views)
      if (o.name == v.name) c.fail("name", "\"" + v.name + "\" names two views");
    if (c.has("offset")) {
      v.relative = true;
      v.offset = c.vec3("offset", v.offset, -kBig, kBig);
      c.rejectUnknown({"name", "offset"});
    } else {
      Camera& k = v.camera;
      k.position = c.vec3("position", k.position, -kBig, kBig);
      k.target = c.vec3("target", k.target, -kBig, kBig);
      k.up = c.vec3("up", k.up, -kBig, kBig);
      k.fovYDegrees = static_cast<float>(c.number("fov", 35.0, 1.0, 170.0));
      if (glm::length(k.target - k.position) < 1e-9f) c.fail("target", "must differ from position");
      if (glm::length(glm::cross(k.target - k.position, k.up)) < 1e-9f)
        c.fail("up", "must not be parallel to the viewing direction");
      c.rejectUnknown({"name", "position", "target", "up", "fov"});
    }
    s.views.push_back(v);
  }
}

}  // namespace clhair::scene_io
