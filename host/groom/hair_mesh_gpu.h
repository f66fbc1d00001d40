// hair_mesh_gpu.h — a hair mesh on the device (GroomGpu): its layer vertices and bundle
// records (host/groom/groom_data.h), AO baked on the device when the mesh has none, and
// per instance the LOD records of kernels/lod.cl. Strands are generated per pass by
// kernels/strands.cl from these tables and the shared blue-noise root sets.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <utility>

#include "clhair/hair_mesh.h"
#include "groom/blue_noise.h"
#include "groom/groom_data.h"
#include "groom/groom_gpu.h"

namespace clhair {

// Root positions in a bundle's face (progressive blue noise), one pair of sets per size:
// a groom uses the smallest power of two (at least 1024) that covers its largest bundle,
// so its strands never depend on which other grooms were loaded before it (a set of 2048
// is not an extension of the set of 1024).
class RootSetsGpu {
 public:
  struct Set {
    std::uint32_t size = 0;
    cl::Buffer quad, triangle;  // float2[size] each
  };
  const Set& forBundle(Device::Impl& dev, std::uint32_t strands);

 private:
  std::map<std::uint32_t, Set> sets_;
};

class HairMeshGpu final : public GroomGpu {
 public:
  // bakeAo: compute AO on the device when `mesh` carries none (AO bakes themselves and
  // strand export do not need it).
  HairMeshGpu(std::shared_ptr<const HairMesh> mesh, GroomStages& stages, bool bakeAo);

  bool prepare(GroomInstanceGpu& inst, const glm::mat4& objToWorld, const ViewDraw& pass) override;
  void lod(GroomInstanceGpu& inst, const cl::Buffer& view, Profiler* profiler) override;
  std::uint32_t strandCount() const override {
    return static_cast<std::uint32_t>(data_.totalStrands);
  }
  std::uint64_t pointSpace() const override {
    return std::uint64_t(data_.totalStrands) * CLH_MAX_CONTROL_POINTS;
  }
  void raster(GroomInstanceGpu& inst, const StrandRaster& r, Profiler* profiler) override;
  void opacity(GroomInstanceGpu& inst, const OpacityDraw& o, std::uint32_t strands,
               Profiler* profiler) override;
  StrandSet exportStrands(float lod) override;
  bool lodEnabled() const override { return mesh_->lod.enabled; }
  GroomKernels kernels() const override {
    return {"lod_bundles", "strands_raster", "strands_raster_persistent", "strands_opacity",
            "strands_motion"};
  }
  std::vector<const cl::Buffer*> tables() const override {
    return {&vertices_, &bundles_, &roots_->quad, &roots_->triangle, &prevVertices_};
  }
  glm::vec3 boundsMin() const override { return data_.boundsMin; }
  glm::vec3 boundsMax() const override { return data_.boundsMax; }
  // At rest (a cage equal to the mesh's layers included): the measured box (hairExtent);
  // drawn with a deformed cage: the bounds.
  glm::vec3 hairMin() const override { return moved_ ? data_.boundsMin : hairMin_; }
  glm::vec3 hairMax() const override { return moved_ ? data_.boundsMax : hairMax_; }
  void useAo(bool on) override;
  // Rebuilds the layer-vertex records (positions, styling frames, bounds) from `cage` and
  // uploads them into the same buffer; the bundles and their strand counts stay those of the
  // rest pose, so strands keep their identity. The same cage (by identity) twice in a row
  // costs nothing.
  void deform(const std::shared_ptr<const std::vector<glm::vec3>>& cage) override;
  bool rasterViews(GroomInstanceGpu& inst, const StrandRaster& r, const cl::Buffer& viewGrooms,
                   const cl::Buffer& views, std::uint32_t count, Profiler* profiler) override;
  bool rasterStill(GroomInstanceGpu& inst, const StrandRaster& r, std::uint64_t still,
                   std::uint32_t subset, std::uint32_t pass, Profiler* profiler) override;
  // The previous frame's strands from previous.deformed (the rest pose when null); only
  // while this frame's layer vertices carry no file tangents (a deformed cage never does),
  // so both frames build their tangents alike.
  bool motion(GroomInstanceGpu& inst, const GroomInstance& previous, const MotionDraw& m,
              const StrandRaster& r, Profiler* profiler) override;

  // AO per layer vertex of `mesh` (1 = open), computed on the device from a sample of its
  // own strands (kernels/ao.cl), or taken from the device's cache folder when the same
  // bake was made before (BinaryCache::dataKey).
  static std::vector<float> bakeAo(const HairMesh& mesh, GroomStages& stages);
  // The box of `mesh`'s strands at rest: the extent of every point of its strands at full
  // detail, generated on the device (a groom of more than 200,000 strands: of a sample of
  // 200,000, widened by 2 % of its diagonal on every side). Cached in the device's folder like
  // the bake; min > max when the groom has no strands.
  static std::pair<glm::vec3, glm::vec3> hairExtent(const HairMesh& mesh, GroomStages& stages);

 private:
  // On the groom of the sampled strands: the bake, and the name of its cache entry.
  std::vector<float> bakeSample(const HairMesh& mesh, int gridCells);
  // The cache entry of the bake (`what` "ao") or of the hair's extent ("extent"), with
  // `version` naming what the entry holds.
  std::string aoCacheKey(const HairMesh& mesh, const char* what,
                         const std::string& version = {}) const;
  // The exported strands of one instance: CLH_MAX_CONTROL_POINTS slots per strand.
  struct Exported {
    std::uint32_t total = 0;
    cl::Buffer points, tangents, counts;
  };
  Exported exportOnDevice(GroomInstanceGpu& inst, float lod);
  std::unique_ptr<GroomInstanceGpu> makeInstance() override;
  std::uint64_t sharedBytes() const override;
  StrandStage::Inputs inputs(const GroomInstanceGpu& inst) const;
  // Keeps the instance's current records and scan in inst.stored and assembles their strands
  // there (false: they exceed the device's memory; nothing kept).
  bool storeStill(GroomInstanceGpu& inst, Profiler* profiler);
  // Layer-vertex records of the mesh with its layer vertices at `cage` (file tangents
  // dropped: they follow from the moved layers).
  GroomData movedRecords(const std::vector<glm::vec3>& cage) const;

  std::shared_ptr<const HairMesh> mesh_;
  GroomStages& stages_;
  GroomData data_;
  std::vector<float> ao_;                    // baked or given AO per layer vertex
  glm::vec3 hairMin_{0.0f}, hairMax_{0.0f};  // the rest pose's hairExtent (else the bounds)
  bool moved_ = false;                       // drawn with a cage other than the rest pose
  bool aoUploaded_ = true;                   // the vertex buffer holds ao_ (else AO = 1)
  gpu::ClhGroomGpu base_{};                  // the view-independent parameter fields
  cl::Buffer vertices_, bundles_;
  cl::Buffer exportView_;  // ClhViewGpu of strand export passes
  const RootSetsGpu::Set* roots_ = nullptr;
  std::shared_ptr<const std::vector<glm::vec3>> cage_;  // held: its address identifies it
  bool hasTangents_ = false;                            // the vertex records hold file tangents
  // the previous frame's layer-vertex records for the motion pass, and the cage they are of
  cl::Buffer prevVertices_;
  std::shared_ptr<const std::vector<glm::vec3>> prevCage_;
  bool prevValid_ = false;
};

}  // namespace clhair
