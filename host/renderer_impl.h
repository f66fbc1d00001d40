// renderer_impl.h — what a Renderer owns: the stages (the kernels passes launch), the grooms
// on the device (cache, shared root sets), the render targets, the scene on the device, the
// shadow maps, the frame's LOD arena, the buffer pool of the frame graph and the frames in
// flight. renderer.cpp builds each frame's graph from the pass files (host/passes/) and
// runs it; renderer_tools.cpp holds the calls that are not a frame (reference, strand
// export, AO bake, groom queries).
#pragma once

#include <deque>
#include <map>
#include <memory>
#include <typeindex>
#include <vector>

#include "cl/device_impl.h"
#include "clhair/renderer.h"
#include "frame/frame_lod.h"
#include "frame/pending_frame.h"
#include "frame/render_target.h"
#include "frame/scene_gpu.h"
#include "frame/shadow_maps.h"
#include "frame/view_targets.h"
#include "frame/visibility_gpu.h"
#include "graph/frame_graph.h"
#include "groom/groom_cache.h"
#include "groom/hair_mesh_gpu.h"
#include "stages/ao_stage.h"
#include "stages/aov_stage.h"
#include "stages/composite_stage.h"
#include "stages/filter_stage.h"
#include "stages/labels_stage.h"
#include "stages/link_stage.h"
#include "stages/point_stage.h"
#include "stages/shade_stage.h"

namespace clhair {

// A centre layer that comes from elsewhere than the strand pass (the traced reference of
// renderer_tools.cpp): the frame hands it the opaque scene's depth once that is drawn (a
// declared host wait), then asks it, groom by groom, for the words it would otherwise
// rasterize. The LOD pass still runs (shading reads its totals); the strand pass does not.
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
  PointStage points;
  FilterStage filter;
  LinkStage link;
  CompositeStage composite;
  AovStage aov;
  LabelsStage labels;
  RenderTarget target;
  ViewTargets views;  // the targets and slices of frames with several views
  SceneGpu scene;
  ShadowMaps shadows;
  FrameLod frameLod;
  VisibilityGpu visibility;
  BufferPool pool;
  Profiler profiler;      // events of the frame being built, handed to its PendingFrame
  cl::Buffer frameStats;  // counters the passes copy for the frame's read-back
  std::size_t frameStatsCap = 0;
  // Frames submitted and not yet waited for, oldest first, and the next ticket.
  std::deque<std::unique_ptr<PendingFrame>> inFlight;
  std::uint64_t nextTicket = 1;
  int maxInFlight = 2;
  PinnedPool pinned;  // read-back staging of devices without host-unified memory

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
        points(dev),
        filter(dev),
        link(dev),
        composite(dev),
        aov(dev),
        labels(dev),
        target(dev),
        views(dev),
        scene(dev),
        shadows(dev),
        frameLod(dev),
        visibility(dev),
        pool(dev),
        pinned(dev) {}

  // The stage of type S a feature's pass launches its kernels with, made on first use and
  // kept with the renderer: a feature's stage needs no member here (S(Device::Impl&)).
  template <class S>
  S& stage() {
    std::shared_ptr<void>& held = featureStages[std::type_index(typeid(S))];
    if (!held) held = std::make_shared<S>(dev);
    return *static_cast<S*>(held.get());
  }
  std::map<std::type_index, std::shared_ptr<void>> featureStages;

  // Dispatch sizing per device type. No mode reads the strand total back unless asked:
  // over-launch sizes the strand pass by the groom's strand count and surplus work-groups
  // leave after one load, so the host never waits inside a frame. On PoCL the benchmark's
  // dispatch section measured read-back and over-launch within 1 % (bench/README.md); on a
  // discrete GPU over-launch also avoids a round trip per groom.
  DispatchMode resolveMode(DispatchMode m) const {
    return m == DispatchMode::Auto ? DispatchMode::OverLaunch : m;
  }

  // Every groom instance of the scene with its device form; the k-th instance of one
  // groom gets instance slot k. Instances of one groom share its layer vertices, so they
  // must share its cage too.
  std::vector<GroomDraw> resolveGrooms(const Scene& s);

  // Builds, compiles and runs the graph of one frame seen by `cameras` (one or more; with
  // `source`, one view whose centre layers replace the strand pass) and returns it in flight.
  std::unique_ptr<PendingFrame> submitFrame(const Scene& s, const std::vector<Camera>& cameras,
                                            const RenderOptions& options, GBufferSource* source);
  // Waits for the oldest frames until fewer than `limit` are in flight.
  void drainTo(std::size_t limit);
  std::vector<Frame> waitFor(std::uint64_t ticket);
  std::uint64_t enqueue(std::unique_ptr<PendingFrame> p);
  // The statistics buffer, at least `words` long.
  cl::Buffer& statsBuffer(std::size_t words);
};

}  // namespace clhair
