// renderer.cpp — builds each frame as a graph of passes (host/graph/frame_graph.h) from the
// scene and options, runs it without waiting, and hands frames out when they complete.
//
// A frame: the scene and view records are uploaded, the deep opacity maps rebuilt when their
// inputs changed, the opaque scene drawn, every groom's LOD pre-pass and the segment budget
// run, then every groom in turn is rasterized, linked, shaded, filtered and composited over
// the same target; the result is read back without blocking. What each step needs is
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
  return impl_->enqueue(impl_->submitFrame(s, o, nullptr));
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
  return impl_->enqueue(impl_->submitViews(s, cameras, qualityOptions(s, options)));
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

std::unique_ptr<PendingFrame> Renderer::Impl::submitFrame(const Scene& s,
                                                          const RenderOptions& options,
                                                          GBufferSource* source) {
  const std::uint64_t waits0 = dev.transfers.hostWaits();
  target.ensure(s.width, s.height, options.msaa);
  FramePlan plan(s, options);
  plan.source = source;
  plan.target = &target;
  std::vector<GroomDraw> draws;
  std::unique_ptr<PendingFrame> p = begin(*this, plan, 1, draws);
  planFrame(plan, draws, resolveMode(options.dispatch));
  int layers = options.msaa + 1;  // allocated once, before any groom is drawn
  for (const GroomPlan& gp : plan.grooms) layers = std::max(layers, gp.layers);
  target.useLayers(layers);
  plan.shadowsRebuilt = shadows.needsRebuild(s, options, plan.lodCorrection, &draws);
  layoutStats(plan, 1, plan.shadowsRebuilt ? draws.size() : shadows.totalSlots());
  statsBuffer(plan.stats.words);

  FrameGraph g(dev, pool);
  importFrame(g, *this, plan);
  addShadowPasses(g, *this, plan);
  addOpaquePass(g, *this, plan);
  if (plan.aovs) addAovBeginPass(g, *this, plan, *p);
  addLodPasses(g, *this, plan);
  for (GroomPlan& gp : plan.grooms) {
    if (!gp.active) continue;
    addStrandPass(g, *this, plan, gp);
    if (gp.huang) addLinkPass(g, *this, plan, gp);
    if (gp.motion) addMotionPass(g, *this, plan, gp);
    if (options.captureGBuffer && gp.index == plan.lastDrawn)
      addCapturePass(g, *this, plan, gp, *p);
    if (options.rasterOnly) continue;
    gp.points ? addPointShadePass(g, *this, plan, gp) : addShadePass(g, *this, plan, gp);
    if (gp.filtered) addFilterPass(g, *this, plan, gp);
    addCompositePass(g, *this, plan, gp);
    if (plan.aovs) addAovGroomPass(g, *this, plan, gp);
    if (plan.aovs && options.cryptomatte) addCryptomattePass(g, *this, plan, gp, *p);
  }
  addReadBackPass(g, *this, plan, *p);
  return run(*this, g, plan, std::move(p), waits0);
}

std::unique_ptr<PendingFrame> Renderer::Impl::submitViews(const Scene& s,
                                                          const std::vector<Camera>& cameras,
                                                          const RenderOptions& options) {
  const std::uint64_t waits0 = dev.transfers.hostWaits();
  views.ensure(target, cameras.size(), s.width, s.height, options.msaa);
  FramePlan plan(s, options);
  plan.target = &target;
  std::vector<GroomDraw> draws;
  std::unique_ptr<PendingFrame> p = begin(*this, plan, cameras.size(), draws);
  planViews(plan, draws, resolveMode(options.dispatch));
  plan.shadowsRebuilt = shadows.needsRebuild(s, options, plan.lodCorrection, nullptr);
  layoutStats(plan, cameras.size(), plan.shadowsRebuilt ? draws.size() : shadows.totalSlots());
  statsBuffer(plan.stats.words);
  for (const GroomPlan& gp : plan.grooms)
    visibility.prepare(gp.index, *gp.draw.instance, options.bakedVisibility, options.lodAggregate,
                       options.multipleScattering,
                       options.ambientOcclusion
                           ? gp.draw.groom->aoField(s, gp.draw.instance->transform)
                           : nullptr);
  FrameGraph g(dev, pool);
  buildViewsFrame(g, *this, plan, cameras, *p);
  return run(*this, g, plan, std::move(p), waits0);
}

}  // namespace clhair
