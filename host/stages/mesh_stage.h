// mesh_stage.h — binds and launches the triangle-mesh kernels (kernels/mesh.cl): the
// scene's meshes into the target's depth (and colour), after the analytic primitives of
// OpaqueStage, from the camera or from a light.
//
// enqueue clears the per-pixel word buffer, rasterizes one work-item per triangle with
// 64-bit atom_min, then resolves one work-item per pixel. The word buffer must hold at
// least width x height words; the geometry buffers hold world-space vertices and normals
// (float4), triangles (uint4: three vertex indices and the colour index) and colours.
#pragma once

#include <cstdint>

#include "stages/dispatch.h"

namespace clhair {

class MeshStage {
 public:
  explicit MeshStage(Device::Impl& dev);
  struct Geometry {
    const cl::Buffer* vertices;   // float4 per vertex, world space
    const cl::Buffer* normals;    // float4 per vertex, world space (zero: use the face's)
    const cl::Buffer* triangles;  // uint4 per triangle
    const cl::Buffer* colors;     // float4 per mesh instance
    std::uint32_t vertexCount, triangleCount, colorCount;
  };
  struct Params {
    const cl::Buffer* scene;    // ClhSceneGpu
    const cl::Buffer* view;     // ClhViewGpu
    Geometry geometry;
    const cl::Buffer* lights;   // ClhLightGpu[]
    const cl::Buffer* shadows;  // ClhShadowGpu[CLH_MAX_SHADOWS]
    const cl::Buffer* shadowOpaque, *shadowHair, *shadowOpacity;  // deep opacity maps
    const cl::Buffer* envSh;    // environment SH (a dummy when none)
    cl::Buffer* words;          // ulong per pixel, scratch
    cl::Buffer* color;          // float4 per pixel
    cl::Buffer* depth;          // float per pixel, the analytic scene's depth on entry
    int width, height;
    bool shade = true;          // false: depth only (a light's view)
  };
  void enqueue(const Params& p, Profiler* profiler);

 private:
  Device::Impl& dev_;
  cl::Kernel clear_, raster_, resolve_;
};

}  // namespace clhair
