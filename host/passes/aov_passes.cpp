// aov_passes.cpp — the layers for compositing gathered on the device (passes.h): the planes
// start from the opaque scene after its pass, and each groom is folded in after its
// composite (kernels/aov.cl); the read-back pass reads them once with the frame.
#include "passes/passes.h"

namespace clhair {

namespace {

// The planes' buffers in a pass that declared them.
AovStage::Planes planesOf(const FrameGraph::Resources& res, const AovHandles& h) {
  return {&res[h.lastDepth], &res[h.owner],   &res[h.ownerMotion], &res[h.alpha],
          &res[h.hair],      &res[h.centreZ], &res[h.tangent],     &res[h.strand]};
}

}  // namespace

void addAovBeginPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, PendingFrame& out) {
  const std::size_t n = plan.pixels;
  AovHandles h;
  h.lastDepth = g.create("AOV last depth", n * 4);
  h.owner = g.create("AOV owner", n * 4);
  h.ownerMotion = g.create("AOV owner motion", n * 8);
  h.alpha = g.create("AOV hair alpha", n * 4);
  h.hair = g.create("AOV hair", n * 16);
  h.centreZ = g.create("AOV centre depth", n * 4);
  h.tangent = g.create("AOV tangent", n * 16);
  h.strand = g.create("AOV strand", n * 16);
  g.blackboard().put(kAovPlanes, h);
  struct Data {
    FrameGraph::Handle depth, color;
  };
  g.addPass<Data>(
      "aov begin",
      [&](FrameGraph::Setup& s, Data& d) {
        d.depth = s.read(plan.camera().depth);
        d.color = s.read(plan.camera().color);
        s.sideEffect().kernel("aov_begin");
        for (const FrameGraph::Handle p : h.all()) s.write(p);
      },
      [&, h](const Data& d, const FrameGraph::Resources& res) {
        // the colour under the hair: temporal reprojection recomposes the frame on it
        std::vector<float>& opaque = out.frames[0].aovs.opaque;
        opaque.resize(plan.pixels * 4);
        out.read(r.dev, r.pinned, res[d.color], 0, opaque.data(), opaque.size() * 4);
        r.aov.begin(res[d.depth], plan.pixels, planesOf(res, h), &r.profiler);
      });
}

void addAovGroomPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp) {
  const AovHandles h = *g.blackboard().get<AovHandles>(kAovPlanes);
  struct Data {
    FrameGraph::Handle groom, gbuffer, result, depth, motion;
  };
  g.addPass<Data>(
      "aov " + std::to_string(gp.index),
      [&](FrameGraph::Setup& s, Data& d) {
        d.groom = s.read(gp.params);
        d.gbuffer = s.read(plan.camera().gbuffer);
        d.result = s.read(gp.views[0].result);
        d.depth = s.read(plan.camera().depth);
        s.kernel("aov_groom");
        if (gp.motion) d.motion = s.read(gp.motionPlane);
        for (const FrameGraph::Handle p : h.all()) s.readWrite(p);
      },
      [&, h](const Data& d, const FrameGraph::Resources& res) {
        AovStage::Groom a;
        a.groom = &res[d.groom];
        a.index = static_cast<std::uint32_t>(gp.index);
        a.gbuffer = &res[d.gbuffer];
        a.samples = plan.options.msaa;
        a.ids = plan.options.strandIds;
        a.layers = static_cast<std::size_t>(plan.camera().target->usedLayers());
        a.result = &res[d.result];
        a.depth = &res[d.depth];
        a.motion = d.motion ? &res[d.motion] : nullptr;
        r.aov.groom(a, plan.pixels, planesOf(res, h), &r.profiler);
      });
}

}  // namespace clhair
