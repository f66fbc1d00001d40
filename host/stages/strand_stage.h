// strand_stage.h — binds and launches strands_raster / strands_export (kernels/strands.cl):
// strands in the device's launch shape (dispatchStrands). The raster kernel is built per MSAA sample count
// (and with counters for statistics runs); the dispatch follows the chosen sizing mode.
#pragma once

#include <cstdint>
#include <map>

#include "stages/dispatch.h"

namespace clhair {

class StrandStage {
 public:
  explicit StrandStage(Device::Impl& dev);

  struct Inputs {
    const cl::Buffer* groom;      // ClhGroomGpu
    const cl::Buffer* bundles;    // ClhBundle[]
    const cl::Buffer* vertices;   // ClhMeshVertex[]
    const cl::Buffer* lod;        // uint4 per bundle
    const cl::Buffer* offsets;    // uint, bundles + 1
    const cl::Buffer* rootsQuad;  // float2[rootSetSize]
    const cl::Buffer* rootsTri;   // float2[rootSetSize]
  };
  struct Raster {
    const cl::Buffer* view;
    const cl::Buffer* sceneDepth;  // float per pixel
    cl::Buffer* gbuffer;           // ulong per pixel, msaa + 1 layers
    cl::Buffer* counters;          // uint[4], written when stats
    int msaa = 1;
    bool stats = false;
    DispatchMode mode = DispatchMode::ReadBack;
    std::uint32_t strands = 0;     // ReadBack: the exact total; otherwise an upper bound
  };
  void raster(const Inputs& in, const Raster& r, Profiler* profiler);
  // points/tangents: float4 * CLH_MAX_CONTROL_POINTS per strand; counts: uint per strand.
  void exportStrands(const Inputs& in, std::uint32_t strands, cl::Buffer& points,
                     cl::Buffer& tangents, cl::Buffer& counts, Profiler* profiler);

 private:
  cl::Kernel& rasterKernel(int msaa, bool stats, bool persistent);
  Device::Impl& dev_;
  std::map<int, cl::Kernel> raster_;
  cl::Kernel export_;
};

}  // namespace clhair
