// scene_framing.cpp — camera presets and view checks: the box a preset frames (the grooms'
// world points without outliers, plus the meshes), the "close" / "mid" / "far" presets
// along a direction, and the warnings for grooms whose units look wrong for the camera.
//
// Outliers (a broken file's stray 1e30 vertex) are left out of the framing and named in one
// warning line per groom when the scene is read.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vector_relational.hpp>

#include "clhair/error.h"
#include "io/enum_field.h"
#include "io/scene_sections.h"

namespace clhair {

namespace {

const std::vector<glm::vec3>& groomPoints(const GroomInstance& g) {
  return g.strands ? g.strands->points : g.mesh->positions;
}

std::string showVec(const glm::vec3& v) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), "(%g, %g, %g)", v.x, v.y, v.z);
  return buf;
}

}  // namespace

namespace scene_io {

// The box that camera presets frame: the bounds of the grooms' world points that are not
// outliers. The 0.5 % and 99.5 % percentiles per axis (over at most about a million
// points, evenly strided) give a core box; a point counts when it lies within one core
// size (the largest axis extent) of that box. For an ordinary groom every point does, so
// the framing is its exact bounds; a stray vertex (a broken file's 1e30) is left out, and
// described in *warnings (one line per groom, naming its first such strand) when given.
void framingBounds(const Scene& s, glm::vec3& lo, glm::vec3& hi, std::vector<std::string>* warnings,
                   const std::string& where) {
  lo = glm::vec3(-0.5f);
  hi = glm::vec3(0.5f);
  std::size_t total = 0;
  for (const GroomInstance& g : s.grooms) total += groomPoints(g).size();
  if (total == 0) return;
  const std::size_t stride = std::max<std::size_t>(1, total / 1'000'000);
  std::vector<float> axis[3];
  for (auto& a : axis) a.reserve(total / stride + s.grooms.size());
  for (const GroomInstance& g : s.grooms)
    for (std::size_t i = 0; i < groomPoints(g).size(); i += stride) {
      const glm::vec3 w = glm::vec3(g.transform * glm::vec4(groomPoints(g)[i], 1.0f));
      for (int c = 0; c < 3; ++c) axis[c].push_back(w[c]);
    }
  glm::vec3 coreLo, coreHi;
  for (int c = 0; c < 3; ++c) {
    std::vector<float>& a = axis[c];
    const std::size_t n = a.size();
    const std::size_t k0 = static_cast<std::size_t>(0.005 * static_cast<double>(n - 1));
    const std::size_t k1 = static_cast<std::size_t>(std::ceil(0.995 * static_cast<double>(n - 1)));
    std::nth_element(a.begin(), a.begin() + k0, a.end());
    coreLo[c] = a[k0];
    std::nth_element(a.begin(), a.begin() + k1, a.end());
    coreHi[c] = a[k1];
  }
  const glm::vec3 coreExtent = coreHi - coreLo;
  float margin = std::max(coreExtent.x, std::max(coreExtent.y, coreExtent.z));
  // a core of one point (or of points in one place) still admits nearby ones
  margin =
      std::max(margin, 1e-6f * std::max(1.0f, std::max(glm::length(coreLo), glm::length(coreHi))));
  const glm::vec3 acceptLo = coreLo - margin, acceptHi = coreHi + margin;

  glm::vec3 blo(std::numeric_limits<float>::max()), bhi(-std::numeric_limits<float>::max());
  for (std::size_t gi = 0; gi < s.grooms.size(); ++gi) {
    const GroomInstance& g = s.grooms[gi];
    const std::vector<glm::vec3>& points = groomPoints(g);
    std::size_t strand = 0, strandEnd = g.strands && !g.strands->pointCounts.empty()
                                            ? g.strands->pointCounts[0]
                                            : 0;
    std::size_t outlierStrands = 0, firstOutlier = 0, lastCounted = ~std::size_t(0);
    glm::vec3 firstPoint(0.0f);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (g.strands)
        while (i >= strandEnd && strand + 1 < g.strands->pointCounts.size())
          strandEnd += g.strands->pointCounts[++strand];
      const glm::vec3 w = glm::vec3(g.transform * glm::vec4(points[i], 1.0f));
      const bool inside =
          glm::all(glm::greaterThanEqual(w, acceptLo)) && glm::all(glm::lessThanEqual(w, acceptHi));
      if (inside) {
        blo = glm::min(blo, w);
        bhi = glm::max(bhi, w);
        continue;
      }
      const std::size_t id = g.strands ? strand : i;
      if (id == lastCounted) continue;
      if (outlierStrands == 0) {
        firstOutlier = id;
        firstPoint = w;
      }
      ++outlierStrands;
      lastCounted = id;
    }
    if (outlierStrands > 0 && warnings) {
      const std::string what = g.strands ? "strand" : "hair-mesh layer vertex";
      std::string msg = where + ": grooms[" + std::to_string(gi) + "] (\"" + g.name +
                        "\"): " + what + " " + std::to_string(firstOutlier) + " has a point at " +
                        showVec(firstPoint) + ", far outside the rest of the hair (" +
                        showVec(coreLo) + " to " + showVec(coreHi) +
                        "); camera presets frame the hair without it";
      if (outlierStrands > 1)
        msg += " (and " + std::to_string(outlierStrands - 1) + " more " + what +
               (outlierStrands > 2 ? "s" : "") + " like it)";
      warnings->push_back(msg);
    }
  }
  if (blo.x <= bhi.x) {
    lo = blo;
    hi = bhi;
    // follow hairs reach up to their offset's growth beyond their guides
    for (const GroomInstance& g : s.grooms) {
      if (!g.strands || g.strands->children.count == 0) continue;
      const ChildrenParams& c = g.strands->children;
      const float scale = std::cbrt(std::fabs(glm::determinant(glm::mat3(g.transform))));
      const float reach = 1.4143f * std::max(c.radius, 0.0f) * (1.0f + c.tipSpread) * scale;
      lo -= glm::vec3(reach);
      hi += glm::vec3(reach);
    }
  }
}

}  // namespace scene_io

std::vector<std::string> viewWarnings(const Scene& scene, const std::string& where) {
  // Human hair is 20..180 um thick on grooms 0.05..1.5 m across, so width / size is 5e-5 or
  // more (3e-5 would be 70 um fibres on a groom 2.3 m across), while the same file in
  // centimetres is 100 times lower; 50 units is 50 m in clhair's metres.
  constexpr float kMinWidthRatio = 3e-5f, kMaxSize = 50.0f, kMinPixels = 1.0f;
  std::vector<std::string> out;
  const Camera& c = scene.camera;
  const glm::vec3 forward = glm::normalize(c.target - c.position);
  const float fy =
      0.5f * static_cast<float>(scene.height) / std::tan(glm::radians(c.fovYDegrees) * 0.5f);
  for (std::size_t i = 0; i < scene.grooms.size(); ++i) {
    const GroomInstance& g = scene.grooms[i];
    Scene one;
    one.grooms.push_back(g);
    glm::vec3 lo, hi;
    scene_io::framingBounds(one, lo, hi, nullptr, "");
    const glm::vec3 ext = hi - lo;
    const float size = std::max(ext.x, std::max(ext.y, ext.z));
    const float width =
        g.strands ? g.strands->appearance.strandWidth : g.mesh->appearance.strandWidth;
    const float depth = glm::dot(0.5f * (lo + hi) - c.position, forward);
    const std::string hint =
        g.strands ? "\"scale\" (0.01 for a file in centimetres, or \"auto\" to scale its roots "
                    "to a head's 0.18 m)"
                  : "\"transform\": {\"scale\": ...} (0.01 for centimetres)";
    std::string msg;
    char buf[256];
    if (size > 0.0f && (width < kMinWidthRatio * size || size > kMaxSize)) {
      std::snprintf(
          buf, sizeof(buf),
          "is %g units across with fibres %g wide (%.2g of its size; human hair is about 1e-4)",
          static_cast<double>(size), static_cast<double>(width), static_cast<double>(width / size));
      msg = buf;
      if (depth > 0.0f) {
        std::snprintf(buf, sizeof(buf), ", so its fibres are %.2g pixels wide here",
                      static_cast<double>(width * fy / depth));
        msg += buf;
      }
      msg += ": are its units right? set " + hint;
    } else if (depth > 0.0f && size * fy / depth < kMinPixels) {
      std::snprintf(buf, sizeof(buf),
                    "covers only %.2g pixels of the %dx%d image (%g units across, %g away)",
                    static_cast<double>(size * fy / depth), scene.width, scene.height,
                    static_cast<double>(size), static_cast<double>(depth));
      msg = std::string(buf) + ": is it in the units you expect? check " + hint + " or the camera";
    }
    if (!msg.empty())
      out.push_back(where + ": grooms[" + std::to_string(i) + "] (\"" + g.name + "\") " + msg);
  }
  return out;
}

CameraPreset parseCameraPreset(const std::string& name) {
  static constexpr EnumName<CameraPreset> kPresets[] = {
      {"close", CameraPreset::Close}, {"mid", CameraPreset::Mid}, {"far", CameraPreset::Far}};
  CameraPreset preset{};
  if (findEnum(kPresets, name, preset)) return preset;
  throw Error("unknown camera preset \"" + name + "\"; expected " +
              enumNameList(EnumNames(kPresets).names, std::size(kPresets), false));
}

namespace {

// Frames the grooms' bounds from unit direction `dir` (target -> eye).
Camera frameAlong(const Scene& scene, CameraPreset preset, glm::vec3 dir, float fovYDeg,
                  glm::vec3 up) {
  glm::vec3 lo, hi;
  scene_io::framingBounds(scene, lo, hi, nullptr, "");
  // the meshes too (a head under its groom), so that none is cut off
  if (scene.grooms.empty() && !scene.meshes.empty()) {
    lo = glm::vec3(std::numeric_limits<float>::max());
    hi = -lo;
  }
  for (const MeshInstance& m : scene.meshes)
    for (const glm::vec3& p : m.mesh->positions) {
      const glm::vec3 w = glm::vec3(m.transform * glm::vec4(p, 1.0f));
      lo = glm::min(lo, w);
      hi = glm::max(hi, w);
    }
  if (!(lo.x <= hi.x)) {
    lo = glm::vec3(-0.5f);
    hi = glm::vec3(0.5f);
  }
  const float fraction = preset == CameraPreset::Close ? 0.6f
                         : preset == CameraPreset::Mid ? 0.2f
                                                       : 0.05f;
  glm::vec3 center = 0.5f * (lo + hi);
  glm::vec3 extent = hi - lo;
  // The groom's size across the view: its vertical extent, or its horizontal one when the
  // image is the smaller side of it (a wide groom must still fit).
  float aspect = static_cast<float>(scene.width) / static_cast<float>(scene.height);
  float horizontal = std::max(extent.x, extent.z) / aspect;
  float size = std::max(extent.y, horizontal);
  float tanHalf = std::tan(glm::radians(fovYDeg) * 0.5f);
  float distance = std::max(size / (2.0f * fraction * tanHalf), glm::length(extent));
  Camera cam;
  cam.fovYDegrees = fovYDeg;
  cam.target = center;
  cam.position = center + dir * distance;
  cam.up = up;
  return cam;
}

}  // namespace

Camera framePreset(const Scene& scene, CameraPreset preset, float azimuthDeg, float elevationDeg,
                   float fovYDeg) {
  float az = glm::radians(azimuthDeg), el = glm::radians(elevationDeg);
  glm::vec3 dir(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
  return frameAlong(scene, preset, dir, fovYDeg, glm::vec3(0, 1, 0));
}

Camera reframeCamera(const Scene& scene, CameraPreset preset) {
  const Camera& c = scene.camera;
  glm::vec3 dir = c.position - c.target;
  const float len = glm::length(dir);
  // loadScene refuses a camera whose target is its position; a Scene built in code may
  // still hold one, and then the default preset direction is used
  const float el = glm::radians(10.0f);
  dir = len > 0.0f && std::isfinite(len) ? dir / len : glm::vec3(0.0f, std::sin(el), std::cos(el));
  return frameAlong(scene, preset, dir, c.fovYDegrees, c.up);
}

}  // namespace clhair
