// aov_builder.cpp — see aov_builder.h.
#include "frame/aov_builder.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <glm/matrix.hpp>

#include "clhair/aov.h"
#include "frame/view_math.h"

namespace clhair {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr std::uint64_t kEmptyWord = ~std::uint64_t(0);  // CLH_GBUF_EMPTY

// Pixel (x_px, y_px) of view-space point p (gpu_types.h, ClhViewGpu); false behind the eye.
bool project(const gpu::ClhViewGpu& v, const glm::vec3& p, float& x, float& y) {
  if (!(p.z > 1e-6f)) return false;
  x = v.cx + v.fx * p.x / p.z;
  y = v.cy - v.fy * p.y / p.z;
  return true;
}

}  // namespace

AovBuilder::AovBuilder(const gpu::ClhViewGpu& view, const std::vector<float>& opaqueDepth)
    : view_(view),
      pixels_(static_cast<std::size_t>(view.width) * view.height),
      lastDepth_(opaqueDepth),
      owner_(pixels_, -1),
      ownerMotion_(pixels_, kEmptyWord),
      hairAlpha_(pixels_, 0.0f),
      centreZ_(pixels_, kInf),
      tangent_(pixels_ * 3, 0.0f),
      strand_(pixels_ * 3, -1.0f),
      hair_(pixels_ * 4, 0.0f) {}

void AovBuilder::addGroom(std::size_t index, const gpu::ClhGroomGpu& params,
                          const std::vector<std::uint64_t>& centre, int layers,
                          const std::vector<float>& hair, const std::vector<float>& depth,
                          const std::vector<std::uint64_t>* motion,
                          const std::vector<std::uint64_t>* ids) {
  if (ids) ids_ = true;
  for (std::size_t p = 0; p < pixels_; ++p) {
    // the hair is composited over what lies below it: coverages combine like alphas "over"
    const float a = std::min(std::max(hair[p * 4 + 3], 0.0f), 1.0f);
    hairAlpha_[p] = a + (1.0f - a) * hairAlpha_[p];
    const float* h = &hair[p * 4];
    if (h[3] > 0.0f) {  // composite.cl's rule, alpha carried along the same way
      float* acc = &hair_[p * 4];
      for (int c = 0; c < 3; ++c) acc[c] = h[c] + (1.0f - h[3]) * acc[c];
      acc[3] = h[3] + (1.0f - h[3]) * acc[3];
    }
    if (depth[p] < lastDepth_[p]) {
      owner_[p] = static_cast<std::int32_t>(index);
      ownerMotion_[p] = motion ? (*motion)[p] : kEmptyWord;
    }
    lastDepth_[p] = depth[p];
    std::uint64_t word = kEmptyWord;
    for (int s = 0; s < layers; ++s) word = std::min(word, centre[s * pixels_ + p]);
    if (word == kEmptyWord) continue;
    const float z =
        gpu::clh_depth_decode(gpu::clh_gbuf_depth(word), params.depth_near, params.depth_far);
    if (!(z < centreZ_[p])) continue;
    centreZ_[p] = z;
    gpu::clh_oct_decode(gpu::clh_gbuf_oct(word), &tangent_[p * 3]);
    if (!ids) continue;
    const std::uint64_t id = (*ids)[p];
    const bool known = id != kEmptyWord;
    strand_[p * 3] = known ? static_cast<float>(index) : -1.0f;
    strand_[p * 3 + 1] = known ? static_cast<float>(gpu::clh_id_strand(id)) : -1.0f;
    strand_[p * 3 + 2] =
        known ? static_cast<float>(gpu::clh_id_pos(id)) / static_cast<float>(CLH_ID_POS_MAX)
              : -1.0f;
  }
}

FrameAovs AovBuilder::finish(const std::vector<float>& depth, const Scene& scene,
                             const Scene* previous) const {
  FrameAovs out;
  out.hairAlpha = hairAlpha_;
  out.tangent = tangent_;
  out.hair = hair_;
  if (ids_) out.strand = strand_;
  out.z.resize(pixels_);
  out.motion.assign(pixels_ * 2, 0.0f);
  for (std::size_t p = 0; p < pixels_; ++p)
    out.z[p] = std::isfinite(depth[p]) ? depth[p] : kAovBackgroundZ;
  if (!previous) return out;
  const glm::mat4 viewToWorld = glm::inverse(worldToView(scene.camera));
  const glm::mat4 prevToView = worldToView(previous->camera);
  // the previous view keeps this frame's sub-pixel shift (jittered reference passes, tests)
  gpu::ClhViewGpu prev = makeView(previous->camera, scene.width, scene.height);
  const gpu::ClhViewGpu still = makeView(scene.camera, scene.width, scene.height);
  prev.cx += view_.cx - still.cx;
  prev.cy += view_.cy - still.cy;
  // per groom: world now -> world in the previous frame (rigid transform keys)
  std::vector<glm::mat4> back(scene.grooms.size(), glm::mat4(1.0f));
  std::vector<bool> moved(scene.grooms.size(), false);
  for (std::size_t g = 0; g < scene.grooms.size() && g < previous->grooms.size(); ++g) {
    moved[g] = previous->grooms[g].transform != scene.grooms[g].transform;
    back[g] = previous->grooms[g].transform * glm::inverse(scene.grooms[g].transform);
  }
  // what did not move has exactly zero motion, not the rounding of a round trip
  const Camera &a = scene.camera, &b = previous->camera;
  const bool cameraMoved = a.position != b.position || a.target != b.target || a.up != b.up ||
                           a.fovYDegrees != b.fovYDegrees;
  const std::size_t width = view_.width;
  for (std::size_t p = 0; p < pixels_; ++p) {
    const float z = depth[p];
    if (!std::isfinite(z)) continue;  // the background does not move
    const float px = static_cast<float>(p % width) + 0.5f;
    const float py = static_cast<float>(p / width) + 0.5f;
    // the shading kernel's reconstruction (shade.cl): the pixel centre at view depth z
    const glm::vec4 pv((px - view_.cx) / view_.fx * z, -(py - view_.cy) / view_.fy * z, z, 1.0f);
    glm::vec4 world = viewToWorld * pv;
    const std::int32_t g = owner_[p];
    if (g >= 0 && ownerMotion_[p] != kEmptyWord) {  // resolved by the groom's motion pass
      const auto mx = static_cast<std::uint32_t>(ownerMotion_[p] >> 32);
      const auto my = static_cast<std::uint32_t>(ownerMotion_[p]);
      float x, y;
      std::memcpy(&x, &mx, 4);
      std::memcpy(&y, &my, 4);
      out.motion[p * 2] = x;
      out.motion[p * 2 + 1] = -y;  // y up
      continue;
    }
    if (!cameraMoved && (g < 0 || !moved[static_cast<std::size_t>(g)])) continue;
    if (g >= 0) world = back[static_cast<std::size_t>(g)] * world;
    float x0, y0;
    if (!project(prev, glm::vec3(prevToView * world), x0, y0)) continue;
    out.motion[p * 2] = x0 - px;
    out.motion[p * 2 + 1] = py - y0;  // y up
  }
  return out;
}

}  // namespace clhair
