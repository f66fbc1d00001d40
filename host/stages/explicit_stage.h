// explicit_stage.h — binds and launches the passes of an explicit (stored-strand) groom:
// lod_chunks + scan_bundles (kernels/lod.cl) over the chunk table, then
// strands_explicit_raster / _persistent / _opacity / _export (kernels/strands_explicit.cl),
// one work-group of 32 lanes per strand. Kernels are built on first use, so renderers that
// never meet a strand file compile nothing extra. The strand dispatch follows the chosen
// sizing mode (read-back, over-launch, persistent grid) like StrandStage; very large
// launches are split (strand_base) to stay within every driver's global-size limits.
#pragma once

#include <cstdint>
#include <map>

#include "stages/dispatch.h"
#include "stages/strand_stage.h"

namespace clhair {

class ExplicitStage {
 public:
  explicit ExplicitStage(Device::Impl& dev);

  // The device tables of one groom (host/groom/explicit_data.h).
  struct Inputs {
    const cl::Buffer* groom;          // ClhGroomGpu (bundle_count = chunks)
    const cl::Buffer* points;         // float4[pointCount]
    const cl::Buffer* strandOffsets;  // uint[strandCount + 1]
    const cl::Buffer* uv;             // uint[strandCount] when hasUv, else any 1-word buffer
    const cl::Buffer* chunks;         // uint4[chunkCount]
    const cl::Buffer* chunkBounds;    // float4[2 * chunkCount]
    cl::Buffer* lod;                  // uint4[chunkCount]
    cl::Buffer* counts;               // uint[2 * chunkCount]
    cl::Buffer* offsets;              // uint[chunkCount + 2]
    std::uint32_t chunkCount, strandCount, pointCount;
    bool hasUv;
  };

  // LOD records of every chunk for `view` and their scan; the total stays on the device.
  void lod(const Inputs& in, const cl::Buffer& view, Profiler* profiler);
  // Blocking 4-byte read of the strands to draw (read-back sizing).
  std::uint32_t readTotal(const Inputs& in);
  // r.strands: ReadBack the exact total, otherwise an upper bound (the groom's strands).
  void raster(const Inputs& in, const StrandStage::Raster& r, Profiler* profiler);
  void opacity(const Inputs& in, const cl::Buffer& lightView, const cl::Buffer& opaqueDepth, const cl::Buffer& shadow,
               const cl::Buffer& hairDepth, cl::Buffer& opacity, std::uint32_t strands, Profiler* profiler);
  // outPoints/outTangents: float4[pointCount]; outCounts: uint[strandCount] (0 = not drawn).
  void exportStrands(const Inputs& in, std::uint32_t strands, cl::Buffer& outPoints, cl::Buffer& outTangents,
                     cl::Buffer& outCounts, Profiler* profiler);

 private:
  cl::Kernel& kernel(const std::string& name, const std::string& file, const std::string& options);
  void bindTables(cl::Kernel& k, const Inputs& in);
  Device::Impl& dev_;
  std::map<std::string, cl::Kernel> kernels_;
};

}  // namespace clhair
