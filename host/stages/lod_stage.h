// lod_stage.h — binds and launches the LOD pre-pass and the scan (kernels/lod.cl), then
// reads back the 4-byte strand total that sizes the strand dispatch (DESIGN.md, Atomics
// and dispatch sizing: read-back).
#pragma once

#include <cstdint>

#include "stages/dispatch.h"

namespace clhair {

class LodStage {
 public:
  static constexpr int kScanWorkGroup = 256;
  explicit LodStage(Device::Impl& dev);
  struct Params {
    const cl::Buffer* groom;     // ClhGroomGpu
    const cl::Buffer* view;      // ClhViewGpu
    const cl::Buffer* bundles;   // ClhBundle[bundleCount]
    const cl::Buffer* vertices;  // ClhMeshVertex[layers * vertices]
    float reach;                 // largest styling offset, object units
    cl::Buffer* lod;             // ClhLodRecord[bundleCount]
    cl::Buffer* counts;          // uint[clh_lod_counts_length(bundleCount)] = 2 * bundleCount
    cl::Buffer* offsets;         // uint[clh_lod_offsets_length(bundleCount)] = bundleCount + 2
    std::uint32_t bundleCount;
  };
  // Enqueues both kernels; the drawn total stays on the device in
  // offsets[clh_lod_drawn_total_at(bundleCount)] (layout: gpu_types.h).
  void enqueue(const Params& p, Profiler* profiler);
  // Blocking 4-byte read of the total (read-back sizing).
  std::uint32_t readTotal(const Params& p);

 private:
  Device::Impl& dev_;
  cl::Kernel lod_;
  cl::Kernel scan_;
};

}  // namespace clhair
