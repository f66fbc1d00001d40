// ao_stage.cpp — see ao_stage.h.
#include "stages/ao_stage.h"

#include "cl/buffers.h"
#include "clhair/gpu_types.h"

namespace clhair {

AoStage::AoStage(Device::Impl& dev) : dev_(dev) {}

std::vector<float> AoStage::bake(const Strands& s, const Grid& grid, const Mesh& mesh) {
  if (!clear_()) {
    clear_ = dev_.kernel("ao.cl", "ao_clear");
    voxelize_ = dev_.kernel("ao.cl", "ao_voxelize");
    bake_ = dev_.kernel("ao.cl", "ao_bake");
  }
  const std::size_t cells = std::size_t(grid.dims.s[0]) * grid.dims.s[1] * grid.dims.s[2];
  cl::Buffer density = makeBuffer<cl_uint>(dev_, "the AO density grid", cells);
  cl::Buffer out = makeBuffer<cl_float>(dev_, "baked AO", mesh.vertexTotal);
  KernelArgs(clear_, "ao")
      .buffer("density", density, cells * sizeof(cl_uint))
      .value("cells", static_cast<cl_uint>(cells));
  dispatch(dev_, clear_, "ao", cl::NDRange(cells), cl::NDRange(64), nullptr);
  const std::uint64_t slots = std::uint64_t(s.total) * CLH_MAX_CONTROL_POINTS;
  KernelArgs(voxelize_, "ao")
      .buffer("points", *s.points, slots * 4 * sizeof(float))
      .buffer("point counts", *s.counts, std::uint64_t(s.total) * sizeof(cl_uint))
      .value("strands", static_cast<cl_uint>(s.total))
      .value("grid corner", grid.lo)
      .value("grid size", grid.dims)
      .value("scale", grid.scale)
      .buffer("density", density, cells * sizeof(cl_uint));
  dispatch(dev_, voxelize_, "ao", cl::NDRange(slots), cl::NDRange(64), nullptr);
  KernelArgs(bake_, "ao")
      .buffer("vertices", *mesh.vertices,
              std::uint64_t(mesh.vertexTotal) * sizeof(gpu::ClhMeshVertex))
      .value("vertex total", static_cast<cl_uint>(mesh.vertexTotal))
      .buffer("bundles", *mesh.bundles, std::uint64_t(mesh.bundleCount) * sizeof(gpu::ClhBundle))
      .value("bundle count", static_cast<cl_uint>(mesh.bundleCount))
      .value("root vertices", static_cast<cl_uint>(mesh.rootVertices))
      .value("grid corner", grid.lo)
      .value("grid size", grid.dims)
      .buffer("density", density, cells * sizeof(cl_uint))
      .buffer("AO", out, std::uint64_t(mesh.vertexTotal) * sizeof(float));
  dispatch(dev_, bake_, "ao", cl::NDRange(mesh.vertexTotal), cl::NDRange(64), nullptr);
  std::vector<float> ao(mesh.vertexTotal, 1.0f);
  readBack(dev_, "baked AO", out, ao.data(), ao.size());
  return ao;
}

std::vector<float> AoStage::field(const std::vector<std::uint32_t>& density, const Grid& grid) {
  if (!field_()) field_ = dev_.kernel("ao.cl", "ao_field");
  const std::size_t cells = std::size_t(grid.dims.s[0]) * grid.dims.s[1] * grid.dims.s[2];
  if (density.size() != cells) throw Error("AO field: the density grid does not match its size");
  cl::Buffer d = makeBuffer<cl_uint>(dev_, "the AO density grid", cells, density.data());
  cl::Buffer out = makeBuffer<cl_float>(dev_, "the AO field", cells);
  KernelArgs(field_, "ao")
      .value("grid corner", grid.lo)
      .value("grid size", grid.dims)
      .buffer("density", d, cells * sizeof(cl_uint))
      .buffer("AO", out, cells * sizeof(float));
  dispatch(dev_, field_, "ao", cl::NDRange((cells + 63) / 64 * 64), cl::NDRange(64), nullptr);
  std::vector<float> ao(cells, 1.0f);
  readBack(dev_, "the AO field", out, ao.data(), ao.size());
  return ao;
}

}  // namespace clhair
