// animation.cpp — keyframe interpolation (clhair/animation.h), the wind deformer and the
// evaluation of a scene at one frame (sceneAtFrame, clhair/scene.h).
//
// Inputs: a loaded Scene with its keys, cage animations and wind. Output: a still Scene
// whose grooms carry the cage of that frame in `deformed`. Nothing here keeps state
// between calls, so a frame evaluates to the same still scene in any order.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include "clhair/error.h"
#include "clhair/scene.h"

namespace clhair {

std::vector<double> KeyTrack::evaluate(double frame) const {
  const std::size_t n = frames.size(), w = static_cast<std::size_t>(width);
  std::vector<double> out(w, 0.0);
  if (n == 0) return out;
  auto key = [&](std::size_t k, std::size_t c) { return values[k * w + c]; };
  if (!(frame > frames.front())) {  // NaN lands here too
    for (std::size_t c = 0; c < w; ++c) out[c] = key(0, c);
    return out;
  }
  if (frame >= frames.back()) {
    for (std::size_t c = 0; c < w; ++c) out[c] = key(n - 1, c);
    return out;
  }
  // the segment [frames[i], frames[i + 1]) holding `frame`
  const std::size_t i =
      static_cast<std::size_t>(std::upper_bound(frames.begin(), frames.end(), frame) -
                               frames.begin()) -
      1;
  const double h = frames[i + 1] - frames[i];
  const double u = (frame - frames[i]) / h;
  for (std::size_t c = 0; c < w; ++c) {
    const double p0 = key(i, c), p1 = key(i + 1, c);
    if (interpolation == Interpolation::Linear) {
      out[c] = p0 + (p1 - p0) * u;
      continue;
    }
    // Catmull-Rom tangents in value per frame at inner keys, zero at the ends
    auto tangent = [&](std::size_t k) {
      if (k == 0 || k + 1 == n) return 0.0;
      return (key(k + 1, c) - key(k - 1, c)) / (frames[k + 1] - frames[k - 1]);
    };
    const double u2 = u * u, u3 = u2 * u;
    const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u;
    const double h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
    out[c] = h00 * p0 + h10 * h * tangent(i) + h01 * p1 + h11 * h * tangent(i + 1);
  }
  return out;
}

std::string framePath(const std::string& pattern, long long frame) {
  const std::size_t nameStart = pattern.find_last_of('/') + 1;  // npos + 1 == 0
  const std::size_t end = pattern.find_last_of('#');
  if (end == std::string::npos || end < nameStart) return pattern;
  std::size_t begin = end;
  while (begin > nameStart && pattern[begin - 1] == '#') --begin;
  std::string digits = std::to_string(frame);
  const std::size_t width = end - begin + 1;
  if (digits.size() < width) digits.insert(0, width - digits.size(), '0');
  return pattern.substr(0, begin) + digits + pattern.substr(end + 1);
}

namespace {

glm::vec3 vec3At(const std::vector<double>& v, std::size_t at) {
  return glm::vec3(static_cast<float>(v[at]), static_cast<float>(v[at + 1]),
                   static_cast<float>(v[at + 2]));
}

std::string frameName(double frame) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", frame);
  return buf;
}

// The cage of `g`'s mesh at `frame` from its cage animation (linear between stored frames,
// clamped to the first and last), or the mesh's own positions.
std::vector<glm::vec3> cageAt(const GroomInstance& g, double frame) {
  if (!g.cage) return g.mesh->positions;
  const CageAnimation& c = *g.cage;
  double k = frame - g.cageStartFrame;
  k = std::min(std::max(k, 0.0), static_cast<double>(c.frames - 1));
  const auto k0 = static_cast<std::uint32_t>(std::floor(k));
  const std::uint32_t k1 = std::min(k0 + 1, c.frames - 1);
  const float t = static_cast<float>(k - k0);
  const glm::vec3* a = c.frame(k0);
  const glm::vec3* b = c.frame(k1);
  std::vector<glm::vec3> out(c.vertices);
  for (std::uint32_t v = 0; v < c.vertices; ++v)
    out[v] = t == 0.0f ? a[v] : a[v] + (b[v] - a[v]) * t;
  return out;
}

// Adds the wind's displacement (clhair/animation.h) to the layer vertices `p` of `mesh`
// placed in the world by `objToWorld`; the offset is computed in world units and taken
// back to object space.
void applyWind(const WindParams& wind, const HairMesh& mesh, const glm::mat4& objToWorld,
               double seconds, std::vector<glm::vec3>& p, const std::string& groomName) {
  const glm::mat3 linear(objToWorld);
  if (std::fabs(glm::determinant(linear)) < 1e-30f)
    throw Error("groom \"" + groomName + "\": wind needs an invertible transform");
  const glm::mat3 toObject = glm::inverse(linear);
  const glm::vec3 dir = glm::normalize(wind.direction);
  const int L = mesh.layerCount, V = mesh.vertexCount;
  const double twoPi = 6.283185307179586;
  for (int v = 0; v < V; ++v) {
    const glm::vec3 root = glm::vec3(objToWorld * glm::vec4(p[static_cast<std::size_t>(v)], 1.0f));
    const double phase = twoPi * (wind.frequency * seconds - glm::dot(root, dir) / wind.wavelength);
    const float gust = static_cast<float>(0.5 + 0.5 * std::sin(phase));
    const glm::vec3 offset = toObject * (dir * (wind.strength * gust));
    for (int l = 1; l < L; ++l) {
      const float h = static_cast<float>(l) / static_cast<float>(L - 1);
      p[static_cast<std::size_t>(l) * V + v] += offset * (h * h);
    }
  }
}

}  // namespace

Camera viewCamera(const Scene& scene, const View& v) {
  if (!v.relative) return v.camera;
  // the scene camera's frame: right, up (orthogonalised) and back
  const Camera& c = scene.camera;
  const glm::vec3 back = glm::normalize(c.position - c.target);
  const glm::vec3 right = glm::normalize(glm::cross(c.up, back));
  const glm::vec3 up = glm::cross(back, right);
  const glm::vec3 shift = v.offset.x * right + v.offset.y * up + v.offset.z * back;
  Camera out = c;
  out.position += shift;
  out.target += shift;
  return out;
}

bool isAnimated(const Scene& scene) {
  if (!scene.cameraAnimation.keys.empty()) return true;
  for (const GroomInstance& g : scene.grooms)
    if (!g.transformKeys.empty() || g.cage || g.wind.strength > 0.0f) return true;
  return false;
}

Scene sceneAtFrame(const Scene& scene, double frame) {
  Scene s = scene;
  for (GroomInstance& g : s.grooms) {
    if (!g.transformKeys.empty()) {
      const std::vector<double> k = g.transformKeys.evaluate(frame);
      glm::mat4 m(1.0f);
      m = glm::translate(m, vec3At(k, 0));
      m = glm::rotate(m, glm::radians(static_cast<float>(k[3])), glm::vec3(0, 1, 0));
      m = glm::scale(m, glm::vec3(static_cast<float>(k[4])));
      g.transform = m * g.fileTransform;
    }
    if (g.strandFrames) {
      // the nearest whole frame, held before the first file and after the last
      const StrandFrames& f = *g.strandFrames;
      const double nearest = std::floor(frame + 0.5);
      const long long n = !(nearest > static_cast<double>(f.first)) ? f.first
                          : nearest >= static_cast<double>(f.last)
                              ? f.last
                              : static_cast<long long>(nearest);
      if (n != f.first) {  // `strands` is the first file as the scene loaded it
        StrandGroom frameGroom;
        try {
          frameGroom = loadStrandGroom(framePath(f.pattern, n), f.maxBytes);
        } catch (const Error& e) {
          throw Error("groom \"" + g.name + "\" at frame " + frameName(frame) + ": " + e.what());
        }
        frameGroom.appearance = g.strands->appearance;
        frameGroom.lod = g.strands->lod;
        frameGroom.children = g.strands->children;
        g.strands = std::make_shared<const StrandGroom>(std::move(frameGroom));
      }
    }
    g.deformed.reset();
    if (g.mesh && (g.cage || g.wind.strength > 0.0f)) {
      std::vector<glm::vec3> p = cageAt(g, frame);
      if (g.wind.strength > 0.0f)
        applyWind(g.wind, *g.mesh, g.transform, frame / scene.frameRate, p, g.name);
      g.deformed = std::make_shared<const std::vector<glm::vec3>>(std::move(p));
    }
  }
  const CameraAnimation& a = scene.cameraAnimation;
  if (!a.keys.empty()) {
    const std::vector<double> k = a.keys.evaluate(frame);
    if (a.preset) {
      s.camera = framePreset(s, a.framing, static_cast<float>(k[0]), static_cast<float>(k[1]),
                             static_cast<float>(k[2]));
    } else {
      Camera& c = s.camera;
      c.position = vec3At(k, 0);
      c.target = vec3At(k, 3);
      c.up = vec3At(k, 6);
      c.fovYDegrees = static_cast<float>(k[9]);
      const glm::vec3 view = c.target - c.position;
      if (glm::length(view) < 1e-9f)
        throw Error("camera at frame " + frameName(frame) +
                    ": the interpolated target equals the position");
      if (glm::length(glm::cross(view, c.up)) < 1e-9f)
        throw Error("camera at frame " + frameName(frame) +
                    ": the interpolated up vector is parallel to the viewing direction");
    }
  }
  return s;
}

}  // namespace clhair
