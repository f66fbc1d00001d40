// link_passes.cpp — Huang's hair linking over a groom's G-buffer (passes.h): the sources are
// selected, their centre lines drawn by the curve pass of the groom's strands, propagated
// along them and merged into the centre layer with the alpha fix's per-strand counts.
// Without linking (a given G-buffer, or linking off) only the selection's set-up and the
// merge's counting run, for the bounds of the anisotropic filter.
#include "passes/passes.h"

namespace clhair {

LinkStage::Params linkParams(const FramePlan& plan, const GroomPlan& gp) {
  RenderTarget& t = *plan.camera().target;
  return {t.viewTarget(), &gp.draw.state->groom,
          &t.gbuffer,     gp.draw.groom->strandCount(),
          gp.layers,      gp.hairBox};
}

void addLinkPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp) {
  g.addPass(
      "link " + std::to_string(gp.index),
      [&](FrameGraph::Setup& s) {
        s.read(plan.camera().record)
            .read(gp.params)
            .readWrite(plan.camera().gbuffer)
            .write(plan.linkState);
        s.kernel("clear_uints").kernel("link_select").kernel("link_merge");
        if (!gp.linking) return;
        s.read(plan.camera().depth).read(gp.tables).read(gp.lod).readWrite(plan.rasterCounters);
        s.kernel(gp.draw.groom->kernels().raster).kernel("link_propagate");
        if (plan.mode == DispatchMode::ReadBack)
          s.hostWait("the groom's strand total for the curve pass (--dispatch readback)");
      },
      [&] {
        const LinkStage::Params lp = linkParams(plan, gp);
        r.link.select(*gp.filter, lp, &r.profiler);
        if (gp.linking) {
          StrandRaster curve = cameraRaster(r, plan, gp);
          curve.ids = false;
          curve.curve = true;
          curve.stats = false;
          curve.mode = plan.mode == DispatchMode::Persistent ? DispatchMode::OverLaunch : plan.mode;
          curve.linkFlags = &r.link.flags();
          curve.linkWords = r.link.flagWords();
          gp.draw.groom->raster(*gp.draw.state, curve, &r.profiler);
          r.link.propagate(lp, &r.profiler);
        }
        r.link.merge(lp, gp.linking, &r.profiler);
      });
}

}  // namespace clhair
