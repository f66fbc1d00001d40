// mesh_stage.cpp — see mesh_stage.h.
#include "stages/mesh_stage.h"

#include "cl/cl_error.h"
#include "clhair/error.h"

namespace clhair {

MeshStage::MeshStage(Device::Impl& dev)
    : dev_(dev),
      clear_(dev.kernel("clear.cl", "clear_words")),
      raster_(dev.kernel("mesh.cl", "mesh_raster")),
      resolve_(dev.kernel("mesh.cl", "mesh_resolve")) {}

void MeshStage::enqueue(const Params& p, Profiler* profiler) {
  const Geometry& g = p.geometry;
  if (g.triangleCount == 0) return;
  const std::size_t pixels = static_cast<std::size_t>(p.width) * static_cast<std::size_t>(p.height);
  const std::size_t wordBytes =
      clCall("mesh pass: reading the word buffer's size", [&] { return p.words->getInfo<CL_MEM_SIZE>(); });
  if (wordBytes < pixels * sizeof(cl_ulong))
    throw Error("mesh pass: the word buffer holds " + std::to_string(wordBytes / sizeof(cl_ulong)) + " pixels, the " +
                std::to_string(p.width) + "x" + std::to_string(p.height) + " view needs " + std::to_string(pixels));
  clear_.setArg(0, *p.words);
  clear_.setArg(1, ~cl_ulong(0));
  clear_.setArg(2, static_cast<cl_ulong>(pixels));
  dispatch(dev_, clear_, "mesh", cl::NDRange(pixels), cl::NDRange(256), profiler);

  raster_.setArg(0, *p.view);
  raster_.setArg(1, *g.vertices);
  raster_.setArg(2, *g.triangles);
  raster_.setArg(3, static_cast<cl_uint>(g.triangleCount));
  raster_.setArg(4, static_cast<cl_uint>(g.vertexCount));
  raster_.setArg(5, *p.words);
  dispatch(dev_, raster_, "mesh", cl::NDRange(g.triangleCount), cl::NDRange(64), profiler);

  resolve_.setArg(0, *p.scene);
  resolve_.setArg(1, *p.view);
  resolve_.setArg(2, *g.vertices);
  resolve_.setArg(3, *g.normals);
  resolve_.setArg(4, *g.triangles);
  resolve_.setArg(5, *g.colors);
  resolve_.setArg(6, static_cast<cl_uint>(g.triangleCount));
  resolve_.setArg(7, static_cast<cl_uint>(g.vertexCount));
  resolve_.setArg(8, static_cast<cl_uint>(g.colorCount));
  resolve_.setArg(9, *p.lights);
  resolve_.setArg(10, *p.shadows);
  resolve_.setArg(11, *p.shadowOpaque);
  resolve_.setArg(12, *p.shadowHair);
  resolve_.setArg(13, *p.shadowOpacity);
  resolve_.setArg(14, *p.envSh);
  resolve_.setArg(15, *p.words);
  resolve_.setArg(16, *p.color);
  resolve_.setArg(17, *p.depth);
  resolve_.setArg(18, static_cast<cl_uint>(p.shade ? 1 : 0));
  dispatch(dev_, resolve_, "mesh", cl::NDRange(p.width, p.height), cl::NDRange(8, 8), profiler);
}

}  // namespace clhair
