// point_stage.h — the passes of per-point shading around the shading itself
// (kernels/points.cl): the marking of the points whose segments own a visible sample, their
// ranks (the compaction: a marked point's slot is the rank of its bit), and the resolve of
// every sample's colour from its segment's two shaded points. The point pass that writes
// the marked points' inputs is the strand kernels' (StrandRaster::points), the shading of
// the listed points ShadeStage::enqueuePoints.
#pragma once

#include <cstdint>
#include <map>

#include "stages/clear_stage.h"
#include "stages/stage_inputs.h"
#include "stages/strand_stage.h"

namespace clhair {

class PointStage {
 public:
  explicit PointStage(Device::Impl& dev);

  // How many bitmap words, scan blocks and records a groom's lists need: `space` points
  // (GroomGpu::pointSpace), at most two marked points per sample of the `boxPixels` pixels
  // the groom can draw into at `msaa` samples.
  struct Sizes {
    std::uint32_t words = 0, blocks = 0, capacity = 0;
    std::uint64_t bitsBytes() const { return std::uint64_t(words) * 4; }
    std::uint64_t blocksBytes() const { return (std::uint64_t(blocks) + 1) * 4; }
    std::uint64_t offsetsBytes() const { return (std::uint64_t(words) + 1) * 4; }
    std::uint64_t recordsBytes() const;
    std::uint64_t colorsBytes() const { return std::uint64_t(capacity) * 16 + 16; }
  };
  // Throws when the point space does not fit the identity word's 32 bits.
  static Sizes sizes(std::uint64_t space, std::size_t boxPixels, int msaa);

  // One groom's lists (buffers owned by the frame's graph).
  struct Lists {
    Sizes sizes;
    cl::Buffer* bits = nullptr;
    cl::Buffer* blocks = nullptr;
    cl::Buffer* offsets = nullptr;
    cl::Buffer* records = nullptr;
    cl::Buffer* colors = nullptr;
    // what the strand kernels' point pass reads and writes
    PointLists pass() const { return {bits, offsets, records, sizes.words, sizes.capacity}; }
  };

  // Clears the bitmap and marks both points of every sample's segment over `box` (the
  // groom's screen box, clipped) of `target`'s G-buffer (msaa sample and identity layers).
  void mark(const ViewTarget& target, const cl::Buffer& gbuffer, int layers, int msaa,
            const PixelRect& box, const Lists& lists, Profiler* profiler);
  // The slots: blocks' counts, their scan, every word's rank (the total at [words]).
  void rank(const Lists& lists, Profiler* profiler);
  // Each sample's colour from its segment's shaded points into `hair` (premultiplied RGBA,
  // alpha the share of samples hit) over `box`.
  void resolve(const ViewTarget& target, const cl::Buffer& gbuffer, int layers, int msaa,
               const PixelRect& box, const Lists& lists, cl::Buffer& hair, Profiler* profiler);

 private:
  cl::Kernel& kernel(const char* name, int msaa);
  Device::Impl& dev_;
  ClearStage clear_;
  std::map<std::pair<std::string, int>, cl::Kernel> kernels_;
};

}  // namespace clhair
