// aov_passes.cpp — the layers for compositing gathered on the device (passes.h): the planes
// start from the opaque scene after its pass, and each groom is folded in after its
// composite (kernels/aov.cl); the read-back pass reads them once with the frame.
#include "passes/passes.h"

namespace clhair {

namespace {

// The planes' buffers (created resources of the graph).
AovStage::Planes planesOf(FrameGraph& g, const FramePlan& plan) {
  const AovHandles& h = plan.aov;
  return {&g.buffer(h.lastDepth), &g.buffer(h.owner), &g.buffer(h.ownerMotion),
          &g.buffer(h.alpha),     &g.buffer(h.hair),  &g.buffer(h.centreZ),
          &g.buffer(h.tangent),   &g.buffer(h.strand)};
}

}  // namespace

void addAovBeginPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, PendingFrame& out) {
  const std::size_t n = plan.pixels;
  AovHandles& h = plan.aov;
  h.lastDepth = g.create("AOV last depth", n * 4);
  h.owner = g.create("AOV owner", n * 4);
  h.ownerMotion = g.create("AOV owner motion", n * 8);
  h.alpha = g.create("AOV hair alpha", n * 4);
  h.hair = g.create("AOV hair", n * 16);
  h.centreZ = g.create("AOV centre depth", n * 4);
  h.tangent = g.create("AOV tangent", n * 16);
  h.strand = g.create("AOV strand", n * 16);
  g.addPass(
      "aov begin",
      [&](FrameGraph::Setup& s) {
        s.read(plan.camera().depth).read(plan.camera().color).sideEffect().kernel("aov_begin");
        for (const FrameGraph::Handle h : plan.aov.all()) s.write(h);
      },
      [&] {
        // the colour under the hair: temporal reprojection recomposes the frame on it
        std::vector<float>& opaque = out.frames[0].aovs.opaque;
        opaque.resize(plan.pixels * 4);
        out.read(r.dev, r.pinned, plan.camera().target->color, 0, opaque.data(), opaque.size() * 4);
        r.aov.begin(plan.camera().target->depth, plan.pixels, planesOf(g, plan), &r.profiler);
      });
}

void addAovGroomPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp) {
  g.addPass(
      "aov " + std::to_string(gp.index),
      [&](FrameGraph::Setup& s) {
        s.read(gp.params)
            .read(plan.camera().gbuffer)
            .read(gp.views[0].result)
            .read(plan.camera().depth)
            .kernel("aov_groom");
        if (gp.motion) s.read(gp.motionPlane);
        for (const FrameGraph::Handle h : plan.aov.all()) s.readWrite(h);
      },
      [&] {
        RenderTarget& t = *plan.camera().target;
        AovStage::Groom a;
        a.groom = &gp.draw.state->groom;
        a.index = static_cast<std::uint32_t>(gp.index);
        a.gbuffer = &t.gbuffer;
        a.samples = plan.options.msaa;
        a.ids = plan.options.strandIds;
        a.layers = static_cast<std::size_t>(t.usedLayers());
        a.result = &g.buffer(gp.views[0].result);
        a.depth = &t.depth;
        a.motion = gp.motion ? &g.buffer(gp.motionPlane) : nullptr;
        r.aov.groom(a, plan.pixels, planesOf(g, plan), &r.profiler);
      });
}

}  // namespace clhair
