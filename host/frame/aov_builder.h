// aov_builder.h — the layers for compositing (Frame::aovs, clhair/aov.h) from the planes
// the AOV passes gathered on the device (kernels/aov.cl), once the frame is read back.
//
// Inputs: per pixel the hair alpha, the grooms' premultiplied hair, the nearest centre word's
// tangent and strand, the groom owning the pixel's depth (-1: the opaque scene) and its
// motion-pass word; the frame's final depth; the cameras and groom transforms of this frame
// and of the previous one. Outputs: Z, hair alpha, tangent, motion, strand, hair.
// Invariants: the surface whose depth is in Z is the one whose motion is given. A deforming
// groom hands in the motion its motion pass resolved per pixel (the strands evaluated at the
// previous frame); a rigid one's pixels are carried through its change of transform and the
// previous camera here.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>

#include "clhair/gpu_types.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"

namespace clhair {

// What the host keeps of a frame's scene for its motion plane (values: the caller's scenes
// may be gone when a frame in flight completes).
struct AovMotionInputs {
  gpu::ClhViewGpu view{};  // the frame's view record (its sub-pixel shift included)
  int width = 0, height = 0;
  Camera camera, previousCamera;
  std::vector<glm::mat4> transforms, previousTransforms;  // groom instances, by index
  bool hasPrevious = false;
  static AovMotionInputs of(const gpu::ClhViewGpu& view, const Scene& scene, const Scene* previous);
};

// The planes as read back: one entry per pixel (tangent and strand: 4 floats, the 4th unused).
struct AovPlanesHost {
  std::vector<std::int32_t> owner;
  std::vector<std::uint64_t> ownerMotion;
  std::vector<float> alpha, hair, tangent, strand;
  bool ids = false;
};

FrameAovs finishAovs(const AovPlanesHost& planes, const std::vector<float>& depth,
                     const AovMotionInputs& in);

}  // namespace clhair
