// groom_gpu.cpp — see groom_gpu.h.
#include "groom/groom_gpu.h"

#include "cl/buffers.h"
#include "groom/hair_mesh_gpu.h"
#include "groom/strand_file_gpu.h"

namespace clhair {

GroomInstanceGpu& GroomGpu::instance(std::size_t k) {
  while (instances_.size() <= k) instances_.push_back(makeInstance());
  return *instances_[k];
}

std::uint32_t GroomGpu::readTotal(const GroomInstanceGpu& inst) {
  if (inst.records == 0) return 0;
  std::uint32_t total = 0;
  readBack(dev_, "the strand total", inst.offsets, &total, 1,
           gpu::clh_lod_drawn_total_at(inst.records));
  return total;
}

std::uint64_t GroomGpu::deviceBytes() {
  const GroomInstanceGpu& inst = instance(0);
  std::uint64_t sum = sharedBytes();
  for (const cl::Buffer* b : {&inst.groom, &inst.lod, &inst.counts, &inst.offsets})
    sum += bufferBytes(*b);
  return sum;
}

std::unique_ptr<GroomGpu> makeGroomGpu(const GroomInstance& gi, GroomStages& stages) {
  if (gi.strands) return std::make_unique<StrandFileGpu>(gi.strands, stages);
  if (!gi.mesh) throw Error("groom \"" + gi.name + "\" has neither a hair mesh nor strands");
  return std::make_unique<HairMeshGpu>(gi.mesh, stages, true);
}

}  // namespace clhair
