// view_strand_passes.cpp — a groom's strands in a frame of several views (passes.h): one
// assembly drawn into every view's G-buffer, or each view drawn on its own where the groom
// cannot share one (strand files: their strands are read, not generated). The strands (LOD,
// culling) are those of the first view in which the groom is in front of the camera. Each
// view's scene depth and G-buffer are slices of one buffer (frame/view_targets.h).
#include "cl/buffers.h"
#include "passes/passes.h"

namespace clhair {

namespace {

// How groom `gp` is drawn in view `v`: a faint strand file is widened where its hair is
// filtered (io/faint_groom.h).
ViewDraw drawOf(const FramePlan& plan, const GroomPlan& gp, std::size_t v) {
  ViewDraw d = plan.views[v].draw;
  d.widenFaint = gp.filtered && !plan.cover && !gp.points;
  return d;
}

// The groom's total of strands drawn, into view v's statistics word.
void copyTotal(Renderer::Impl& r, const FramePlan& plan, const GroomPlan& gp, std::size_t v,
               cl::Buffer& stats) {
  const GroomInstanceGpu& inst = *gp.draw.state;
  if (inst.records == 0) return;
  r.target.copyUints(inst.offsets, gpu::clh_lod_drawn_total_at(inst.records), stats,
                     plan.linkAt + v * plan.grooms.size() + gp.index, 1, &r.profiler);
}

}  // namespace

void addViewsStrandPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp) {
  const GroomKernels kernels = gp.draw.groom->kernels();
  struct Data {
    FrameGraph::Handle grooms;  // the groom's record in each view
  };
  g.addPass<Data>(
      "strands " + std::to_string(gp.index) + ", all views",
      [&, kernels](FrameGraph::Setup& s, Data& data) {
        s.reads({plan.views[gp.lodView].record, gp.tables});
        s.reads({plan.viewRecords});
        data.grooms = s.write(plan.viewGrooms);
        s.writes({gp.params, gp.lod});
        for (const ViewPlan& vp : plan.views) s.reads({vp.depth}).writes({vp.gbuffer});
        s.readsWrites({plan.rasterCounters, plan.frameStats});
        s.kernel(kernels.lod).kernel("scan_bundles").kernel("clear_words");
        s.kernel("strands_raster_views").kernel("copy_uints");
        if (plan.mode == DispatchMode::ReadBack) s.hostWait("the groom's strand total");
      },
      [&](const Data& data, const FrameGraph::Resources& res) {
        // each view's record; the LOD view's last, so that the instance holds it for the LOD
        // pass and the assembly
        ViewTargets& vt = r.views;
        const GroomDraw& d = gp.draw;
        const std::size_t V = plan.views.size(), lv = gp.lodView;
        GroomInstanceGpu& inst = *d.state;
        d.groom->useAo(plan.options.ambientOcclusion);
        gp.viewRecords.assign(V, gpu::ClhGroomGpu{});
        for (std::size_t v = V; v-- > 0;) {
          d.groom->prepare(inst, d.instance->transform, drawOf(plan, gp, v));
          gp.viewRecords[v] = inst.params;
        }
        for (std::size_t v = 0; v < V; ++v)
          if (!gp.views[v].inFront) {  // every point behind the eye: nothing is drawn in it
            gpu::ClhGroomGpu& rec = gp.viewRecords[v];
            std::fill(std::begin(rec.obj_to_view), std::end(rec.obj_to_view), 0.0f);
            rec.obj_to_view[11] = -1.0f;
            rec.depth_near = gp.viewRecords[lv].depth_near;
            rec.depth_far = gp.viewRecords[lv].depth_far;
          }
        if (lv != 0) d.groom->prepare(inst, d.instance->transform, drawOf(plan, gp, lv));
        d.groom->lod(inst, res[plan.views[lv].record], &r.profiler);
        r.target.clearWords(vt.gbuffers, V * vt.gbufferStride, &r.profiler);
        upload(r.dev, res[data.grooms], gp.viewRecords.data(), V);
        StrandRaster raster = cameraRaster(r, plan, gp, plan.views[lv], res);
        raster.sceneDepth = &vt.depths;
        raster.gbuffer = &vt.gbuffers;
        raster.pixels = plan.pixels;
        raster.layers = plan.options.msaa + 1;
        raster.ids = false;
        raster.depthStride = vt.depthStride;
        raster.gbufferStride = vt.gbufferStride;
        gp.together = d.groom->rasterViews(inst, raster, vt.grooms, vt.records,
                                           static_cast<std::uint32_t>(V), &r.profiler);
        if (!gp.together) return;
        for (std::size_t v = 0; v < V; ++v)
          if (gp.views[v].inFront) copyTotal(r, plan, gp, v, res[plan.frameStats]);
      });
}

void declareViewDraw(FrameGraph::Setup& s, const FramePlan& plan, const GroomPlan& gp,
                     const ViewPlan& vp) {
  // a groom that draws each view on its own: its own LOD and strands per view
  s.reads({vp.depth, gp.tables}).readsWrites({vp.gbuffer, gp.params, gp.lod});
  s.readsWrites({plan.frameStats, plan.rasterCounters});
  const GroomKernels k = gp.draw.groom->kernels();
  s.kernel(k.lod).kernel("scan_bundles").kernel("clear_words").kernel("copy_uints");
  s.kernel(plan.mode == DispatchMode::Persistent ? k.rasterPersistent : k.raster);
  if (plan.mode == DispatchMode::ReadBack) s.hostWait("the groom's strand total");
}

void drawInView(Renderer::Impl& r, const FramePlan& plan, GroomPlan& gp, const ViewPlan& vp,
                const FrameGraph::Resources& res) {
  GroomInstanceGpu& inst = *gp.draw.state;
  if (gp.together) {
    uploadChanged(r.dev, inst.groom, inst.sent, &gp.viewRecords[vp.index], 1);
    return;
  }
  const GroomDraw& d = gp.draw;
  const int layers = plan.options.msaa + 1;
  d.groom->prepare(inst, d.instance->transform, drawOf(plan, gp, vp.index));
  d.groom->lod(inst, res[vp.record], &r.profiler);
  r.target.clearWords(res[vp.gbuffer], plan.pixels * static_cast<std::size_t>(layers), &r.profiler);
  StrandRaster own = cameraRaster(r, plan, gp, vp, res);
  own.layers = layers;
  own.ids = false;
  d.groom->raster(inst, own, &r.profiler);
  copyTotal(r, plan, gp, vp.index, res[plan.frameStats]);
}

void addViewsRecordPass(FrameGraph& g, GroomPlan& gp) {
  g.addPass(
      "record " + std::to_string(gp.index),
      [&](FrameGraph::Setup& s) { s.reads({gp.params}).sideEffect(); },
      [&](const FrameGraph::Resources&) { gp.draw.state->params = gp.viewRecords[gp.lodView]; });
}

}  // namespace clhair
