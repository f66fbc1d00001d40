// groom_gpu.cpp — see groom_gpu.h.
#include "groom/groom_gpu.h"

#include "cl/buffers.h"
#include "groom/hair_mesh_gpu.h"
#include "groom/strand_file_gpu.h"
#include "stages/view_math.h"

namespace clhair {

bool GroomGpu::inFront(const glm::mat4& objToWorld, const glm::mat4& worldToView) const {
  float nearZ = 0.0f, farZ = 0.0f;
  return depthRange(boundsMin(), boundsMax(), worldToView * objToWorld, nearZ, farZ);
}

GroomInstanceGpu& GroomGpu::instance(std::size_t k) {
  while (instances_.size() <= k) instances_.push_back(makeInstance());
  return *instances_[k];
}

std::unique_ptr<GroomInstanceGpu> GroomGpu::newInstance(const std::string& groomName,
                                                        std::uint32_t records,
                                                        const gpu::ClhGroomGpu& params) {
  auto inst = std::make_unique<GroomInstanceGpu>();
  const std::string what = "groom \"" + groomName + "\"";
  inst->params = params;
  inst->records = records;
  inst->groom = makeBuffer<gpu::ClhGroomGpu>(dev_, what + " parameters", 1, &inst->params);
  const auto* bytes = reinterpret_cast<const unsigned char*>(&inst->params);
  inst->sent.assign(bytes, bytes + sizeof(inst->params));
  inst->lod = makeBuffer<gpu::ClhLodRecord>(dev_, what + " LOD records", records);
  inst->counts =
      makeBuffer<cl_uint>(dev_, what + " strand counts", gpu::clh_lod_counts_length(records));
  inst->offsets =
      makeBuffer<cl_uint>(dev_, what + " strand offsets", gpu::clh_lod_offsets_length(records));
  return inst;
}

void GroomGpu::deform(const std::shared_ptr<const std::vector<glm::vec3>>& cage) {
  if (cage) throw Error("a strand-file groom has no cage to deform (only hair meshes have one)");
}

bool GroomGpu::rasterViews(GroomInstanceGpu&, const StrandRaster&, const cl::Buffer&,
                           const cl::Buffer&, std::uint32_t, Profiler*) {
  return false;
}

bool GroomGpu::rasterStill(GroomInstanceGpu&, const StrandRaster&, std::uint64_t, std::uint32_t,
                           std::uint32_t, Profiler*) {
  return false;
}

bool GroomGpu::motion(GroomInstanceGpu&, const GroomInstance&, const MotionDraw&,
                      const StrandRaster&, Profiler*) {
  return false;
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
