// renderer.cpp — builds each frame as a graph of passes (host/graph/frame_graph.h) from the
// scene and options, runs it without waiting, and hands frames out when they complete.
//
// A frame: the scene and view records are uploaded, the deep opacity maps rebuilt when their
// inputs changed, each view's opaque scene drawn, every groom's LOD pre-pass and the segment
// budget run, then every groom in turn is rasterized, linked, and in each view shaded,
// filtered and composited over the view's target; the result is read back without blocking.
// A frame of several views is built by the same code: the passes of a view are added once per
// view, and each groom's strands are drawn into every view by one pass. What each step needs is
// decided once by planFrame (host/frame/frame_plan.h); each feature is a pass file in
// host/passes/. submit() returns as soon as the frame is enqueued; wait() blocks for it.
#include "renderer_impl.h"

#include <algorithm>

#include "clhair/progressive.h"
#include "passes/passes.h"

namespace clhair {

Renderer::Renderer(Device device) : impl_(std::make_unique<Impl>(std::move(device))) {}

Renderer::~Renderer() {
  try {
    impl_->drainTo(0);
  } catch (...) {  // destructors never throw: a failed frame has nothing left to hand out
  }
}

const Device& Renderer::device() const { return impl_->device; }

Frame Renderer::render(const Scene& s, const RenderOptions& options) {
  if (qualityLevel(s, options) != Quality::Final) return wait(submit(s, options));
  ProgressiveStill still(*this, s, options);  // quality final: jittered passes
  still.add(0, finalPasses(s, options));
  return still.frame();
}

FrameTicket Renderer::submit(const Scene& s, const RenderOptions& options) {
  if (qualityLevel(s, options) == Quality::Final)
    throw Error("quality final accumulates passes: render() renders it, submit() does not");
  const RenderOptions o = qualityOptions(s, options);
  return impl_->enqueue(impl_->submitFrame(s, {s.camera}, o, nullptr));
}

Frame Renderer::wait(FrameTicket ticket) { return std::move(impl_->waitFor(ticket).at(0)); }

std::vector<Frame> Renderer::renderViews(const Scene& s, const std::vector<Camera>& cameras,
                                         const RenderOptions& options) {
  return waitViews(submitViews(s, cameras, options));
}

FrameTicket Renderer::submitViews(const Scene& s, const std::vector<Camera>& cameras,
                                  const RenderOptions& options) {
  if (cameras.size() > static_cast<std::size_t>(kMaxViews))
    throw Error(std::to_string(cameras.size()) + " views; at most " + std::to_string(kMaxViews));
  if (cameras.size() < 2) {
    Scene one = s;
    if (!cameras.empty()) one.camera = cameras[0];
    return submit(one, options);
  }
  if (qualityLevel(s, options) == Quality::Final)
    throw Error("quality final renders one view at a time");
  return impl_->enqueue(impl_->submitFrame(s, cameras, qualityOptions(s, options), nullptr));
}

std::vector<Frame> Renderer::waitViews(FrameTicket ticket) { return impl_->waitFor(ticket); }

void Renderer::setFramesInFlight(int frames) {
  if (frames < 1 || frames > kMaxFramesInFlight)
    throw Error("frames in flight must be 1.." + std::to_string(kMaxFramesInFlight) + ", not " +
                std::to_string(frames));
  impl_->maxInFlight = frames;
  impl_->drainTo(static_cast<std::size_t>(frames));
}

int Renderer::framesInFlight() const { return impl_->maxInFlight; }

std::vector<GroomDraw> Renderer::Impl::resolveGrooms(const Scene& s) {
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

// Compiles and runs a built graph, and hands its frame over in flight.
static std::unique_ptr<PendingFrame> run(Renderer::Impl& r, FrameGraph& g, FramePlan& plan,
                                         std::unique_ptr<PendingFrame> p, std::uint64_t waits0) {
  g.compile();
  if (plan.options.describePasses) p->frames[0].passes = g.describe();
  try {
    g.execute();
  } catch (...) {
    // reads already enqueued write into `p`: let them land before it is freed
    try {
      r.dev.queue.finish();
    } catch (...) {
    }
    throw;
  }
  p->seal(r.dev);
  r.profiler.moveTo(p->profiler);
  r.pool.endFrame();
  r.grooms.trim();
  p->waits = r.dev.transfers.hostWaits() - waits0;
  return p;
}

// Starts a frame: its pending record, the profiler, the grooms and the shadow decision.
static std::unique_ptr<PendingFrame> begin(Renderer::Impl& r, FramePlan& plan, std::size_t views,
                                           std::vector<GroomDraw>& draws) {
  auto p = std::make_unique<PendingFrame>();
  p->frames.resize(views);
  p->timings = plan.options.timings || plan.options.stageCores;
  r.profiler.clear();
  r.profiler.enabled = p->timings;
  r.profiler.hostTiming = plan.options.stageCores;
  r.shadows.reserve(plan.scene);  // before the grooms: see ShadowMaps::reserve
  r.grooms.beginFrame();
  draws = r.resolveGrooms(plan.scene);
  r.frameLod.bind(draws);  // every draw's LOD records in one buffer, for the segment budget
  return p;
}

// The targets of a frame of `V` views: the renderer's own for one view, else a target per
// view whose depth and G-buffer are slices of the views' shared buffers.
static void viewTargets(Renderer::Impl& r, const Scene& s, const RenderOptions& o, std::size_t V,
                        std::vector<RenderTarget*>& targets, std::vector<cl::Buffer*>& depths,
                        std::vector<cl::Buffer*>& gbuffers) {
  if (V == 1) {
    r.target.ensure(s.width, s.height, o.msaa);
    targets = {&r.target};
    depths = {&r.target.depth};
    gbuffers = {&r.target.gbuffer};
    return;
  }
  r.views.ensure(r.target, V, s.width, s.height, o.msaa);
  for (std::size_t v = 0; v < V; ++v) {
    targets.push_back(&r.views.target(v));
    depths.push_back(&r.views.depthSlices[v]);
    gbuffers.push_back(&r.views.gbufferSlices[v]);
  }
}

// The groom's passes in each view it is in front of: in a frame of several views, its
// strands are drawn into every view at once (then each view's record is handed back).
static void addGroomPasses(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp,
                           PendingFrame& p) {
  const RenderOptions& o = plan.options;
  plan.severalViews() ? addViewsStrandPass(g, r, plan, gp) : addStrandPass(g, r, plan, gp);
  if (gp.huang) addLinkPass(g, r, plan, gp);
  if (gp.motion) addMotionPass(g, r, plan, gp);
  if (o.captureGBuffer && gp.index == plan.lastDrawn) addCapturePass(g, r, plan, gp, p);
  if (o.rasterOnly) return;
  for (ViewPlan& vp : plan.views) {
    if (!gp.views[vp.index].inFront) continue;
    gp.points ? addPointShadePass(g, r, plan, gp) : addShadePass(g, r, plan, gp, vp);
    if (gp.filtered) addFilterPass(g, r, plan, gp, vp);
    addCompositePass(g, r, plan, gp, vp);
  }
  if (plan.aovs) addAovGroomPass(g, r, plan, gp);
  if (plan.aovs && o.cryptomatte) addCryptomattePass(g, r, plan, gp, p);
  if (plan.severalViews()) addViewsRecordPass(g, gp);
}

std::unique_ptr<PendingFrame> Renderer::Impl::submitFrame(const Scene& s,
                                                          const std::vector<Camera>& cameras,
                                                          const RenderOptions& options,
                                                          GBufferSource* source) {
  const std::uint64_t waits0 = dev.transfers.hostWaits();
  const std::size_t V = cameras.size();
  std::vector<RenderTarget*> targets;
  std::vector<cl::Buffer*> depths, gbuffers;
  viewTargets(*this, s, options, V, targets, depths, gbuffers);
  FramePlan plan(s, options);
  plan.source = source;
  std::vector<GroomDraw> draws;
  std::unique_ptr<PendingFrame> p = begin(*this, plan, V, draws);
  planFrame(plan, draws, resolveMode(options.dispatch), cameras, targets, depths, gbuffers);
  if (V == 1) {
    int layers = options.msaa + 1;  // allocated once, before any groom is drawn
    for (const GroomPlan& gp : plan.grooms) layers = std::max(layers, gp.layers);
    target.useLayers(layers);
  }
  plan.shadowsRebuilt =
      shadows.needsRebuild(s, options, plan.lodCorrection, V == 1 ? &draws : nullptr);
  layoutStats(plan, V, plan.shadowsRebuilt ? draws.size() : shadows.totalSlots());
  statsBuffer(plan.stats.words);

  FrameGraph g(dev, pool);
  importFrame(g, *this, plan);
  addShadowPasses(g, *this, plan);
  for (ViewPlan& vp : plan.views) addOpaquePass(g, *this, plan, vp);
  if (plan.aovs) addAovBeginPass(g, *this, plan, *p);
  if (V == 1) addLodPasses(g, *this, plan);
  for (GroomPlan& gp : plan.grooms)
    if (gp.active) addGroomPasses(g, *this, plan, gp, *p);
  addReadBackPass(g, *this, plan, *p);
  return run(*this, g, plan, std::move(p), waits0);
}

}  // namespace clhair
