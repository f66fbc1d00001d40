// strand_file_gpu.h — stored strands on the device (GroomGpu): the strand tables of
// host/groom/explicit_data.h in LOD order (points, per-strand offsets, root uv, chunk
// table and bounds, children record and guide neighbours) and per instance the chunk LOD
// records of kernels/lod.cl (lod_chunks). kernels/strands_explicit.cl draws them, children
// of the stored strands included (host/groom/children.h).
#pragma once

#include <map>
#include <memory>

#include "clhair/strand_groom.h"
#include "groom/ao_field.h"
#include "groom/explicit_data.h"
#include "groom/groom_gpu.h"

namespace clhair {

class StrandFileGpu final : public GroomGpu {
 public:
  StrandFileGpu(std::shared_ptr<const StrandGroom> groom, GroomStages& stages);

  bool prepare(GroomInstanceGpu& inst, const glm::mat4& objToWorld, const ViewDraw& pass) override;
  void lod(GroomInstanceGpu& inst, const cl::Buffer& view, Profiler* profiler) override;
  bool storedStrands() const override { return true; }
  // Strands drawn at full detail: the stored ones and their children.
  std::uint32_t strandCount() const override {
    return static_cast<std::uint32_t>(data_.drawnStrands);
  }
  // child c of a guide numbers its points after c copies of the stored ones (as export does)
  std::uint64_t pointSpace() const override {
    return data_.totalPoints * (std::uint64_t(data_.kids.count) + 1);
  }
  void raster(GroomInstanceGpu& inst, const StrandRaster& r, Profiler* profiler) override;
  void opacity(GroomInstanceGpu& inst, const OpacityDraw& o, std::uint32_t strands,
               Profiler* profiler) override;
  StrandSet exportStrands(float lod) override;
  // The previous frame's strands from previous.strands (a per-frame file): only when every
  // strand has as many points in both files (point k of strand s is the same point).
  bool motion(GroomInstanceGpu& inst, const GroomInstance& previous, const MotionDraw& m,
              const StrandRaster& r, Profiler* profiler) override;
  bool lodEnabled() const override { return groom_->lod.enabled; }
  GroomKernels kernels() const override {
    return {"lod_chunks", "strands_explicit_raster", "strands_explicit_raster_persistent",
            "strands_explicit_opacity", "strands_explicit_motion"};
  }
  std::vector<const cl::Buffer*> tables() const override {
    return {&points_,      &strandOffsets_, &uv_,         &chunks_,
            &chunkBounds_, &kids_,          &neighbours_, &prevPoints_};
  }
  const AoField* aoField(const Scene& scene, const glm::mat4& objToWorld) override;
  glm::vec3 boundsMin() const override { return data_.boundsMin; }
  glm::vec3 boundsMax() const override { return data_.boundsMax; }
  // The points of the strands that draw something (a strand whose points all coincide draws
  // nothing); with children, the bounds (they spread around their guides).
  glm::vec3 hairMin() const override { return hairMin_; }
  glm::vec3 hairMax() const override { return hairMax_; }

 private:
  std::unique_ptr<GroomInstanceGpu> makeInstance() override;
  std::uint64_t sharedBytes() const override;
  ExplicitStage::Inputs inputs(GroomInstanceGpu& inst) const;
  // Whether the groom draws faint in this view (io/faint_groom.h), cached by the view.
  bool faint(const glm::mat4& objToView, const FaintView& view);
  const AoField* withDiffusedLight(const Scene& scene, const glm::mat4& objToWorld,
                                   const std::string& placement);

  std::shared_ptr<const StrandGroom> groom_;
  GroomStages& stages_;
  ExplicitData data_;           // host copy without the points (they live on the device)
  std::size_t pointWords_ = 0;  // float4 in points_: the points, then file colours
  gpu::ClhGroomGpu base_{};
  cl::Buffer points_, strandOffsets_, uv_, chunks_, chunkBounds_, kids_, neighbours_;
  cl::Buffer prevPoints_;  // the motion pass: previous frame's points in this order
  std::shared_ptr<const StrandGroom> prevGroom_;
  glm::vec3 hairMin_{0.0f}, hairMax_{0.0f};  // hairMin/hairMax
  AoDensity aoDensity_;                      // the AO field's density grid of the hair alone
  // fields baked for placements among occluders, by their density grid's checksum
  std::map<std::uint64_t, std::unique_ptr<AoField>> aoFields_;
  std::string lastPlacement_;  // the last placement's bytes, its grid with the occluders
  AoDensity placedDensity_;    // marked, and its field
  const AoField* lastField_ = nullptr;
  // the field with the light diffused through the groom (diffusion_field.h), for the last
  // placement and lights
  std::string diffusedKey_;
  std::unique_ptr<AoField> diffused_;
  // the view of the last faint-groom estimate, and its answer
  bool faintKnown_ = false;
  glm::mat4 faintView_{1.0f};
  FaintView faintPixels_;
  bool faint_ = false;
};

}  // namespace clhair
