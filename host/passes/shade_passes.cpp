// shade_passes.cpp — a groom's deferred shading, filter and composite (passes.h).
#include "passes/passes.h"

namespace clhair {

ShadeStage::Params shadeParams(Renderer::Impl& r, const FramePlan& plan, const GroomPlan& gp,
                               const cl::Buffer& view, const cl::Buffer& groom,
                               const cl::Buffer& gbuffer, cl::Buffer& hair) {
  GroomInstanceGpu& inst = *gp.draw.state;
  ShadeStage::Params sp;
  sp.target = viewTarget(plan, view);
  sp.lighting = r.scene.lighting(r.shadows.maps());
  sp.groom = &groom;
  sp.offsets = &inst.offsets;
  sp.records = inst.records;
  sp.gbuffer = &gbuffer;
  sp.hair = &hair;
  sp.msaa = plan.options.msaa;
  const VisibilityGpu::Inputs v = r.visibility.inputs(gp.index);
  sp.visibility = v.record;
  sp.visibilityTable = v.table;
  sp.visibilityCells = v.cells;
  sp.aoField = v.aoField;
  sp.aoFieldVoxels = v.aoFieldVoxels;
  sp.cover = plan.cover;
  return sp;
}

void addShadePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp, ViewPlan& vp) {
  GroomView& gv = gp.views[vp.index];
  gv.result = gv.hair;
  struct Data {
    GroomInView in;
    FrameGraph::Handle hair;
  };
  g.addPass<Data>(
      "shade " + std::to_string(gp.index) + vp.suffix,
      [&](FrameGraph::Setup& s, Data& d) {
        d.in = readGroomInView(s, vp, gp);
        s.reads({plan.scene_, plan.shadowMaps, gp.lod, plan.visibility});
        d.hair = s.write(gv.hair);
        s.kernel("shade_deferred");
        if (plan.severalViews()) declareViewDraw(s, plan, gp, vp);
      },
      [&](const Data& d, const FrameGraph::Resources& res) {
        if (plan.severalViews()) drawInView(r, plan, gp, vp, res);
        r.shade.enqueue(shadeParams(r, plan, gp, res[d.in.view], res[d.in.groom], res[d.in.gbuffer],
                                    res[d.hair]),
                        &r.profiler);
      });
}

void addFilterPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp, ViewPlan& vp) {
  GroomView& gv = gp.views[vp.index];
  struct Data {
    GroomInView in;
    FrameGraph::Handle hair, filtered;
  };
  if (!gp.huang) {
    gv.result = gv.filteredHair;
    g.addPass<Data>(
        "filter " + std::to_string(gp.index) + vp.suffix,
        [&](FrameGraph::Setup& s, Data& d) {
          d.in = readGroomInView(s, vp, gp);
          d.hair = s.read(gv.hair);
          s.writes({plan.filterParams});
          d.filtered = s.write(gv.filteredHair);
          s.kernel("filter_reconstruct");
        },
        [&](const Data& d, const FrameGraph::Resources& res) {
          r.filter.enqueue(*gp.filter,
                           {viewTarget(plan, res[d.in.view]), &res[d.in.groom], &res[d.in.gbuffer],
                            &res[d.hair], &res[d.filtered]},
                           &r.profiler);
        });
    return;
  }
  // Huang's alpha fix into the filter's buffer, then (aniso) the anisotropic filter back (one
  // view)
  gv.result = gp.filter->aniso ? gv.hair : gv.filteredHair;
  struct Fix {
    FrameGraph::Handle hair, filtered, stats;
  };
  g.addPass<Fix>(
      "alpha fix " + std::to_string(gp.index),
      [&](FrameGraph::Setup& s, Fix& d) {
        readGroomInView(s, vp, gp);  // linkParams fetches them
        s.reads({plan.linkState});
        d.hair = s.readWrite(gv.hair);
        d.filtered = s.write(gv.filteredHair);
        d.stats = s.write(plan.frameStats);
        s.kernel("link_alpha").kernel("copy_uints");
        if (gp.filter->aniso) s.kernel("link_aniso");
      },
      [&](const Fix& d, const FrameGraph::Resources& res) {
        r.link.finish(linkParams(plan, gp, res), gp.filter->aniso, res[d.hair], res[d.filtered],
                      &r.profiler);
        // the groom's linking counters, for the frame's statistics
        r.target.copyUints(r.link.counterBuffer(), 0, res[d.stats], plan.linkAt + 4 * gp.index, 4,
                           &r.profiler);
      });
}

void addCompositePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp,
                      ViewPlan& vp) {
  const GroomView& gv = gp.views[vp.index];
  struct Data {
    GroomInView in;
    FrameGraph::Handle hair, color, depth;
  };
  g.addPass<Data>(
      "composite " + std::to_string(gp.index) + vp.suffix,
      [&](FrameGraph::Setup& s, Data& d) {
        d.in = readGroomInView(s, vp, gp);
        d.hair = s.read(gv.result);
        d.color = s.readWrite(vp.color);
        d.depth = s.readWrite(vp.depth);
        s.kernel("composite_over");
      },
      [&](const Data& d, const FrameGraph::Resources& res) {
        r.composite.enqueue(
            {viewTarget(plan, res[d.in.view]), &res[d.in.groom], &res[d.hair], &res[d.in.gbuffer],
             &res[d.color], &res[d.depth], plan.options.msaa, static_cast<int>(gp.depthLayers),
             gp.huang || gp.points ? gp.hairBox : PixelRect{}},
            &r.profiler);
      });
}

}  // namespace clhair
