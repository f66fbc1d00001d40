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
//
// Path mode (the constructor's flag) adds opaque surfaces and tracePaths(): a CPU path
// tracer through the same curves, the reference with scattering between fibres
// (path_trace.cpp; docs/path-reference.md).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "clhair/gpu_types.h"
#include "clhair/strand_groom.h"

namespace clhair {

class StrandTracer {
 public:
  explicit StrandTracer(bool pathMode = false);
  ~StrandTracer();
  StrandTracer(const StrandTracer&) = delete;
  StrandTracer& operator=(const StrandTracer&) = delete;

  // Adds groom draw `draw` (its index in the scene's groom list): `strands` in object
  // space, placed by `params` as prepared for this camera (obj_to_view, obj_to_world,
  // strand_width, look). Before commit() only.
  void addGroom(std::uint32_t draw, const StrandSet& strands, const gpu::ClhGroomGpu& params);
  // Path mode only, before commit(): opaque Lambertian surfaces in view space (linear
  // albedo): a sphere, and triangles (xyz per vertex, three indices per triangle).
  void addSphere(const float centre[3], float radius, const float albedo[3]);
  void addTriangles(const std::vector<float>& positions, const std::vector<std::uint32_t>& indices,
                    const float albedo[3]);
  // Builds the acceleration structure.
  void commit();

  // One ray per pixel through (i + 1/2, j + 1/2) of `view` (its intrinsics and size),
  // ending at depth[pixel] (view z; +inf where nothing is drawn). Keeps the nearest hit.
  void trace(const gpu::ClhViewGpu& view, const std::vector<float>& depth);
  // Words of groom draw `draw` where the last trace's nearest hit lies on it, the empty
  // word elsewhere; `params`' depth mapping is used (the frame's own record).
  void centreLayer(std::uint32_t draw, const gpu::ClhGroomGpu& params,
                   std::vector<std::uint64_t>& words) const;
  // Path mode: the path-traced image (PathSetup in this header's second half).
  struct PathLight {
    bool point = true;
    float pos[3] = {0.0f, 0.0f, 0.0f};  // view space: a point light's position, or the unit
                                        // direction toward a directional light
    float rgb[3] = {0.0f, 0.0f, 0.0f};  // colour x intensity (point lights: at distance 1)
  };
  struct PathSetup {
    gpu::ClhViewGpu view{};  // intrinsics, size and world_to_view (tangents to view space)
    std::vector<PathLight> lights;
    float ambient[3] = {0.0f, 0.0f, 0.0f};     // radiance of every path that leaves the scene
    float background[3] = {0.0f, 0.0f, 0.0f};  // what a camera ray that meets nothing sees
    int spp = 16;                              // paths per pixel, 1..65536
    // Scattering events per path: light is gathered from the lights at events 1..maxEvents,
    // and the path continues past event k only when k < maxEvents (1: direct light at the
    // first fibre or surface seen, no ambient, no interreflection).
    int maxEvents = 64;
    int rouletteAfter = 3;  // Russian roulette from this event on
    std::uint32_t seed = 1;
  };
  struct PathImage {
    std::vector<float> rgb;    // 3 per pixel, mean radiance of the pixel's paths
    std::vector<float> depth;  // view depth of the nearest surface any of its camera rays met
    std::uint64_t rays = 0;    // Embree queries: camera, continuation and shadow rays
    // [N]: the radiance paths brought back from the environment (ambient or background, mean
    // of the channels) after N scattering events, summed over the pixels, per sample. With
    // no lights it sums to the image's mean times its pixels; the sums' order across threads
    // varies, so unlike the image it may differ in its last bits between runs.
    std::vector<double> escapedAfter;
  };
  PathImage tracePaths(const PathSetup& setup) const;

  // Pixels of the last trace that hit a strand.
  std::uint64_t hits() const;

  std::uint64_t strands() const;
  std::uint64_t segments() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace clhair
