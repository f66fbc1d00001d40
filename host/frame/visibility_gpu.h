// visibility_gpu.h — the shading pass's baked-visibility inputs on the device
// (Renderer::Impl): each bake's spherical-harmonics table, uploaded on first use and kept
// with the bake, one ClhVisibilityGpu record per groom draw of the frame and a one-cell
// table for draws without a bake. The record also places the groom's AO field (strand
// files, host/groom/ao_field.h), which the draw's inputs hold. Records are written when a frame is
// planned, so every draw has its own and the shading passes of one frame never see another's.
#pragma once

#include <deque>
#include <map>
#include <memory>
#include <vector>

#include "cl/device_impl.h"
#include "clhair/scene.h"
#include "stages/ao_stage.h"

namespace clhair {

class VisibilityGpu {
 public:
  explicit VisibilityGpu(Device::Impl& dev);
  // Draw k's record for instance `gi` (a disabled one when it has no bake or `enabled` is
  // false); the record also says whether LOD strands take the aggregated BCSDF, and where
  // the groom's AO field lies (`ao`: none when null).
  void prepare(std::size_t k, const GroomInstance& gi, bool enabled, bool lodAggregate,
               bool multipleScattering, const AoField* ao);
  struct Inputs {
    const cl::Buffer* record = nullptr;
    const cl::Buffer* table = nullptr;
    std::uint32_t cells = 1;
    const cl::Buffer* aoField = nullptr;  // float per voxel, or a one-float buffer
    std::uint64_t aoFieldVoxels = 1;
  };
  Inputs inputs(std::size_t k) const { return inputs_.at(k); }
  // Every record and table (what the shading passes declare).
  std::vector<const cl::Buffer*> buffers() const;

 private:
  Device::Impl& dev_;
  std::map<const VisibilityBake*, std::pair<std::shared_ptr<const VisibilityBake>, cl::Buffer>>
      tables_;
  std::deque<cl::Buffer> records_;
  std::deque<cl::Buffer> fields_;  // draw k's AO field (a handle: the groom may be released)
  std::deque<std::vector<unsigned char>> sent_;
  std::vector<Inputs> inputs_;
  cl::Buffer none_;
};

}  // namespace clhair
