// renderer_impl.h — what a Renderer owns: the stages, the grooms on the device (cache,
// shared root sets), the render target, the scene on the device, the shadow pass and the
// profiler. renderer.cpp runs the frame loop over them; renderer_tools.cpp holds the
// calls that are not a frame (reference, strand export, AO bake, groom queries).
#pragma once

#include <map>
#include <memory>
#include <vector>

#include "cl/device_impl.h"
#include "clhair/renderer.h"
#include "frame/frame_lod.h"
#include "frame/render_target.h"
#include "frame/scene_gpu.h"
#include "frame/shadow_pass.h"
#include "groom/groom_cache.h"
#include "groom/hair_mesh_gpu.h"
#include "stages/ao_stage.h"
#include "stages/composite_stage.h"
#include "stages/filter_stage.h"
#include "stages/link_stage.h"
#include "stages/shade_stage.h"

namespace clhair {

// A centre layer that comes from elsewhere than the strand pass (the traced reference of
// renderer_tools.cpp): the frame loop hands it the opaque scene's depth once that is drawn,
// then asks it, groom by groom, for the words it would otherwise rasterize. The LOD pass
// still runs (shading reads its totals); the strand pass does not.
class GBufferSource {
 public:
  virtual ~GBufferSource() = default;
  // The frame's view record and the opaque scene's view depth per pixel (+inf: nothing).
  virtual void opaqueDrawn(const gpu::ClhViewGpu& view, const std::vector<float>& depth) = 0;
  // The centre layer (width * height words) of groom draw `draw`, whose record for this
  // frame is `params`.
  virtual void centreLayer(std::uint32_t draw, const gpu::ClhGroomGpu& params,
                           std::vector<std::uint64_t>& words) = 0;
};

struct Renderer::Impl {
  Device device;
  Device::Impl& dev;
  LodStage lod;
  StrandStage strands;
  ExplicitStage explicitStrands;
  AoStage ao;
  RootSetsGpu roots;
  GroomStages stages;
  GroomCache grooms;
  ShadeStage shade;
  FilterStage filter;
  std::unique_ptr<LinkStage> linkStage;  // built on first use (kernels/link.cl)
  CompositeStage composite;
  RenderTarget target;
  SceneGpu scene;
  ShadowPass shadows;
  FrameLod frameLod;
  Profiler profiler;
  // Baked visibility tables on the device, by bake (kept alive with it), the per-draw
  // ClhVisibilityGpu and a one-cell table for grooms without a bake.
  std::map<const VisibilityBake*, std::pair<std::shared_ptr<const VisibilityBake>, cl::Buffer>>
      visibilityTables;
  cl::Buffer visibilityParams, visibilityNone;

  explicit Impl(Device d)
      : device(std::move(d)),
        dev(*device.impl()),
        lod(dev),
        strands(dev),
        explicitStrands(dev),
        ao(dev),
        stages{dev, lod, strands, explicitStrands, ao, roots},
        grooms(stages),
        shade(dev),
        filter(dev),
        composite(dev),
        target(dev),
        scene(dev),
        shadows(dev),
        frameLod(dev) {}

  // CPU devices: the benchmark's dispatch section (bench/README.md) measured read-back and
  // over-launch level within noise on PoCL, persistent no better, and read-back launches
  // exactly the drawn strands, so it is the CPU default. GPUs: over-launch avoids the host
  // round trip between the pre-pass and the strand pass (a pipeline bubble per groom on a
  // discrete GPU), and surplus work-groups leave after one load. Re-run
  // `clhair_bench --only dispatch` on a GPU and change this if it disagrees.
  DispatchMode resolveMode(DispatchMode m) const {
    if (m != DispatchMode::Auto) return m;
    return dev.info.isGpu ? DispatchMode::OverLaunch : DispatchMode::ReadBack;
  }

  // The shading pass's baked-visibility inputs for groom instance `gi`: its table (uploaded
  // on first use) and its ClhVisibilityGpu, or a disabled record when it has no bake or
  // `enabled` is false; the record also says whether LOD strands take the aggregated BCSDF.
  // It is rewritten per draw (the queue is in order).
  void bindVisibility(const GroomInstance& gi, bool enabled, bool lodAggregate,
                      ShadeStage::Params& sp);
  // Shades instance `gi` (device state `inst`) from target `t`'s G-buffer (or `gbuffer`)
  // into its hair buffer, with the frame's lights and maps and the groom's baked visibility.
  void shadeGroom(RenderTarget& t, const GroomInstance& gi, GroomInstanceGpu& inst,
                  const ShadowMapInputs& maps, const RenderOptions& options, bool cover = false,
                  const cl::Buffer* gbuffer = nullptr);

  // One frame (Renderer::render); with `source`, its centre layers replace the strand pass
  // (MSAA 1 only).
  Frame frame(const Scene& s, const RenderOptions& options, GBufferSource* source);
  // Several views of one assembly (Renderer::renderViews, two cameras or more).
  std::vector<Frame> views(const Scene& s, const std::vector<Camera>& cameras,
                           const RenderOptions& options);
  // Targets of views after the first (which draws into `target`), and the per-view slices
  // the multi-view strand pass reads and writes: each view's scene depth and G-buffer are
  // sub-buffers of viewDepths and viewGBuffers (their origins on viewAlign bytes).
  std::vector<std::unique_ptr<RenderTarget>> viewTargets;
  cl::Buffer viewDepths, viewGBuffers, viewRecords, viewGrooms;
  std::vector<cl::Buffer> viewDepthSlices, viewGBufferSlices;
  std::size_t viewDepthWords = 0, viewGBufferWords = 0, viewSlots = 0, viewSlicePixels = 0;
  std::size_t viewAlign = 0;

  // Every groom instance of the scene with its device form; the k-th instance of one
  // groom gets instance slot k. Instances of one groom share its layer vertices, so they
  // must share its cage too.
  std::vector<GroomDraw> resolveGrooms(const Scene& s) {
    std::vector<GroomDraw> draws;
    std::map<const GroomGpu*, std::size_t> seen;
    std::map<const GroomGpu*, const void*> cages;
    for (const GroomInstance& gi : s.grooms) {
      GroomGpu& g = grooms.get(gi);
      auto [c, first] = cages.emplace(&g, gi.deformed.get());
      if (!first && c->second != gi.deformed.get())
        throw Error("groom \"" + gi.name +
                    "\": two instances of one hair mesh are deformed differently in one frame; "
                    "give each animated instance its own hair mesh");
      draws.push_back({&gi, &g, &g.instance(seen[&g]++)});
    }
    return draws;
  }
};

}  // namespace clhair
