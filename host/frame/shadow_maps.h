// shadow_maps.h — deep opacity maps (Yuksel & Keyser 2008) of every shadowed light over
// all grooms, built with the strand kernels from the light's view (with LOD when the
// frame allows it). A pinhole at the light (a directional light: far away, narrow)
// frames the grooms' bounds; the opaque scene and the meshes give the light's opaque
// depth, the strands' nearest depth bounds the first layer, and the opacity passes fill
// CLH_DOM_LAYERS layers per texel. The maps are reused across frames while nothing they
// depend on changes (RenderOptions::reuseShadows): lights, shadow settings, opaque
// primitives, grooms, their transforms and deformed cages, LOD options, and, where the
// camera's LOD caps a groom's light passes (RenderOptions::shadowLodCamera), the groom's
// size on the camera's screen to half an octave.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "clhair/renderer.h"
#include "frame/scene_gpu.h"
#include "groom/groom_gpu.h"
#include "stages/clear_stage.h"
#include "stages/shadow_stage.h"

namespace clhair {

class ShadowMaps {
 public:
  explicit ShadowMaps(Device::Impl& dev);
  // Whether the maps must be built again for this frame: not when the previous ones still
  // hold (and reuse is allowed). Call once per frame, then rebuild() when it says so.
  // `draws`: the frame's grooms when the camera's LOD may cap their light passes (a frame
  // of one view), else null.
  bool needsRebuild(const Scene& s, const RenderOptions& options, bool lodCorrection,
                    const std::vector<GroomDraw>* draws);
  // Whether the light passes of a groom drawn by the camera with `cameraLod` (its LOD on)
  // are capped by the camera's LOD (RenderOptions::shadowLodCamera).
  static bool cameraCaps(const RenderOptions& options, bool cameraLod);
  // Builds the maps in passes of the frame graph, before the camera's opaque pass (which
  // receives hair shadows too): begin(), then drawLight() for each of mappedLights() in
  // order, then finish().
  // The lights that get a map, in slot order (indices into s.lights): the first
  // CLH_MAX_SHADOWS with shadows, none without grooms.
  static std::vector<std::size_t> mappedLights(const Scene& s, std::size_t grooms);
  // Clears the strand totals and keeps the camera's LOD records of the grooms whose light
  // passes it caps. `camera`: the camera's view (its record on the device), whose LOD caps
  // the light passes of the grooms it draws with LOD; null: the light's view alone.
  void begin(const Scene& s, const RenderOptions& options, bool lodCorrection,
             const std::vector<GroomDraw>& grooms, const ViewDraw* camera, Profiler* profiler);
  // The next slot's map, of light s.lights[light]: the opaque depth, the strands' depth and
  // their deep opacity from the light. Strand passes are sized by `mode` (read-back waits).
  void drawLight(const Scene& s, std::size_t light, SceneGpu& scene, DispatchMode mode,
                 Profiler* profiler);
  // The slots' records uploaded: the maps hold for this frame's key.
  void finish();
  // Allocates the maps the scene's shadowed lights need, before anything of the frame is
  // released: Oclgrind 21.10 keeps a released buffer's uninitialised-memory shadow, its size
  // included, for the next buffer that gets its slot, so maps allocated after the AO bake's
  // temporaries are gone inherit shorter shadows and read as uninitialised past them.
  void reserve(const Scene& s);
  ShadowMapInputs maps() const;
  // The maps (what the shading and opaque passes read).
  std::vector<const cl::Buffer*> mapBuffers() const;
  // The maps and the pass's own scratch (what a rebuild writes).
  std::vector<const cl::Buffer*> buffers() const;
  // Strands drawn into the maps by the last rebuild: one uint per light slot and groom draw
  // (CLH_MAX_SHADOWS x totalSlots()), summed by the frame's read-back.
  const cl::Buffer& totals() const { return totals_; }
  std::size_t totalSlots() const { return totalSlots_; }
  // Texels per side of the maps this frame reads (after needsRebuild).
  int resolution() const { return planned_ > 0 ? planned_ : res_; }
  // The maps' resolution: the scene's (ShadowParams::resolution) or, where the camera's view
  // of the grooms is smaller, a texel per pixel of their bounding sphere's diameter on the
  // camera's screen (`across`), rounded up to a power of two, at least kMinResolution.
  static int mapResolution(int sceneResolution, float across);
  static constexpr int kMinResolution = 64;

 private:
  // Everything the maps depend on, to reuse them while it stays the same: the bytes of the
  // lights, shadow settings, opaque primitives, transforms, deformed cages and options, and
  // the identity of every groom and mesh (held, so an address is never reused).
  struct Key {
    std::vector<unsigned char> bytes;
    std::vector<std::shared_ptr<const void>> held;
    bool operator==(const Key& o) const { return bytes == o.bytes && held == o.held; }
  };
  static Key keyOf(const Scene& s, const RenderOptions& o, bool lodCorrection);
  // The light's view framing every groom, and its distance and radius from their centre.
  Camera lightCamera(const Light& light, float& dist, float& radius) const;
  // The world box around the grooms' hair boxes (`hair`) or bounds, and its half diagonal.
  float worldBox(bool hair, glm::vec3& lo, glm::vec3& hi) const;
  void ensureBuffers(int res);  // maps of res x res texels from now on
  void allocate(int res);       // planes that hold maps of up to res x res texels

  Device::Impl& dev_;
  ShadowStage stage_;
  ClearStage clear_;
  int res_ = 0;                                  // texels per side of the maps built last
  int capacity_ = 0;                             // texels per side the planes hold
  int planned_ = 0;                              // this frame's (needsRebuild)
  std::array<cl::Buffer, CLH_MAX_SHADOWS> one_;  // one ClhShadowGpu per slot
  cl::Buffer all_;                               // ClhShadowGpu[CLH_MAX_SHADOWS]
  cl::Buffer opaque_, hair_, opacity_;           // texel planes of all slots
  cl::Buffer lightView_, lightColor_, lightDepth_, lightGBuffer_, counters_;
  cl::Buffer totals_;
  cl::Buffer cameraLod_;  // the camera's LOD records of every capped groom draw, in order
  std::size_t cameraLodCap_ = 0;
  std::size_t totalSlots_ = 0, totalCap_ = 0;
  Key lastKey_;
  bool valid_ = false;
  // the rebuild under way: its grooms, the light passes' settings, which grooms the camera
  // caps (and where their records start), the slots' records and how many are taken
  std::vector<GroomDraw> grooms_;
  ViewDraw lightDraw_;
  float lightLambdaScale_ = 1.0f;  // the light passes' LOD lambda scale before the framing
  std::vector<char> capped_;
  std::vector<std::uint32_t> cameraAt_;
  std::vector<gpu::ClhShadowGpu> params_;
  int slots_ = 0;
};

}  // namespace clhair
