// ao_stage.h — binds and launches the ambient-occlusion bake (kernels/ao.cl): exported
// strands are splatted into a density grid of fibre extinction, then every hair-mesh
// layer vertex averages the visibility of 64 directions through it. The kernels are
// built on first use (scenes whose meshes carry AO never compile them).
#pragma once

#include <cstdint>
#include <vector>

#include "cl/dispatch.h"

namespace clhair {

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

 private:
  Device::Impl& dev_;
  cl::Kernel clear_, voxelize_, bake_;
};

}  // namespace clhair
