// strand_stage.h — binds and launches strands_raster / strands_export (kernels/strands.cl):
// one work-group of 32 lanes per strand, sized from the LOD pre-pass total. Very large
// totals are split into several dispatches (strand_base) to stay within every driver's
// limits on global size.
#pragma once

#include <cstdint>

#include "stages/dispatch.h"

namespace clhair {

class StrandStage {
 public:
  static constexpr std::uint32_t kLanes = 32;            // one logical sub-group
  static constexpr std::uint32_t kMaxGroupsPerDispatch = 1u << 22;
  explicit StrandStage(Device::Impl& dev);

  struct Inputs {
    const cl::Buffer* groom;     // ClhGroomGpu
    const cl::Buffer* bundles;   // ClhBundle[]
    const cl::Buffer* vertices;  // ClhMeshVertex[]
    const cl::Buffer* lod;       // uint4 per bundle
    const cl::Buffer* offsets;   // uint, bundles + 1
    const cl::Buffer* rootsQuad; // float2[rootSetSize]
    const cl::Buffer* rootsTri;  // float2[rootSetSize]
    std::uint32_t strands;       // total from the LOD pass
  };
  void raster(const Inputs& in, const cl::Buffer& view, const cl::Buffer& sceneDepth,
              cl::Buffer& center, Profiler* profiler);
  // points/tangents: float4 * CLH_MAX_CONTROL_POINTS per strand; counts: uint per strand.
  void exportStrands(const Inputs& in, cl::Buffer& points, cl::Buffer& tangents, cl::Buffer& counts,
                     Profiler* profiler);

 private:
  Device::Impl& dev_;
  cl::Kernel raster_;
  cl::Kernel export_;
};

}  // namespace clhair
