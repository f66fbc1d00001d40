// link_passes.cpp — Huang's hair linking over a groom's G-buffer (passes.h): the sources are
// selected, their centre lines drawn by the curve pass of the groom's strands, propagated
// along them and merged into the centre layer with the alpha fix's per-strand counts.
// Without linking (a given G-buffer, or linking off) only the selection's set-up and the
// merge's counting run, for the bounds of the anisotropic filter.
#include "passes/passes.h"

namespace clhair {

LinkStage::Params linkParams(const FramePlan& plan, const GroomPlan& gp,
                             const FrameGraph::Resources& res) {
  const ViewPlan& camera = plan.camera();
  return {viewTarget(plan, res[camera.record]), &res[gp.params], &res[camera.gbuffer],
          gp.draw.groom->strandCount(),         gp.layers,       gp.hairBox};
}

void addLinkPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp) {
  g.addPass(
      "link " + std::to_string(gp.index),
      [&](FrameGraph::Setup& s) {
        const ViewPlan& camera = plan.camera();
        s.reads({camera.record, gp.params}).readsWrites({camera.gbuffer}).writes({plan.linkState});
        s.kernel("clear_uints").kernel("link_select").kernel("link_merge");
        if (!gp.linking) return;
        s.reads({camera.depth, gp.tables, gp.lod}).readsWrites({plan.rasterCounters});
        s.kernel(gp.draw.groom->kernels().raster).kernel("link_propagate");
        if (plan.mode == DispatchMode::ReadBack)
          s.hostWait("the groom's strand total for the curve pass (--dispatch readback)");
      },
      [&](const FrameGraph::Resources& res) {
        const LinkStage::Params lp = linkParams(plan, gp, res);
        r.link.select(*gp.filter, lp, &r.profiler);
        if (gp.linking) {
          StrandRaster curve = cameraRaster(r, plan, gp, plan.camera(), res);
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
