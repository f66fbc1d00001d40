// scene_keys.cpp — the keyed and placed parts of a scene: "keys" tracks (camera and groom
// animation, docs/scene-format.md "Animation"), "transform" objects and an entry's "up" axis.
//
// A track is read into a KeyTrack (clhair/animation.h) whose values hold, per key, every
// field in the order given; sceneAtFrame interpolates them.
#include <cmath>
#include <cstdio>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include "clhair/error.h"
#include "io/enum_field.h"
#include "io/scene_sections.h"

namespace clhair::scene_io {

namespace {

using nlohmann::json;

constexpr EnumName<Interpolation> kInterpolations[] = {{"linear", Interpolation::Linear},
                                                       {"smooth", Interpolation::Smooth}};

std::string showNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", v);
  return buf;
}

}  // namespace

KeyTrack readKeys(const JsonReader& o, const std::vector<KeyField>& fields,
                  const std::vector<double>& defaults) {
  KeyTrack t;
  for (const KeyField& f : fields) t.width += f.width;
  t.interpolation = readEnum(o, "interpolation", o.string("interpolation", "linear"),
                             kInterpolations, EnumWording::Expected);
  const json& a = o.require("keys");
  if (!a.is_array() || a.empty())
    o.fail("keys", "must be a non-empty array of key objects ({\"frame\": 1, ...})");
  if (a.size() > 100000)
    o.fail("keys", "holds " + std::to_string(a.size()) + " keys, at most 100000 are supported");
  std::vector<std::string> known{"frame"};
  for (const KeyField& f : fields) known.push_back(f.name);
  for (std::size_t i = 0; i < a.size(); ++i) {
    JsonReader k = o.object(a[i], "keys[" + std::to_string(i) + "]");
    k.require("frame");
    const double frame = k.number("frame", 0.0, -1e7, 1e7);
    if (!t.frames.empty() && !(frame > t.frames.back()))
      k.fail("frame", "is " + showNumber(frame) + ", not after the previous key's " +
                          showNumber(t.frames.back()) + ": keys must be in increasing frame order");
    t.frames.push_back(frame);
    std::size_t at = 0;
    for (const KeyField& f : fields) {
      if (f.width == 3) {
        const glm::vec3 def(static_cast<float>(defaults[at]), static_cast<float>(defaults[at + 1]),
                            static_cast<float>(defaults[at + 2]));
        const glm::vec3 v = k.vec3(f.name, def, f.lo, f.hi);
        t.values.insert(t.values.end(), {v.x, v.y, v.z});
      } else {
        t.values.push_back(k.number(f.name, defaults[at], f.lo, f.hi));
      }
      at += static_cast<std::size_t>(f.width);
    }
    k.rejectUnknown(known);
  }
  return t;
}

// A "transform" object: translate / rotate_y / scale or a row-major matrix. With `keys`
// (grooms), "keys" and "interpolation" animate translate, rotate_y and scale.
glm::mat4 readTransform(const JsonReader& parent, const json& j, KeyTrack* keys) {
  JsonReader t = parent.object(j, "transform");
  glm::mat4 m(1.0f);
  if (t.has("matrix")) {
    if (keys && t.has("keys"))
      t.fail("keys", "animate translate, rotate_y and scale: give those instead of \"matrix\"");
    const json& a = t.require("matrix");
    if (!a.is_array() || a.size() != 16) t.fail("matrix", "must be 16 numbers, row-major");
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) {
        if (!a[r * 4 + c].is_number()) t.fail("matrix", "must be 16 numbers, row-major");
        double d = a[r * 4 + c].get<double>();
        if (!std::isfinite(d) || std::fabs(d) > 3.0e38)
          t.fail("matrix", "holds a non-finite number or one beyond float range");
        m[c][r] = static_cast<float>(d);
      }
    // a singular matrix flattens what it places to a plane, a line or a point, which then
    // draws nothing (the smallest "scale" allowed, 1e-6 on every axis, has a determinant of 1e-18)
    const double det = glm::determinant(glm::dmat3(glm::mat3(m)));
    if (!(std::fabs(det) >= 1e-18))
      t.fail("matrix", "is degenerate: its 3x3 part has determinant " + showNumber(det) +
                           ", so it flattens everything it places (expected at least 1e-18 in "
                           "magnitude)");
    t.rejectUnknown({"matrix"});
    return m;
  }
  glm::vec3 translate = t.vec3("translate", glm::vec3(0.0f), -kBig, kBig);
  float rotateY = static_cast<float>(t.number("rotate_y", 0.0, -360.0, 360.0));
  float scale = static_cast<float>(t.number("scale", 1.0, 1e-6, 1e6));
  if (keys && (t.has("keys") || t.has("interpolation"))) {
    *keys = readKeys(t,
                     {{"translate", 3, -kBig, kBig},
                      {"rotate_y", 1, -36000.0, 36000.0},
                      {"scale", 1, 1e-6, 1e6}},
                     {translate.x, translate.y, translate.z, rotateY, scale});
    t.rejectUnknown({"translate", "rotate_y", "scale", "keys", "interpolation"});
  } else {
    t.rejectUnknown({"translate", "rotate_y", "scale"});
  }
  m = glm::translate(m, translate);
  m = glm::rotate(m, glm::radians(rotateY), glm::vec3(0, 1, 0));
  m = glm::scale(m, glm::vec3(scale));
  return m;
}

UpAxis readUpAxis(const JsonReader& o) {
  static constexpr EnumName<UpAxis> kUpAxes[] = {
      {"x", UpAxis::X}, {"y", UpAxis::Y}, {"z", UpAxis::Z}};
  return readEnum(o, "up", o.string("up", "y"), kUpAxes, EnumWording::Expected);
}

}  // namespace clhair::scene_io
