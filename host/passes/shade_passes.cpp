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

void addShadePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp) {
  gp.result = gp.hair;
  g.addPass(
      "shade " + std::to_string(gp.index),
      [&](FrameGraph::Setup& s) {
        s.read(plan.viewRecord).read(plan.scene_).read(plan.shadowMaps).read(plan.gbuffer);
        s.read(gp.params).read(gp.lod).read(plan.visibility).write(gp.hair);
        s.kernel("shade_deferred");
      },
      [&] {
        RenderTarget& t = *plan.target;
        ShadeStage::Params sp =
            shadeParams(r, t, gp, t.gbuffer, g.buffer(gp.hair), plan.options.msaa);
        sp.cover = plan.cover;
        r.shade.enqueue(sp, &r.profiler);
      });
}

void addFilterPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp) {
  if (!gp.huang) {
    gp.result = gp.filteredHair;
    g.addPass(
        "filter " + std::to_string(gp.index),
        [&](FrameGraph::Setup& s) {
          s.read(plan.viewRecord).read(gp.params).read(plan.gbuffer).read(gp.hair);
          s.write(plan.filterParams).write(gp.filteredHair).kernel("filter_reconstruct");
        },
        [&] {
          RenderTarget& t = *plan.target;
          r.filter.enqueue(*gp.filter,
                           {t.viewTarget(), &gp.draw.state->groom, &t.gbuffer, &g.buffer(gp.hair),
                            &g.buffer(gp.filteredHair)},
                           &r.profiler);
        });
    return;
  }
  // Huang's alpha fix into the filter's buffer, then (aniso) the anisotropic filter back
  gp.result = gp.filter->aniso ? gp.hair : gp.filteredHair;
  g.addPass(
      "alpha fix " + std::to_string(gp.index),
      [&](FrameGraph::Setup& s) {
        s.read(plan.viewRecord).read(gp.params).read(plan.gbuffer).read(plan.linkState);
        s.readWrite(gp.hair).write(gp.filteredHair).write(plan.frameStats);
        s.kernel("link_alpha").kernel("copy_uints");
        if (gp.filter->aniso) s.kernel("link_aniso");
      },
      [&] {
        r.link.finish(linkParams(plan, gp), gp.filter->aniso, g.buffer(gp.hair),
                      g.buffer(gp.filteredHair), &r.profiler);
        // the groom's linking counters, for the frame's statistics
        r.target.copyUints(r.link.counterBuffer(), 0, r.frameStats, plan.linkAt + 4 * gp.index, 4,
                           &r.profiler);
      });
}

void addCompositePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp) {
  g.addPass(
      "composite " + std::to_string(gp.index),
      [&](FrameGraph::Setup& s) {
        s.read(plan.viewRecord).read(gp.params).read(plan.gbuffer).read(gp.result);
        s.readWrite(plan.color).readWrite(plan.depth).kernel("composite_over");
      },
      [&] {
        RenderTarget& t = *plan.target;
        r.composite.enqueue(
            {t.viewTarget(), &gp.draw.state->groom, &g.buffer(gp.result), &t.gbuffer, &t.color,
             &t.depth, plan.options.msaa, static_cast<int>(gp.depthLayers),
             gp.huang || gp.points ? gp.hairBox : PixelRect{}},
            &r.profiler);
      });
}

}  // namespace clhair
