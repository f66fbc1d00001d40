// view_math.h — cameras to the device's view records (ClhViewGpu of gpu_types.h): the
// world-to-view matrix of a look-at camera, the pinhole intrinsics of a target size, and
// the depth range a groom's bounds span in a view (its G-buffer depth mapping).
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "clhair/gpu_types.h"
#include "clhair/scene.h"

namespace clhair {

void store4(float* dst, const glm::vec3& v, float w);
// Row-major 3x4 from the upper 3x4 of a column-major glm matrix.
void storeMat34(float* dst, const glm::mat4& m);

glm::mat4 worldToView(const Camera& cam);
// The view record of `cam` over a width x height target, one sample per pixel.
gpu::ClhViewGpu makeView(const Camera& cam, int width, int height);

// Depth range of the view-space box of object bounds [lo, hi]; false when all of it lies
// behind the camera.
bool depthRange(const glm::vec3& lo, const glm::vec3& hi, const glm::mat4& objToView, float& nearZ,
                float& farZ);

}  // namespace clhair
