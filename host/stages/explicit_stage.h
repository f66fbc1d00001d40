// explicit_stage.h — binds and launches the passes of an explicit (stored-strand) groom:
// lod_chunks + scan_bundles (kernels/lod.cl) over the chunk table, then
// strands_explicit_raster / _persistent / _opacity / _export (kernels/strands_explicit.cl),
// strands in the device's launch shape. Kernels are built on first use, so renderers that
// never meet a strand file compile nothing extra. The strand dispatch follows the chosen
// sizing mode (read-back, over-launch, persistent grid) like StrandStage; very large
// launches are split (strand_base) to stay within every driver's global-size limits.
#pragma once

#include <cstdint>
#include <map>

#include "stages/strand_stage.h"

namespace clhair {

class ExplicitStage {
 public:
  explicit ExplicitStage(Device::Impl& dev);

  // The device tables of one groom (host/groom/explicit_data.h) and one instance's LOD
  // records and scan.
  struct Inputs {
    const cl::Buffer* groom = nullptr;          // ClhGroomGpu (bundle_count = chunks)
    const cl::Buffer* points = nullptr;         // float4[pointWords]
    const cl::Buffer* strandOffsets = nullptr;  // uint[strandCount + 1]
    const cl::Buffer* uv = nullptr;      // uint[strandCount] when hasUv, else any 1-word buffer
    const cl::Buffer* chunks = nullptr;  // uint4[chunkCount]
    const cl::Buffer* chunkBounds = nullptr;  // float4[2 * chunkCount]
    const cl::Buffer* kids = nullptr;         // ClhChildrenGpu (count 0: no children)
    const cl::Buffer* neighbours = nullptr;   // uint[strandCount * kids.neighbours], or 1 word
    std::uint64_t neighbourWords = 1;
    cl::Buffer* lod = nullptr;      // ClhLodRecord[chunkCount]
    cl::Buffer* counts = nullptr;   // uint[clh_lod_counts_length(chunkCount)]
    cl::Buffer* offsets = nullptr;  // uint[clh_lod_offsets_length(chunkCount)]
    std::uint32_t chunkCount = 0, strandCount = 0, pointCount = 0;  // stored strands
    std::uint32_t children = 0;  // per stored strand (ClhChildrenGpu::count)
    std::size_t pointWords = 0;  // float4 in `points` (file colours follow the points)
    bool hasUv = false;
  };

  // LOD records of every chunk for `view` and their scan; the total stays on the device.
  void lod(const Inputs& in, const cl::Buffer& view, Profiler* profiler);
  void raster(const Inputs& in, const StrandRaster& r, Profiler* profiler);
  void opacity(const Inputs& in, const OpacityDraw& o, std::uint32_t strands, Profiler* profiler);
  // The motion pass: `previous` holds the previous frame's points (pointCount float4, this
  // groom's order); r is the raster pass just run.
  void motion(const Inputs& in, const cl::Buffer& previous, const MotionDraw& m,
              const StrandRaster& r, Profiler* profiler);
  // outPoints/outTangents: float4[pointCount * (1 + children)]; outCounts:
  // uint[strandCount * (1 + children)] (0 = not drawn); child c of stored strand s at
  // s + c * strandCount, its points after c copies of the stored points.
  void exportStrands(const Inputs& in, std::uint32_t strands, cl::Buffer& outPoints,
                     cl::Buffer& outTangents, cl::Buffer& outCounts, Profiler* profiler);

 private:
  cl::Kernel& kernel(const std::string& name, const std::string& file, const std::string& options);
  // groom, view, the tables, records, counts and children: the first 13 arguments of every
  // kernel
  KernelArgs bindTables(cl::Kernel& k, const Inputs& in, const cl::Buffer& view,
                        const std::string& stage, std::uint64_t viewBytes);
  Device::Impl& dev_;
  std::map<std::string, cl::Kernel> kernels_;
};

}  // namespace clhair
