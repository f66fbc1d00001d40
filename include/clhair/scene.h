// scene.h — what one frame shows: camera, lights, opaque primitives and grooms.
//
// Scenes are JSON files (docs/scene-format.md). Groom files are resolved relative to the
// scene file; a camera can be given explicitly or as a preset that frames all grooms at
// about 60 % (close), 20 % (mid) or 5 % (far) of the image height.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "clhair/hair_mesh.h"

namespace clhair {

struct Camera {
  glm::vec3 position{0.0f, 0.0f, 1.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fovYDegrees = 35.0f;
};

struct Light {
  enum class Type { Point, Directional };
  Type type = Type::Directional;
  glm::vec3 position{0.0f};        // point lights
  glm::vec3 direction{0.0f, 1.0f, 0.0f};  // directional: toward the light
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
};

struct Sphere {
  glm::vec3 center{0.0f};
  float radius = 1.0f;
  glm::vec3 color{0.5f};
};

struct Plane {
  glm::vec3 normal{0.0f, 1.0f, 0.0f};
  float offset = 0.0f;  // dot(normal, x) = offset
  glm::vec3 color{0.5f};
};

struct GroomInstance {
  std::string name;
  std::shared_ptr<const HairMesh> mesh;
  glm::mat4 transform{1.0f};  // object -> world
};

struct Scene {
  int width = 1280;
  int height = 720;
  Camera camera;
  glm::vec3 background{0.05f, 0.06f, 0.08f};
  glm::vec3 ambient{0.05f};
  std::vector<Light> lights;
  std::vector<Sphere> spheres;
  std::vector<Plane> planes;
  std::vector<GroomInstance> grooms;
};

enum class CameraPreset { Close, Mid, Far };
// Frames the world bounds of all grooms at 60 / 20 / 5 % of the image height, seen from
// the direction given by azimuth (degrees about +y, 0 looks along -z) and elevation.
Camera framePreset(const Scene& scene, CameraPreset preset, float azimuthDeg = 0.0f,
                   float elevationDeg = 10.0f, float fovYDeg = 35.0f);
CameraPreset parseCameraPreset(const std::string& name);

// Largest accepted image side; larger requests are refused as absurd.
constexpr int kMaxImageSide = 16384;

Scene loadScene(const std::string& path);

}  // namespace clhair
