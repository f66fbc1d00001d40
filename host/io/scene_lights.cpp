// scene_lights.cpp — a scene's light: "background", "background_image", "ambient", the
// "lights" (point or directional, up to 16, up to 4 casting shadows), the deep-opacity
// "shadows" settings and the "environment" (an equirectangular map or a procedural sky).
//
// Files named here are relative to the scene's folder and must exist when the scene is read.
#include <string>
#include <system_error>

#include <glm/geometric.hpp>

#include "clhair/error.h"
#include "io/enum_field.h"
#include "io/scene_sections.h"

namespace clhair::scene_io {

using nlohmann::json;

namespace {

constexpr int kMaxShadowedLights = 4;  // deep opacity maps a frame has (CLH_MAX_SHADOWS)

constexpr EnumName<Light::Type> kLightTypes[] = {{"point", Light::Type::Point},
                                                 {"directional", Light::Type::Directional}};

}  // namespace

void readBackground(const JsonReader& r, const std::filesystem::path& base, Scene& s) {
  s.background = r.vec3("background", s.background, 0.0, kBig);
  if (r.has("background_image")) {
    std::filesystem::path f = r.string("background_image", "");
    if (f.empty()) r.fail("background_image", "is empty");
    if (!f.is_absolute()) f = base / f;
    s.backgroundImage = f.lexically_normal().string();
    std::error_code ec;
    if (!std::filesystem::exists(s.backgroundImage, ec))
      r.fail("background_image", "\"" + s.backgroundImage + "\" does not exist");
  }
  s.ambient = r.vec3("ambient", s.ambient, 0.0, kBig);
}

void readLights(const JsonReader& r, Scene& s) {
  if (!r.has("lights")) return;
  const json& lights = r.require("lights");
  if (!lights.is_array()) r.fail("lights", "must be an array");
  std::vector<std::size_t> implicit;  // lights that did not say whether they cast shadows
  for (std::size_t i = 0; i < lights.size(); ++i) {
    JsonReader l = r.object(lights[i], "lights[" + std::to_string(i) + "]");
    Light light;
    light.type =
        readEnum(l, "type", l.string("type", "directional"), kLightTypes, EnumWording::Expected);
    if (light.type == Light::Type::Point) {
      light.position = l.vec3("position", light.position, -kBig, kBig);
    } else {
      glm::vec3 d = l.vec3("direction", light.direction, -kBig, kBig);
      if (glm::length(d) < 1e-6f) l.fail("direction", "must not be zero");
      light.direction = glm::normalize(d);
    }
    light.color = l.vec3("color", light.color, 0.0, kBig);
    light.intensity = static_cast<float>(l.number("intensity", light.intensity, 0.0, kBig));
    light.shadows = l.boolean("shadows", true);
    if (!l.has("shadows")) implicit.push_back(i);
    l.rejectUnknown({"type", "position", "direction", "color", "intensity", "shadows"});
    s.lights.push_back(light);
  }
  if (s.lights.size() > 16)
    r.fail("lights",
           "holds " + std::to_string(s.lights.size()) + " lights, at most 16 are supported");
  int shadowed = 0;
  for (const Light& l : s.lights) shadowed += l.shadows;
  const int implicitCount = static_cast<int>(implicit.size());
  if (shadowed - implicitCount > kMaxShadowedLights)
    r.fail("lights", std::to_string(shadowed - implicitCount) +
                         " lights say \"shadows\": true, at most " +
                         std::to_string(kMaxShadowedLights) + " can");
  // Every light casts hair shadows unless it says "shadows": false; past the maps there are,
  // the last lights that did not ask for one go without, with a note.
  for (int k = implicitCount - 1; k >= 0 && shadowed > kMaxShadowedLights; --k, --shadowed) {
    s.lights[implicit[k]].shadows = false;
    s.notes.push_back(r.file() + ": lights[" + std::to_string(implicit[k]) +
                      "] casts no hair shadow: at most " + std::to_string(kMaxShadowedLights) +
                      " lights have deep opacity maps (set \"shadows\": false on another light "
                      "to give this one a map)");
  }
}

void readShadows(const JsonReader& r, Scene& s) {
  if (!r.has("shadows")) return;
  JsonReader o = r.object(r.require("shadows"), "shadows");
  s.shadows.resolution = o.integer("resolution", s.shadows.resolution, 16, 4096);
  if (o.has("layers")) {
    glm::vec3 l =
        o.vec3("layers", glm::vec3(s.shadows.layers[0], s.shadows.layers[1], s.shadows.layers[2]),
               1e-7, kBig);
    if (!(l.x < l.y && l.y < l.z))
      o.fail("layers", "must increase: three layer ends past the first hair");
    for (int i = 0; i < 3; ++i) s.shadows.layers[i] = l[i];
  }
  s.shadows.density = static_cast<float>(o.number("density", s.shadows.density, 0.0, 1e6));
  s.shadows.lodCorrection = o.boolean("lod_correction", s.shadows.lodCorrection);
  s.shadows.bias = static_cast<float>(o.number("bias", s.shadows.bias, 0.0, 1000.0));
  s.shadows.pcf = o.boolean("pcf", s.shadows.pcf);
  s.shadows.lodScale = static_cast<float>(o.number("lod_scale", s.shadows.lodScale, 1e-3, 1e3));
  o.rejectUnknown(
      {"resolution", "layers", "density", "lod_correction", "bias", "pcf", "lod_scale"});
}

void readEnvironment(const JsonReader& r, const std::filesystem::path& base, Scene& s) {
  if (!r.has("environment")) return;
  JsonReader o = r.object(r.require("environment"), "environment");
  EnvironmentDesc& e = s.environment;
  e.enabled = true;
  if (o.has("file") == o.has("sky"))
    o.fail("file", "give exactly one of \"file\" (an equirectangular map) and \"sky\"");
  if (o.has("file")) {
    std::filesystem::path f = o.string("file", "");
    if (!f.is_absolute()) f = base / f;
    e.file = f.lexically_normal().string();
    std::error_code ec;
    if (!std::filesystem::exists(e.file, ec)) o.fail("file", "\"" + e.file + "\" does not exist");
  } else {
    JsonReader k = o.object(o.require("sky"), "sky");
    SkyParams& sky = e.sky;
    sky.sunElevationDeg =
        static_cast<float>(k.number("sun_elevation", sky.sunElevationDeg, -90.0, 90.0));
    sky.sunAzimuthDeg =
        static_cast<float>(k.number("sun_azimuth", sky.sunAzimuthDeg, -360.0, 360.0));
    sky.sunAngularDiameterDeg =
        static_cast<float>(k.number("sun_angular_diameter", sky.sunAngularDiameterDeg, 0.01, 45.0));
    sky.sunColor = k.vec3("sun_color", sky.sunColor, 0.0, kBig);
    sky.sunIrradiance = static_cast<float>(k.number("sun_irradiance", sky.sunIrradiance, 0.0, 1e6));
    sky.zenith = k.vec3("zenith", sky.zenith, 0.0, kBig);
    sky.horizon = k.vec3("horizon", sky.horizon, 0.0, kBig);
    sky.ground = k.vec3("ground", sky.ground, 0.0, kBig);
    sky.gradientExponent =
        static_cast<float>(k.number("gradient_exponent", sky.gradientExponent, 0.01, 100.0));
    sky.groundBlend = static_cast<float>(k.number("ground_blend", sky.groundBlend, 0.0, 1.0));
    sky.width = k.integer("resolution", sky.width, 16, 4096);
    k.rejectUnknown({"sun_elevation", "sun_azimuth", "sun_angular_diameter", "sun_color",
                     "sun_irradiance", "zenith", "horizon", "ground", "gradient_exponent",
                     "ground_blend", "resolution"});
  }
  e.intensity = static_cast<float>(o.number("intensity", e.intensity, 0.0, 1e6));
  e.rotateYDegrees = static_cast<float>(o.number("rotate_y", e.rotateYDegrees, -360.0, 360.0));
  e.visible = o.boolean("visible", e.visible);
  o.rejectUnknown({"file", "sky", "intensity", "rotate_y", "visible"});
}

}  // namespace clhair::scene_io
