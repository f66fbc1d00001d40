// aov_builder.cpp — see aov_builder.h.
#include "frame/aov_builder.h"

#include <cmath>
#include <cstring>
#include <limits>

#include <glm/matrix.hpp>

#include "clhair/aov.h"
#include "stages/view_math.h"

namespace clhair {

namespace {

constexpr std::uint64_t kEmptyWord = ~std::uint64_t(0);  // CLH_GBUF_EMPTY

// Pixel (x_px, y_px) of view-space point p (gpu_types.h, ClhViewGpu); false behind the eye.
bool project(const gpu::ClhViewGpu& v, const glm::vec3& p, float& x, float& y) {
  if (!(p.z > 1e-6f)) return false;
  x = v.cx + v.fx * p.x / p.z;
  y = v.cy - v.fy * p.y / p.z;
  return true;
}

}  // namespace

AovMotionInputs AovMotionInputs::of(const gpu::ClhViewGpu& view, const Scene& scene,
                                    const Scene* previous) {
  AovMotionInputs in;
  in.view = view;
  in.width = scene.width;
  in.height = scene.height;
  in.camera = scene.camera;
  for (const GroomInstance& g : scene.grooms) in.transforms.push_back(g.transform);
  if (previous) {
    in.hasPrevious = true;
    in.previousCamera = previous->camera;
    for (const GroomInstance& g : previous->grooms) in.previousTransforms.push_back(g.transform);
  }
  return in;
}

FrameAovs finishAovs(const AovPlanesHost& planes, const std::vector<float>& depth,
                     const AovMotionInputs& in) {
  const std::size_t pixels = depth.size();
  FrameAovs out;
  out.hairAlpha = planes.alpha;
  out.hair = planes.hair;
  out.tangent.resize(pixels * 3);
  for (std::size_t p = 0; p < pixels; ++p)
    for (int c = 0; c < 3; ++c) out.tangent[p * 3 + c] = planes.tangent[p * 4 + c];
  if (planes.ids) {
    out.strand.resize(pixels * 3);
    for (std::size_t p = 0; p < pixels; ++p)
      for (int c = 0; c < 3; ++c) out.strand[p * 3 + c] = planes.strand[p * 4 + c];
  }
  out.z.resize(pixels);
  out.motion.assign(pixels * 2, 0.0f);
  for (std::size_t p = 0; p < pixels; ++p)
    out.z[p] = std::isfinite(depth[p]) ? depth[p] : kAovBackgroundZ;
  if (!in.hasPrevious) return out;
  const glm::mat4 viewToWorld = glm::inverse(worldToView(in.camera));
  const glm::mat4 prevToView = worldToView(in.previousCamera);
  // the previous view keeps this frame's sub-pixel shift (jittered reference passes, tests)
  gpu::ClhViewGpu prev = makeView(in.previousCamera, in.width, in.height);
  const gpu::ClhViewGpu still = makeView(in.camera, in.width, in.height);
  prev.cx += in.view.cx - still.cx;
  prev.cy += in.view.cy - still.cy;
  // per groom: world now -> world in the previous frame (rigid transform keys)
  const std::size_t G = in.transforms.size();
  std::vector<glm::mat4> back(G, glm::mat4(1.0f));
  std::vector<bool> moved(G, false);
  for (std::size_t g = 0; g < G && g < in.previousTransforms.size(); ++g) {
    moved[g] = in.previousTransforms[g] != in.transforms[g];
    back[g] = in.previousTransforms[g] * glm::inverse(in.transforms[g]);
  }
  // what did not move has exactly zero motion, not the rounding of a round trip
  const Camera &a = in.camera, &b = in.previousCamera;
  const bool cameraMoved = a.position != b.position || a.target != b.target || a.up != b.up ||
                           a.fovYDegrees != b.fovYDegrees;
  const std::size_t width = in.view.width;
  for (std::size_t p = 0; p < pixels; ++p) {
    const float z = depth[p];
    if (!std::isfinite(z)) continue;  // the background does not move
    const float px = static_cast<float>(p % width) + 0.5f;
    const float py = static_cast<float>(p / width) + 0.5f;
    // the shading kernel's reconstruction (shade.cl): the pixel centre at view depth z
    const glm::vec4 pv((px - in.view.cx) / in.view.fx * z, -(py - in.view.cy) / in.view.fy * z, z,
                       1.0f);
    glm::vec4 world = viewToWorld * pv;
    const std::int32_t g = planes.owner[p];
    if (g >= 0 && planes.ownerMotion[p] != kEmptyWord) {  // resolved by the groom's motion pass
      const auto mx = static_cast<std::uint32_t>(planes.ownerMotion[p] >> 32);
      const auto my = static_cast<std::uint32_t>(planes.ownerMotion[p]);
      float x, y;
      std::memcpy(&x, &mx, 4);
      std::memcpy(&y, &my, 4);
      out.motion[p * 2] = x;
      out.motion[p * 2 + 1] = -y;  // y up
      continue;
    }
    const bool ownerMoved = g >= 0 && static_cast<std::size_t>(g) < G && moved[g];
    if (!cameraMoved && !ownerMoved) continue;
    if (g >= 0 && static_cast<std::size_t>(g) < G)
      world = back[static_cast<std::size_t>(g)] * world;
    float x0, y0;
    if (!project(prev, glm::vec3(prevToView * world), x0, y0)) continue;
    out.motion[p * 2] = x0 - px;
    out.motion[p * 2 + 1] = py - y0;  // y up
  }
  return out;
}

}  // namespace clhair
