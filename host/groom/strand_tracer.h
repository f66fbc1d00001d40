// strand_tracer.h — the strands of a scene's grooms as round curves in an Embree scene,
// traced one ray per pixel: the independent visibility of Renderer::renderReference.
//
// Each groom instance's strands, as the strand kernels draw them (GroomGpu::exportStrands:
// points, tangents, styling w, AO, root uv and file colour), become Embree round linear
// curves in the camera's view space, segment for segment the polyline the rasterizer
// walks, with the fibre's true world width (the groom's strand width, or the file's
// per-point thickness scaled like the points) and no minimum or maximum in pixels.
// trace() shoots one ray through every pixel centre of a (sub-pixel shifted) view, from the
// rasterizer's near plane to the opaque scene's depth there, on all hardware threads;
// centreLayer() turns the hits that landed on one groom into the 64-bit G-buffer words the
// strand pass writes (gpu_types.h: depth code, octahedral world tangent, u, v, w, AO, or
// the file colour in u, v and AO), so the same shading and compositing kernels use them.
// The words carry the attributes interpolated linearly at the hit along its segment.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "clhair/gpu_types.h"
#include "clhair/strand_groom.h"

namespace clhair {

class StrandTracer {
 public:
  StrandTracer();
  ~StrandTracer();
  StrandTracer(const StrandTracer&) = delete;
  StrandTracer& operator=(const StrandTracer&) = delete;

  // Adds groom draw `draw` (its index in the scene's groom list): `strands` in object
  // space, placed by `params` as prepared for this camera (obj_to_view, obj_to_world,
  // strand_width, look). Before commit() only.
  void addGroom(std::uint32_t draw, const StrandSet& strands, const gpu::ClhGroomGpu& params);
  // Builds the acceleration structure.
  void commit();

  // One ray per pixel through (i + 1/2, j + 1/2) of `view` (its intrinsics and size),
  // ending at depth[pixel] (view z; +inf where nothing is drawn). Keeps the nearest hit.
  void trace(const gpu::ClhViewGpu& view, const std::vector<float>& depth);
  // Words of groom draw `draw` where the last trace's nearest hit lies on it, the empty
  // word elsewhere; `params`' depth mapping is used (the frame's own record).
  void centreLayer(std::uint32_t draw, const gpu::ClhGroomGpu& params,
                   std::vector<std::uint64_t>& words) const;
  // Pixels of the last trace that hit a strand.
  std::uint64_t hits() const;

  std::uint64_t strands() const;
  std::uint64_t segments() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace clhair
