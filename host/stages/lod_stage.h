// lod_stage.h — binds and launches the LOD pre-pass and the scan (kernels/lod.cl) of a
// hair mesh: one LOD record per bundle, the strand counts, and their exclusive scan with
// the drawn and visible totals after the last bundle (the layout is in
// kernels/include/clhair/gpu_types.h). GroomGpu::readTotal is the blocking 4-byte read that sizes
// a read-back strand dispatch (DESIGN.md, Atomics and dispatch sizing).
#pragma once

#include <cstdint>

#include "cl/dispatch.h"

namespace clhair {

class LodStage {
 public:
  static constexpr int kScanWorkGroup = 256;
  explicit LodStage(Device::Impl& dev);
  struct Params {
    const cl::Buffer* groom = nullptr;     // ClhGroomGpu
    const cl::Buffer* view = nullptr;      // ClhViewGpu
    const cl::Buffer* bundles = nullptr;   // ClhBundle[bundleCount]
    const cl::Buffer* vertices = nullptr;  // ClhMeshVertex[vertexTotal]
    float reach = 0.0f;                    // largest styling offset, view units
    cl::Buffer* lod = nullptr;             // ClhLodRecord[bundleCount]
    cl::Buffer* counts = nullptr;          // uint[clh_lod_counts_length(bundleCount)]
    cl::Buffer* offsets = nullptr;         // uint[clh_lod_offsets_length(bundleCount)]
    std::uint32_t bundleCount = 0;
    std::size_t vertexTotal = 0;
  };
  // Enqueues both kernels; the drawn total stays on the device in
  // offsets[clh_lod_drawn_total_at(bundleCount)] (layout: gpu_types.h).
  void enqueue(const Params& p, Profiler* profiler);

 private:
  Device::Impl& dev_;
  cl::Kernel lod_;
  cl::Kernel scan_;
};

// Binds and launches the scan of `n` bundles' counts into their offsets (gpu_types.h).
void enqueueScan(Device::Impl& dev, cl::Kernel& scan, const cl::Buffer& counts,
                 const cl::Buffer& offsets, std::uint32_t n, Profiler* profiler);

}  // namespace clhair
