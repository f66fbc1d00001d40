// shade_passes.cpp — a groom's deferred shading, filter and composite (passes.h).
#include "passes/passes.h"

namespace clhair {

LinkStage::Params linkParams(const FramePlan& plan, const GroomPlan& gp);

ShadeStage::Params shadeParams(Renderer::Impl& r, const RenderTarget& t, const GroomPlan& gp,
                               const cl::Buffer& gbuffer, cl::Buffer& hair, int msaa) {
  GroomInstanceGpu& inst = *gp.draw.state;
  ShadeStage::Params sp;
  sp.target = t.viewTarget();
  sp.lighting = r.scene.lighting(r.shadows.maps());
  sp.groom = &inst.groom;
  sp.offsets = &inst.offsets;
  sp.records = inst.records;
  sp.gbuffer = &gbuffer;
  sp.hair = &hair;
  sp.msaa = msaa;
  const VisibilityGpu::Inputs v = r.visibility.inputs(gp.index);
  sp.visibility = v.record;
  sp.visibilityTable = v.table;
  sp.visibilityCells = v.cells;
  sp.aoField = v.aoField;
  sp.aoFieldVoxels = v.aoFieldVoxels;
  return sp;
}

void addShadePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp, ViewPlan& vp) {
  GroomView& gv = gp.views[vp.index];
  gv.result = gv.hair;
  g.addPass(
      "shade " + std::to_string(gp.index) + vp.suffix,
      [&](FrameGraph::Setup& s) {
        s.read(vp.record).read(plan.scene_).read(plan.shadowMaps).read(vp.gbuffer);
        s.read(gp.params).read(gp.lod).read(plan.visibility).write(gv.hair);
        s.kernel("shade_deferred");
        if (plan.severalViews()) declareViewDraw(s, plan, gp, vp);
      },
      [&] {
        if (plan.severalViews()) drawInView(r, plan, gp, vp);
        ShadeStage::Params sp = shadeParams(r, *vp.target, gp, g.buffer(vp.gbuffer),
                                            g.buffer(gv.hair), plan.options.msaa);
        sp.cover = plan.cover;
        r.shade.enqueue(sp, &r.profiler);
      });
}

void addFilterPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp, ViewPlan& vp) {
  GroomView& gv = gp.views[vp.index];
  if (!gp.huang) {
    gv.result = gv.filteredHair;
    g.addPass(
        "filter " + std::to_string(gp.index) + vp.suffix,
        [&](FrameGraph::Setup& s) {
          s.read(vp.record).read(gp.params).read(vp.gbuffer).read(gv.hair);
          s.write(plan.filterParams).write(gv.filteredHair).kernel("filter_reconstruct");
        },
        [&] {
          r.filter.enqueue(*gp.filter,
                           {vp.target->viewTarget(), &gp.draw.state->groom, &g.buffer(vp.gbuffer),
                            &g.buffer(gv.hair), &g.buffer(gv.filteredHair)},
                           &r.profiler);
        });
    return;
  }
  // Huang's alpha fix into the filter's buffer, then (aniso) the anisotropic filter back (one
  // view)
  gv.result = gp.filter->aniso ? gv.hair : gv.filteredHair;
  g.addPass(
      "alpha fix " + std::to_string(gp.index),
      [&](FrameGraph::Setup& s) {
        s.read(vp.record).read(gp.params).read(vp.gbuffer).read(plan.linkState);
        s.readWrite(gv.hair).write(gv.filteredHair).write(plan.frameStats);
        s.kernel("link_alpha").kernel("copy_uints");
        if (gp.filter->aniso) s.kernel("link_aniso");
      },
      [&] {
        r.link.finish(linkParams(plan, gp), gp.filter->aniso, g.buffer(gv.hair),
                      g.buffer(gv.filteredHair), &r.profiler);
        // the groom's linking counters, for the frame's statistics
        r.target.copyUints(r.link.counterBuffer(), 0, r.frameStats, plan.linkAt + 4 * gp.index, 4,
                           &r.profiler);
      });
}

void addCompositePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp,
                      ViewPlan& vp) {
  const GroomView& gv = gp.views[vp.index];
  g.addPass(
      "composite " + std::to_string(gp.index) + vp.suffix,
      [&](FrameGraph::Setup& s) {
        s.read(vp.record).read(gp.params).read(vp.gbuffer).read(gv.result);
        s.readWrite(vp.color).readWrite(vp.depth).kernel("composite_over");
      },
      [&] {
        RenderTarget& t = *vp.target;
        r.composite.enqueue(
            {t.viewTarget(), &gp.draw.state->groom, &g.buffer(gv.result), &g.buffer(vp.gbuffer),
             &g.buffer(vp.color), &g.buffer(vp.depth), plan.options.msaa,
             static_cast<int>(gp.depthLayers), gp.huang || gp.points ? gp.hairBox : PixelRect{}},
            &r.profiler);
      });
}

}  // namespace clhair
