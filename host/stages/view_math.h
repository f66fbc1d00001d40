// view_math.h — cameras to the device's view records (ClhViewGpu of gpu_types.h): the
// world-to-view matrix of a look-at camera, the pinhole intrinsics of a target size, and
// the depth range a groom's bounds span in a view (its G-buffer depth mapping) and the
// screen box they project to.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "clhair/gpu_types.h"
#include "clhair/scene.h"
#include "io/faint_groom.h"
#include "stages/stage_inputs.h"

namespace clhair {

void store4(float* dst, const glm::vec3& v, float w);
// Row-major 3x4 from the upper 3x4 of a column-major glm matrix.
void storeMat34(float* dst, const glm::mat4& m);

glm::mat4 worldToView(const Camera& cam);
// The view record of `cam` over a width x height target, one sample per pixel.
gpu::ClhViewGpu makeView(const Camera& cam, int width, int height);
// The pixels of a view record, for the faint-groom estimate (io/faint_groom.h).
FaintView faintView(const gpu::ClhViewGpu& v);

// Depth range of the view-space box of object bounds [lo, hi]; false when all of it lies
// behind the camera.
bool depthRange(const glm::vec3& lo, const glm::vec3& hi, const glm::mat4& objToView, float& nearZ,
                float& farZ);

// The pixels of `view`'s image that a groom whose object bounds [lo, hi] are placed by
// objToView can draw into: the pixels holding the hull of the box's eight projected corners
// (pinhole projection as raster_core.h's: x = cx + fx X / Z, y = cy - fy Y / Z), `margin`
// more on every side, clipped to the image. Every point of the box projects into the hull
// when all corners lie in front of the camera; when one lies closer than kScreenBoxNearZ
// (the strand pass clips at the near plane, the projection has no bound) it is the whole
// image. Empty when the hull misses the image.
constexpr float kScreenBoxNearZ = 1e-3f;
// The margin of a groom's screen box in the frame: the strand pass writes a pixel a
// strand's line touches (the conservative layer, the curve layers) or whose sample lies
// within half the hit diameter of the line, at most CLH_MAX_HIT_DIAMETER / 2 = 1.5 px
// across it, 2.2 px along the minor axis of the walk (coverage trapezoids: 1.5 px); a
// point's pixel is the floor of its coordinates, so 3 pixels hold every write, and one more
// covers the host's and the device's different rounding of the projection.
constexpr int kScreenBoxMargin = 4;
PixelRect screenBox(const glm::vec3& lo, const glm::vec3& hi, const glm::mat4& objToView,
                    const gpu::ClhViewGpu& view, int margin);

}  // namespace clhair
