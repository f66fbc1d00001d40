// views_frame.cpp — the graph of a frame with several views of one assembly (passes.h).
//
// Every per-view step (opaque scene, shading, filter, composite, read-back) runs once per
// view, and each hair mesh's strands are assembled once per groom and drawn into every
// view's G-buffer (strands_raster_views). The strands (LOD, culling) are those of the first
// view in which the groom is in front of the camera. Strand files draw each view on their
// own (their strands are read, not generated). Each view's scene depth and G-buffer are
// slices of one buffer (frame/view_targets.h).
#include <memory>

#include "cl/buffers.h"
#include "passes/passes.h"
#include "stages/view_math.h"

namespace clhair {

namespace {

// What the passes of one groom share while the frame runs.
struct GroomViews {
  std::vector<bool> inFront;
  std::size_t lodView = 0;
  std::vector<gpu::ClhGroomGpu> records;  // the groom's record in each view
  bool together = true;
};

}  // namespace

void buildViewsFrame(FrameGraph& g, Renderer::Impl& r, FramePlan& plan,
                     const std::vector<Camera>& cameras, PendingFrame& out) {
  const Scene& s = plan.scene;
  const RenderOptions& o = plan.options;
  const std::size_t V = cameras.size();
  ViewTargets& vt = r.views;
  std::vector<gpu::ClhViewGpu> records(V);
  std::vector<ViewDraw> passes(V);
  for (std::size_t v = 0; v < V; ++v) {
    records[v] = makeView(cameras[v], s.width, s.height);
    records[v].samples = static_cast<gpu::clh_u32>(o.msaa);
    records[v].cx += o.jitterX;
    records[v].cy += o.jitterY;
    RenderTarget& t = vt.target(v);
    uploadChanged(r.dev, t.view, t.viewSent, &records[v], 1);
    passes[v].view = &t.view;
    passes[v].worldToView = worldToView(cameras[v]);
    passes[v].lod = o.lod;
    passes[v].lodLambdaScale = o.lodLambdaScale * lodResolutionScale(s.height);
    passes[v].lodStrandScale = o.lodLambdaScale;
    passes[v].trueWidth = o.trueWidth;
    passes[v].shadowLodCorrection = plan.lodCorrection;
    passes[v].pixels = faintView(records[v]);
  }
  uploadChanged(r.dev, vt.records, vt.recordsSent, records.data(), V);
  r.scene.upload(s);
  const std::size_t pixels = plan.pixels;
  const std::size_t layers = static_cast<std::size_t>(o.msaa) + 1;

  plan.scene_ = g.import("scene", r.scene.buffers(), true);
  plan.shadowMaps = g.import("shadow maps", r.shadows.buffers(), !plan.shadowsRebuilt, true);
  importStats(g, r, plan);
  plan.filterParams = g.import("filter parameters", {&r.filter.params()}, false);
  plan.visibility = g.import("baked visibility", r.visibility.buffers(), true);
  plan.rasterCounters = g.import("raster counters", {&r.target.stats}, true);
  std::vector<const cl::Buffer*> depthBufs = {&vt.depths}, gbufferBufs = {&vt.gbuffers};
  for (std::size_t v = 0; v < V; ++v) {
    depthBufs.push_back(&vt.depthSlices[v]);
    gbufferBufs.push_back(&vt.gbufferSlices[v]);
  }
  const FrameGraph::Handle depths = g.import("depth of every view", depthBufs, false, true);
  const FrameGraph::Handle gbuffers = g.import("G-buffers of every view", gbufferBufs, false);
  const FrameGraph::Handle viewRecords = g.import("view records", {&vt.records, &vt.grooms}, true);
  std::vector<FrameGraph::Handle> viewRecord(V), colour(V);
  for (std::size_t v = 0; v < V; ++v) {
    const std::string view = "view " + std::to_string(v);
    viewRecord[v] = g.import(view + " record", {&vt.target(v).view}, true);
    colour[v] = g.import(view + " colour", {&vt.target(v).color}, false, true);
  }
  for (GroomPlan& gp : plan.grooms) {
    const std::string label = "groom " + std::to_string(gp.index);
    gp.tables = g.import(label + " tables", gp.draw.groom->tables(), true);
    gp.params = g.import(label + " record", {&gp.draw.state->groom}, true);
    gp.lod =
        g.import(label + " LOD",
                 {&gp.draw.state->lod, &gp.draw.state->counts, &gp.draw.state->offsets}, false);
  }
  addShadowPass(g, r, plan);
  for (std::size_t v = 0; v < V; ++v)
    g.addPass(
        "opaque, view " + std::to_string(v),
        [&, v](FrameGraph::Setup& st) {
          st.read(viewRecord[v]).read(plan.scene_).read(plan.shadowMaps);
          st.write(colour[v]).write(depths);
          st.kernel("opaque_render").kernel("mesh_raster").kernel("mesh_resolve");
          st.kernel("clear_words");
        },
        [&r, &vt, v] {
          RenderTarget& t = vt.target(v);
          r.scene.drawOpaque(t.viewTarget(), r.shadows.maps(), t.color, vt.depthSlices[v], true,
                             &r.profiler);
        });
  for (GroomPlan& gp : plan.grooms) {
    const GroomDraw d = gp.draw;
    auto gv = std::make_shared<GroomViews>();
    gv->inFront.assign(V, false);
    gv->lodView = V;
    for (std::size_t v = V; v-- > 0;) {
      gv->inFront[v] = d.groom->inFront(d.instance->transform, passes[v].worldToView);
      if (gv->inFront[v]) gv->lodView = v;
    }
    if (gv->lodView == V) continue;
    gp.active = 1;
    const FilterParams& fp = *gp.filter;
    const bool filtered = o.msaa == 1 && (o.filter < 0 ? fp.enabled : o.filter == 1);
    // the shared strand pass writes no identity layer, so "auto" falls back to Lipp's
    // filter here; Huang's asked for by name is refused
    if (filtered &&
        (o.filterMethod < 0 ? fp.method == FilterParams::Method::Huang : o.filterMethod == 1))
      throw Error("groom \"" + d.instance->name +
                  "\": Huang's filter takes one view at a time; render the views one by one "
                  "(--views NAME) or use Lipp's filter");
    // a faint strand file is widened where its hair is filtered (io/faint_groom.h)
    std::vector<ViewDraw> groomPasses = passes;
    for (ViewDraw& vp : groomPasses) vp.widenFaint = filtered && !plan.cover && !gp.points;
    const std::size_t k = gp.index;
    const std::size_t totalsAt = plan.linkAt;  // the views' strand totals: V x D words
    const std::size_t D = plan.grooms.size();
    const GroomKernels kernels = d.groom->kernels();
    g.addPass(
        "strands " + std::to_string(k) + ", all views",
        [&, kernels](FrameGraph::Setup& st) {
          st.read(viewRecord[gv->lodView]).read(viewRecords).read(gp.tables);
          st.write(gp.params).write(gp.lod).read(depths).write(gbuffers);
          st.readWrite(plan.rasterCounters).readWrite(plan.frameStats);
          st.kernel(kernels.lod).kernel("scan_bundles").kernel("clear_words");
          st.kernel("strands_raster_views").kernel("copy_uints");
          if (plan.mode == DispatchMode::ReadBack) st.hostWait("the groom's strand total");
        },
        [&, gv, groomPasses, d, k, totalsAt, D, V, pixels, layers] {
          // each view's record (transform, depth mapping); the LOD view's last, so that the
          // instance holds it for the LOD pass and the assembly
          GroomInstanceGpu& inst = *d.state;
          d.groom->useAo(plan.options.ambientOcclusion != 0);
          gv->records.assign(V, gpu::ClhGroomGpu{});
          for (std::size_t v = V; v-- > 0;) {
            d.groom->prepare(inst, d.instance->transform, groomPasses[v]);
            gv->records[v] = inst.params;
          }
          const std::size_t lv = gv->lodView;
          for (std::size_t v = 0; v < V; ++v)
            if (!gv->inFront[v]) {  // every point behind the eye: nothing is drawn in this view
              gpu::ClhGroomGpu& rec = gv->records[v];
              std::fill(std::begin(rec.obj_to_view), std::end(rec.obj_to_view), 0.0f);
              rec.obj_to_view[11] = -1.0f;
              rec.depth_near = gv->records[lv].depth_near;
              rec.depth_far = gv->records[lv].depth_far;
            }
          if (lv != 0) d.groom->prepare(inst, d.instance->transform, groomPasses[lv]);
          d.groom->lod(inst, vt.target(lv).view, &r.profiler);
          r.target.clearWords(vt.gbuffers, V * vt.gbufferStride, &r.profiler);
          upload(r.dev, vt.grooms, gv->records.data(), V);
          StrandRaster raster = cameraRaster(r, plan, gp);
          raster.view = &vt.target(lv).view;
          raster.sceneDepth = &vt.depths;
          raster.gbuffer = &vt.gbuffers;
          raster.pixels = pixels;
          raster.layers = static_cast<int>(layers);
          raster.ids = false;
          raster.depthStride = vt.depthStride;
          raster.gbufferStride = vt.gbufferStride;
          gv->together = d.groom->rasterViews(inst, raster, vt.grooms, vt.records,
                                              static_cast<std::uint32_t>(V), &r.profiler);
          if (!gv->together || inst.records == 0) return;
          for (std::size_t v = 0; v < V; ++v)
            if (gv->inFront[v])
              r.target.copyUints(inst.offsets, gpu::clh_lod_drawn_total_at(inst.records),
                                 r.frameStats, totalsAt + v * D + k, 1, &r.profiler);
        });
    for (std::size_t v = 0; v < V; ++v) {
      if (!gv->inFront[v]) continue;
      const std::string name = std::to_string(k) + ", view " + std::to_string(v);
      const FrameGraph::Handle hair = g.create("groom " + name + " hair", pixels * 16);
      const FrameGraph::Handle filteredHair =
          filtered ? g.create("groom " + name + " filtered hair", pixels * 16) : hair;
      g.addPass(
          "shade " + name,
          [&, v, hair, kernels](FrameGraph::Setup& st) {
            st.read(viewRecord[v]).read(plan.scene_).read(plan.shadowMaps).read(gbuffers);
            st.read(depths).read(gp.tables).readWrite(gp.params).readWrite(gp.lod);
            st.read(plan.visibility).write(hair).readWrite(plan.frameStats);
            st.readWrite(plan.rasterCounters).kernel("shade_deferred");
            // a groom that draws each view on its own: its own LOD and strands per view
            st.kernel(kernels.lod)
                .kernel("scan_bundles")
                .kernel("clear_words")
                .kernel("copy_uints");
            st.kernel(plan.mode == DispatchMode::Persistent ? kernels.rasterPersistent
                                                            : kernels.raster);
            if (plan.mode == DispatchMode::ReadBack) st.hostWait("the groom's strand total");
          },
          [&, gv, groomPasses, d, v, k, totalsAt, D, hair, pixels, layers] {
            RenderTarget& t = vt.target(v);
            GroomInstanceGpu& inst = *d.state;
            cl::Buffer& gbuffer = vt.gbufferSlices[v];
            if (!gv->together) {
              d.groom->prepare(inst, d.instance->transform, groomPasses[v]);
              d.groom->lod(inst, t.view, &r.profiler);
              r.target.clearWords(gbuffer, pixels * layers, &r.profiler);
              StrandRaster own = cameraRaster(r, plan, gp);
              own.view = &t.view;
              own.sceneDepth = &vt.depthSlices[v];
              own.gbuffer = &gbuffer;
              own.layers = static_cast<int>(layers);
              own.ids = false;
              d.groom->raster(inst, own, &r.profiler);
              if (inst.records > 0)
                r.target.copyUints(inst.offsets, gpu::clh_lod_drawn_total_at(inst.records),
                                   r.frameStats, totalsAt + v * D + k, 1, &r.profiler);
            } else {
              uploadChanged(r.dev, inst.groom, inst.sent, &gv->records[v], 1);
            }
            r.shade.enqueue(shadeParams(r, t, gp, gbuffer, g.buffer(hair), plan.options.msaa),
                            &r.profiler);
          });
      if (filtered)
        g.addPass(
            "filter " + name,
            [&, v, hair, filteredHair](FrameGraph::Setup& st) {
              st.read(viewRecord[v]).read(gp.params).read(gbuffers).read(hair);
              st.write(plan.filterParams).write(filteredHair).kernel("filter_reconstruct");
            },
            [&, v, d, hair, filteredHair] {
              RenderTarget& t = vt.target(v);
              r.filter.enqueue(fp,
                               {t.viewTarget(), &d.state->groom, &vt.gbufferSlices[v],
                                &g.buffer(hair), &g.buffer(filteredHair)},
                               &r.profiler);
            });
      g.addPass(
          "composite " + name,
          [&, v, filteredHair](FrameGraph::Setup& st) {
            st.read(viewRecord[v]).read(gp.params).read(gbuffers).read(filteredHair);
            st.readWrite(colour[v]).readWrite(depths).kernel("composite_over");
          },
          [&, v, d, filteredHair, filtered] {
            RenderTarget& t = vt.target(v);
            r.composite.enqueue({t.viewTarget(), &d.state->groom, &g.buffer(filteredHair),
                                 &vt.gbufferSlices[v], &t.color, &vt.depthSlices[v],
                                 plan.options.msaa, filtered ? 2 : plan.options.msaa, PixelRect{}},
                                &r.profiler);
          });
    }
    g.addPass(
        "record " + std::to_string(k),
        [&](FrameGraph::Setup& st) { st.read(gp.params).sideEffect(); },
        [gv, d] { d.state->params = gv->records[gv->lodView]; });
  }
  g.addPass(
      "read-back",
      [&, V](FrameGraph::Setup& st) {
        st.read(depths).readWrite(plan.frameStats).read(plan.shadowMaps).sideEffect();
        st.kernel("copy_uints");
        for (std::size_t v = 0; v < V; ++v) st.read(colour[v]);
      },
      [&r, &vt, &out, V, pixels, at = plan.shadowAt, words = plan.stats.words, w = s.width,
       h = s.height, depth = o.readBackDepth] {
        if (words != at && r.shadows.totals()())
          r.target.copyUints(r.shadows.totals(), 0, r.frameStats, at, words - at, &r.profiler);
        out.stats.assign(words, 0u);
        out.read(r.dev, r.pinned, r.frameStats, 0, out.stats.data(), words * 4);
        for (std::size_t v = 0; v < V; ++v) {
          Frame& f = out.frames[v];
          f.color.width = w;
          f.color.height = h;
          f.color.rgba.resize(pixels * 4);
          out.read(r.dev, r.pinned, vt.target(v).color, 0, f.color.rgba.data(), pixels * 16);
          if (!depth) continue;
          f.depth.resize(pixels);
          out.read(r.dev, r.pinned, vt.depthSlices[v], 0, f.depth.data(), pixels * 4);
        }
      });
  out.finishers.push_back([V, D = plan.grooms.size(), totalsAt = plan.linkAt,
                           shadowAt = plan.shadowAt](PendingFrame& p) {
    std::uint64_t shadow = 0;
    for (std::size_t i = shadowAt; i < p.stats.size(); ++i) shadow += p.stats[i];
    for (std::size_t v = 0; v < V; ++v) {
      FrameStats& st = p.frames[v].stats;
      for (std::size_t k = 0; k < D; ++k) st.strandsDrawn += p.stats[totalsAt + v * D + k];
      st.shadowStrandsDrawn = shadow;
    }
  });
}

}  // namespace clhair
