// groom_gpu.h — a groom on the device, whichever form it comes in. GroomGpu is the one
// interface the frame loop and the shadow pass draw through; HairMeshGpu (strands
// generated per frame from a hair mesh, kernels/strands.cl) and StrandFileGpu (stored
// strands, kernels/strands_explicit.cl) implement it.
//
// Geometry (hair-mesh records, strand tables) is uploaded once per groom and shared by
// every instance of it in a scene. What differs per instance — the view-dependent
// parameter record, the LOD records and their scan — lives in a GroomInstanceGpu: the
// k-th instance of a groom in a frame uses instance slot k, so two instances of one mesh
// never overwrite each other's LOD or strand totals.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "cl/dispatch.h"
#include "clhair/frame_types.h"
#include "clhair/gpu_types.h"
#include "clhair/scene.h"
#include "io/faint_groom.h"
#include "stages/explicit_stage.h"
#include "stages/lod_stage.h"
#include "stages/strand_stage.h"

namespace clhair {

class AoStage;
struct AoField;
class RootSetsGpu;

// The stages and shared tables every groom draws with; owned by the renderer.
struct GroomStages {
  Device::Impl& dev;
  LodStage& lod;
  StrandStage& strands;
  ExplicitStage& explicitStrands;
  AoStage& ao;
  RootSetsGpu& roots;  // blue-noise root positions all hair meshes share
};

// The kernels a groom's passes launch (what the frame graph's passes declare).
struct GroomKernels {
  const char* lod;
  const char* raster;
  const char* rasterPersistent;
  const char* opacity;
  const char* motion;
};

// One pass over the grooms: the camera's view or a light's.
struct ViewDraw {
  const cl::Buffer* view = nullptr;  // ClhViewGpu
  glm::mat4 worldToView{1.0f};
  // > 0: one depth mapping for every groom (a light's G-buffer is shared by all grooms)
  float nearZ = -1.0f, farZ = -1.0f;
  Toggle lod = Toggle::Default;  // RenderOptions::lod semantics
  float lodLambdaScale = 1.0f;
  float lodStrandScale =
      1.0f;                // on every groom's strands per pixel (RenderOptions::lodLambdaScale)
  bool trueWidth = false;  // ignore the minimum hit diameter (reference passes)
  bool shadowLodCorrection = true;
  // A camera's pixels (for a faint strand file's widening, io/faint_groom.h); widenFaint:
  // the groom's hair is filtered here, so a faint one may be drawn kFaintHitDiameterPx wide
  // with the alpha of its true width (the filters scale it)
  FaintView pixels;
  bool widenFaint = false;
};

// The per-instance part of a groom on the device.
struct GroomInstanceGpu {
  gpu::ClhGroomGpu params{};        // as last prepared
  cl::Buffer groom;                 // ClhGroomGpu
  std::vector<unsigned char> sent;  // the bytes `groom` holds (uploads skip what it holds)
  cl::Buffer lod;                   // ClhLodRecord per bundle / chunk
  cl::Buffer counts;                // strands per bundle / chunk (gpu_types.h, scan layout)
  cl::Buffer offsets;               // their scan and totals (clh_lod_drawn_total_at(records))
  std::uint32_t records = 0;        // bundles or chunks
  float reach = 0.0f;               // hair meshes: styling reach in view units
  // Where lod, counts and offsets live when they are views of the frame's LOD arena
  // (host/frame/frame_lod.h): the arena's generation and this instance's byte offset.
  std::uint64_t arenaGeneration = 0;
  std::size_t arenaAt = 0;
  StoredStrands stored;  // a still's strands, assembled in its first pass (rasterStill)
};

class GroomGpu {
 public:
  virtual ~GroomGpu() = default;

  // Instance slot k (created on first use).
  GroomInstanceGpu& instance(std::size_t k);

  // Fills and uploads the view-dependent parameters of `inst` for an instance placed by
  // `objToWorld`; false when the groom lies entirely behind the view.
  virtual bool prepare(GroomInstanceGpu& inst, const glm::mat4& objToWorld,
                       const ViewDraw& pass) = 0;
  // Whether prepare() would find some of the groom in front of the view (its bounds' depth
  // range), without preparing anything.
  bool inFront(const glm::mat4& objToWorld, const glm::mat4& worldToView) const;
  virtual GroomKernels kernels() const = 0;
  // The groom's own LOD setting (a pass with lod -1 follows it).
  virtual bool lodEnabled() const = 0;
  // The device buffers of the shared tables the strand kernels read (geometry, previous
  // frame's geometry for motion, root sets): what a pass drawing this groom declares.
  virtual std::vector<const cl::Buffer*> tables() const = 0;
  // LOD records and their scan for the view the instance was prepared for.
  virtual void lod(GroomInstanceGpu& inst, const cl::Buffer& view, Profiler* profiler) = 0;
  // Blocking 4-byte read of the strands the last LOD pass kept.
  std::uint32_t readTotal(const GroomInstanceGpu& inst);
  // Every strand of the groom (the bound of an over-launched dispatch).
  virtual std::uint32_t strandCount() const = 0;
  // The groom's point space for per-point shading (gpu_types.h, the sample identity word):
  // hair meshes CLH_MAX_CONTROL_POINTS per strand, strand files their stored points.
  virtual std::uint64_t pointSpace() const = 0;
  // Stored strands (strand files): a record's segments depend on each strand's length.
  virtual bool storedStrands() const { return false; }
  virtual void raster(GroomInstanceGpu& inst, const StrandRaster& r, Profiler* profiler) = 0;
  virtual void opacity(GroomInstanceGpu& inst, const OpacityDraw& o, std::uint32_t strands,
                       Profiler* profiler) = 0;
  // The strands as the kernels generate or draw them at LOD value `lod` (1: full detail).
  virtual StrandSet exportStrands(float lod) = 0;
  // Object-space bounds of the drawn geometry, styling included.
  virtual glm::vec3 boundsMin() const = 0;
  virtual glm::vec3 boundsMax() const = 0;
  // Object-space box of the hair as drawn, within the bounds above: what the light maps frame
  // (their texels and depth layers spread over it). Strand files: the points of the strands
  // that draw something. Hair meshes at rest: the extent of their strands, measured once
  // (HairMeshGpu::hairExtent; the bounds add every styling offset's largest reach to the
  // cage, about twice the hair's size for long_wavy).
  virtual glm::vec3 hairMin() const { return boundsMin(); }
  virtual glm::vec3 hairMax() const { return boundsMax(); }
  // Baked AO on or off for the next passes (hair meshes; strand files carry none).
  virtual void useAo(bool) {}
  // The groom's AO field for an instance placed by `objToWorld` in `scene` (strand files,
  // host/groom/ao_field.h; baked on first use), or null when its AO is baked per vertex
  // (hair meshes) or it has no extent.
  virtual const AoField* aoField(const Scene& /*scene*/, const glm::mat4& /*objToWorld*/) {
    return nullptr;
  }
  // Hair meshes: draw the next passes with the layer vertices `cage` (layer-major, object
  // space), or the mesh's own when null. Strand files have no cage and refuse one.
  virtual void deform(const std::shared_ptr<const std::vector<glm::vec3>>& cage);
  // Several views of one assembly (StrandStage::rasterViews); false when this groom draws
  // each view on its own instead (nothing drawn).
  virtual bool rasterViews(GroomInstanceGpu& inst, const StrandRaster& r,
                           const cl::Buffer& viewGrooms, const cl::Buffer& views,
                           std::uint32_t count, Profiler* profiler);
  // A pass of still `still` (RenderOptions::still): the strands of the records its first
  // pass drew are assembled once, kept in inst.stored and drawn from there in every pass
  // (StrandStage::rasterStored); the first pass reads the records back (a host wait). False
  // when this groom cannot (nothing drawn; the caller draws with raster()): strand files,
  // which are stored already, the curve, point and coverage passes, and strands that do not
  // fit the device's memory.
  // subset > 1: the pass draws one strand in `subset` (RenderOptions::finalSubset), chosen
  // by `pass`.
  virtual bool rasterStill(GroomInstanceGpu& inst, const StrandRaster& r, std::uint64_t still,
                           std::uint32_t subset, std::uint32_t pass, Profiler* profiler);
  // The motion pass (MotionDraw, right after raster() with the same `r`): screen motion to
  // the previous frame of every pixel the groom's conservative layer won, the strands
  // evaluated a second time from `previous` (the previous frame's record of this groom
  // instance: its cage, or its per-frame strand file). False when the groom cannot give it
  // (nothing written; the caller keeps rigid motion).
  virtual bool motion(GroomInstanceGpu& inst, const GroomInstance& previous, const MotionDraw& m,
                      const StrandRaster& r, Profiler* profiler);
  // Bytes of the shared tables plus one instance's buffers.
  std::uint64_t deviceBytes();

 protected:
  explicit GroomGpu(Device::Impl& dev) : dev_(dev) {}
  virtual std::unique_ptr<GroomInstanceGpu> makeInstance() = 0;
  // An instance's buffers for `records` bundles or chunks, its parameters set to `params`
  // (what implementations of makeInstance share).
  std::unique_ptr<GroomInstanceGpu> newInstance(const std::string& groomName, std::uint32_t records,
                                                const gpu::ClhGroomGpu& params);
  virtual std::uint64_t sharedBytes() const = 0;
  Device::Impl& dev_;

 private:
  std::vector<std::unique_ptr<GroomInstanceGpu>> instances_;
};

// One instance of a groom in a frame: the scene's record, the shared geometry and the
// instance slot it draws with.
struct GroomDraw {
  const GroomInstance* instance = nullptr;
  GroomGpu* groom = nullptr;
  GroomInstanceGpu* state = nullptr;
};

// Builds the device form of a scene's groom instance (hair mesh or strand file).
std::unique_ptr<GroomGpu> makeGroomGpu(const GroomInstance& gi, GroomStages& stages);

}  // namespace clhair
