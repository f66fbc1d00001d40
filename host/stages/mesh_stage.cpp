// mesh_stage.cpp — see mesh_stage.h.
#include "stages/mesh_stage.h"

namespace clhair {

MeshStage::MeshStage(Device::Impl& dev) : dev_(dev) {}

void MeshStage::enqueue(const Params& p, Profiler* profiler) {
  const Geometry& g = p.geometry;
  if (g.triangleCount == 0) return;
  if (!raster_()) {  // built with the first scene that has triangles
    clear_ = dev_.kernel("clear.cl", "clear_words");
    raster_ = dev_.kernel("mesh.cl", "mesh_raster");
    resolve_ = dev_.kernel("mesh.cl", "mesh_resolve");
  }
  const std::uint64_t pixels = p.target.pixels();
  const std::uint64_t vertexBytes = std::uint64_t(g.vertexCount) * 4 * sizeof(float);
  const std::uint64_t triangleBytes = std::uint64_t(g.triangleCount) * 4 * sizeof(cl_uint);
  KernelArgs(clear_, "mesh")
      .buffer("mesh depth words", *p.words, pixels * sizeof(cl_ulong))
      .value("value", ~cl_ulong(0))
      .value("count", static_cast<cl_ulong>(pixels));
  dispatch(dev_, clear_, "mesh", cl::NDRange(pixels), cl::NDRange(256), profiler);

  KernelArgs(raster_, "mesh")
      .buffer("view", *p.target.view, sizeof(gpu::ClhViewGpu))
      .buffer("vertices", *g.vertices, vertexBytes)
      .buffer("triangles", *g.triangles, triangleBytes)
      .value("triangle count", static_cast<cl_uint>(g.triangleCount))
      .value("vertex count", static_cast<cl_uint>(g.vertexCount))
      .buffer("mesh depth words", *p.words, pixels * sizeof(cl_ulong));
  dispatch(dev_, raster_, "mesh", cl::NDRange(g.triangleCount), cl::NDRange(64), profiler);

  KernelArgs a(resolve_, "mesh");
  a.buffer("scene", *p.lighting.scene, sizeof(gpu::ClhSceneGpu))
      .buffer("view", *p.target.view, sizeof(gpu::ClhViewGpu))
      .buffer("vertices", *g.vertices, vertexBytes)
      .buffer("normals", *g.normals, vertexBytes)
      .buffer("triangles", *g.triangles, triangleBytes)
      .buffer("colours", *g.colors, std::uint64_t(g.colorCount) * 4 * sizeof(float))
      .value("triangle count", static_cast<cl_uint>(g.triangleCount))
      .value("vertex count", static_cast<cl_uint>(g.vertexCount))
      .value("colour count", static_cast<cl_uint>(g.colorCount));
  bindLightsAndShadows(a, p.lighting);
  a.buffer("environment SH", *p.lighting.env.sh, CLH_ENV_SH_FLOATS * sizeof(float))
      .buffer("mesh depth words", *p.words, pixels * sizeof(cl_ulong))
      .buffer("colour", *p.color, pixels * 4 * sizeof(float))
      .buffer("depth", *p.depth, pixels * sizeof(float))
      .value("shade", static_cast<cl_uint>(p.shade ? 1 : 0));
  dispatch(dev_, resolve_, "mesh", cl::NDRange(p.target.width, p.target.height), cl::NDRange(8, 8),
           profiler);
}

}  // namespace clhair
