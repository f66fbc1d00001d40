// ao_stage.h — binds and launches the ambient-occlusion bake (kernels/ao.cl): exported
// strands are splatted into a density grid of fibre extinction, then every hair-mesh
// layer vertex averages the visibility of 64 directions through it. A groom without layer
// vertices (a strand file) gets the same visibility at every voxel centre instead: its AO
// field, which the shading reads at the shaded point (kernels/common/ao_field.h). The
// kernels are built on first use (scenes whose meshes carry AO never compile them).
#pragma once

#include <cstdint>
#include <vector>

#include "cl/dispatch.h"

namespace clhair {

// A groom's AO field on the device: visibility per voxel centre, x fastest.
struct AoField {
  cl::Buffer values;        // float per voxel; with light diffused through the groom (flags 3)
                            // three more planes of a voxel's scattered radiance, r, g and b
  cl_float4 lo{};           // xyz: object-space corner of voxel (0, 0, 0), w: voxel size
  cl_uint4 dims{};          // voxels per axis
  cl_uint flags = 1;        // 1: AO; 3: AO and diffused light (ClhVisibilityGpu.ao_dims[3])
  std::vector<float> host;  // the AO per voxel, as on the device
  std::uint64_t voxels() const { return std::uint64_t(dims.s[0]) * dims.s[1] * dims.s[2]; }
  std::uint64_t floats() const { return voxels() * ((flags & 2u) ? 4u : 1u); }
};

class AoStage {
 public:
  explicit AoStage(Device::Impl& dev);
  struct Grid {
    cl_float4 lo;   // xyz: the grid's corner, w: voxel size
    cl_uint4 dims;  // cells per axis
    float scale;    // extinction added per unit of strand length in a cell
  };
  struct Strands {  // exported strands: CLH_MAX_CONTROL_POINTS slots per strand
    const cl::Buffer* points = nullptr;
    const cl::Buffer* counts = nullptr;
    std::uint32_t total = 0;
  };
  struct Mesh {  // the hair mesh whose vertices receive AO
    const cl::Buffer* vertices = nullptr;
    const cl::Buffer* bundles = nullptr;
    std::uint32_t vertexTotal = 0, bundleCount = 0, rootVertices = 0;
  };
  // AO per layer vertex (1 = open).
  std::vector<float> bake(const Strands& strands, const Grid& grid, const Mesh& mesh);
  // The AO of every voxel centre of `grid` (ao_field), from a density grid already splatted
  // (uint per voxel, fixed point as ao_voxelize writes it; grid.scale is not read).
  std::vector<float> field(const std::vector<std::uint32_t>& density, const Grid& grid);

 private:
  Device::Impl& dev_;
  cl::Kernel clear_, voxelize_, bake_, field_;
};

}  // namespace clhair
