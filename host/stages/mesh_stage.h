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

#include "stages/stage_inputs.h"

namespace clhair {

class MeshStage {
 public:
  explicit MeshStage(Device::Impl& dev);
  struct Geometry {
    const cl::Buffer* vertices = nullptr;   // float4 per vertex, world space
    const cl::Buffer* normals = nullptr;    // float4 per vertex, world space (zero: use the face's)
    const cl::Buffer* triangles = nullptr;  // uint4 per triangle
    const cl::Buffer* colors = nullptr;     // float4 per mesh instance
    std::uint32_t vertexCount = 0, triangleCount = 0, colorCount = 0;
  };
  struct Params {
    ViewTarget target;
    LightingInputs lighting;
    Geometry geometry;
    cl::Buffer* words = nullptr;  // ulong per pixel, scratch
    cl::Buffer* color = nullptr;  // float4 per pixel
    cl::Buffer* depth = nullptr;  // float per pixel, the analytic scene's depth on entry
    bool shade = true;            // false: depth only (a light's view)
  };
  void enqueue(const Params& p, Profiler* profiler);

 private:
  Device::Impl& dev_;
  cl::Kernel clear_, raster_, resolve_;
};

}  // namespace clhair
