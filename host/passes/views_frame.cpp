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

// What every view's passes share: the views' settings and the graph's handles of their
// records, targets and the slices' buffers.
struct Views {
  std::size_t count = 0, pixels = 0, layers = 0;
  std::vector<ViewDraw> draws;  // how a groom is drawn in each view
  FrameGraph::Handle depths, gbuffers, records;
  std::vector<FrameGraph::Handle> record, colour;  // per view
};

// The views' records uploaded, the frame's resources imported.
std::shared_ptr<Views> importViews(FrameGraph& g, Renderer::Impl& r, FramePlan& plan,
                                   const std::vector<Camera>& cameras) {
  const Scene& s = plan.scene;
  const RenderOptions& o = plan.options;
  ViewTargets& vt = r.views;
  auto views = std::make_shared<Views>();
  Views& w = *views;
  w.count = cameras.size();
  w.pixels = plan.pixels;
  w.layers = static_cast<std::size_t>(o.msaa) + 1;
  std::vector<gpu::ClhViewGpu> records(w.count);
  w.draws.resize(w.count);
  for (std::size_t v = 0; v < w.count; ++v) {
    records[v] = makeView(cameras[v], s.width, s.height);
    records[v].samples = static_cast<gpu::clh_u32>(o.msaa);
    records[v].cx += o.jitterX;
    records[v].cy += o.jitterY;
    RenderTarget& t = vt.target(v);
    uploadChanged(r.dev, t.view, t.viewSent, &records[v], 1);
    ViewDraw& d = w.draws[v];
    d.view = &t.view;
    d.worldToView = worldToView(cameras[v]);
    d.lod = o.lod;
    d.lodLambdaScale = o.lodLambdaScale * lodResolutionScale(s.height);
    d.lodStrandScale = o.lodLambdaScale;
    d.trueWidth = o.trueWidth;
    d.shadowLodCorrection = plan.lodCorrection;
    d.pixels = faintView(records[v]);
  }
  uploadChanged(r.dev, vt.records, vt.recordsSent, records.data(), w.count);
  r.scene.upload(s);

  plan.scene_ = g.import("scene", r.scene.buffers(), true);
  plan.shadowMaps = g.import("shadow maps", r.shadows.buffers(), !plan.shadowsRebuilt, true);
  importStats(g, r, plan);
  plan.filterParams = g.import("filter parameters", {&r.filter.params()}, false);
  plan.visibility = g.import("baked visibility", r.visibility.buffers(), true);
  plan.rasterCounters = g.import("raster counters", {&r.target.stats}, true);
  std::vector<const cl::Buffer*> depthBufs = {&vt.depths}, gbufferBufs = {&vt.gbuffers};
  for (std::size_t v = 0; v < w.count; ++v) {
    depthBufs.push_back(&vt.depthSlices[v]);
    gbufferBufs.push_back(&vt.gbufferSlices[v]);
  }
  w.depths = g.import("depth of every view", depthBufs, false, true);
  w.gbuffers = g.import("G-buffers of every view", gbufferBufs, false);
  w.records = g.import("view records", {&vt.records, &vt.grooms}, true);
  w.record.resize(w.count);
  w.colour.resize(w.count);
  for (std::size_t v = 0; v < w.count; ++v) {
    const std::string view = "view " + std::to_string(v);
    w.record[v] = g.import(view + " record", {&vt.target(v).view}, true);
    w.colour[v] = g.import(view + " colour", {&vt.target(v).color}, false, true);
  }
  for (GroomPlan& gp : plan.grooms) {
    const std::string label = "groom " + std::to_string(gp.index);
    gp.tables = g.import(label + " tables", gp.draw.groom->tables(), true);
    gp.params = g.import(label + " record", {&gp.draw.state->groom}, true);
    gp.lod =
        g.import(label + " LOD",
                 {&gp.draw.state->lod, &gp.draw.state->counts, &gp.draw.state->offsets}, false);
  }
  return views;
}

void addOpaquePasses(FrameGraph& g, Renderer::Impl& r, FramePlan& plan,
                     const std::shared_ptr<Views>& views) {
  for (std::size_t v = 0; v < views->count; ++v)
    g.addPass(
        "opaque, view " + std::to_string(v),
        [&, views, v](FrameGraph::Setup& st) {
          st.read(views->record[v]).read(plan.scene_).read(plan.shadowMaps);
          st.write(views->colour[v]).write(views->depths);
          st.kernel("opaque_render").kernel("mesh_raster").kernel("mesh_resolve");
          st.kernel("clear_words");
        },
        [&r, v] {
          ViewTargets& vt = r.views;
          RenderTarget& t = vt.target(v);
          r.scene.drawOpaque(t.viewTarget(), r.shadows.maps(), t.color, vt.depthSlices[v], true,
                             &r.profiler);
        });
}

// Each view's record of the groom (transform, depth mapping), its LOD from its first view in
// front and its strands assembled once and drawn into every view (strands_raster_views).
void addSharedStrandPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan,
                         const std::shared_ptr<Views>& views, GroomPlan& gp,
                         const std::shared_ptr<GroomViews>& gv,
                         const std::vector<ViewDraw>& draws) {
  const GroomDraw d = gp.draw;
  const std::size_t k = gp.index, D = plan.grooms.size();
  const std::size_t totalsAt = plan.linkAt;  // the views' strand totals: V x D words
  const GroomKernels kernels = d.groom->kernels();
  g.addPass(
      "strands " + std::to_string(k) + ", all views",
      [&, views, gv, kernels](FrameGraph::Setup& st) {
        st.read(views->record[gv->lodView]).read(views->records).read(gp.tables);
        st.write(gp.params).write(gp.lod).read(views->depths).write(views->gbuffers);
        st.readWrite(plan.rasterCounters).readWrite(plan.frameStats);
        st.kernel(kernels.lod).kernel("scan_bundles").kernel("clear_words");
        st.kernel("strands_raster_views").kernel("copy_uints");
        if (plan.mode == DispatchMode::ReadBack) st.hostWait("the groom's strand total");
      },
      [&, views, gv, draws, d, k, totalsAt, D] {
        // each view's record; the LOD view's last, so that the instance holds it for the LOD
        // pass and the assembly
        ViewTargets& vt = r.views;
        const std::size_t V = views->count;
        GroomInstanceGpu& inst = *d.state;
        d.groom->useAo(plan.options.ambientOcclusion);
        gv->records.assign(V, gpu::ClhGroomGpu{});
        for (std::size_t v = V; v-- > 0;) {
          d.groom->prepare(inst, d.instance->transform, draws[v]);
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
        if (lv != 0) d.groom->prepare(inst, d.instance->transform, draws[lv]);
        d.groom->lod(inst, vt.target(lv).view, &r.profiler);
        r.target.clearWords(vt.gbuffers, V * vt.gbufferStride, &r.profiler);
        upload(r.dev, vt.grooms, gv->records.data(), V);
        StrandRaster raster = cameraRaster(r, plan, gp);
        raster.view = &vt.target(lv).view;
        raster.sceneDepth = &vt.depths;
        raster.gbuffer = &vt.gbuffers;
        raster.pixels = views->pixels;
        raster.layers = static_cast<int>(views->layers);
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
}

// View v of the groom: shaded (drawn on its own first when its strands could not be drawn
// into every view at once), filtered, composited.
void addViewPasses(FrameGraph& g, Renderer::Impl& r, FramePlan& plan,
                   const std::shared_ptr<Views>& views, GroomPlan& gp,
                   const std::shared_ptr<GroomViews>& gv, const std::vector<ViewDraw>& draws,
                   std::size_t v, bool filtered) {
  const GroomDraw d = gp.draw;
  const std::size_t k = gp.index, D = plan.grooms.size(), totalsAt = plan.linkAt;
  const std::size_t pixels = views->pixels, layers = views->layers;
  const GroomKernels kernels = d.groom->kernels();
  const std::string name = std::to_string(k) + ", view " + std::to_string(v);
  const FrameGraph::Handle hair = g.create("groom " + name + " hair", pixels * 16);
  const FrameGraph::Handle filteredHair =
      filtered ? g.create("groom " + name + " filtered hair", pixels * 16) : hair;
  g.addPass(
      "shade " + name,
      [&, views, v, hair, kernels](FrameGraph::Setup& st) {
        st.read(views->record[v]).read(plan.scene_).read(plan.shadowMaps).read(views->gbuffers);
        st.read(views->depths).read(gp.tables).readWrite(gp.params).readWrite(gp.lod);
        st.read(plan.visibility).write(hair).readWrite(plan.frameStats);
        st.readWrite(plan.rasterCounters).kernel("shade_deferred");
        // a groom that draws each view on its own: its own LOD and strands per view
        st.kernel(kernels.lod).kernel("scan_bundles").kernel("clear_words").kernel("copy_uints");
        st.kernel(plan.mode == DispatchMode::Persistent ? kernels.rasterPersistent
                                                        : kernels.raster);
        if (plan.mode == DispatchMode::ReadBack) st.hostWait("the groom's strand total");
      },
      [&, gv, draws, d, v, k, totalsAt, D, hair, pixels, layers] {
        ViewTargets& vt = r.views;
        RenderTarget& t = vt.target(v);
        GroomInstanceGpu& inst = *d.state;
        cl::Buffer& gbuffer = vt.gbufferSlices[v];
        if (!gv->together) {
          d.groom->prepare(inst, d.instance->transform, draws[v]);
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
        [&, views, v, hair, filteredHair](FrameGraph::Setup& st) {
          st.read(views->record[v]).read(gp.params).read(views->gbuffers).read(hair);
          st.write(plan.filterParams).write(filteredHair).kernel("filter_reconstruct");
        },
        [&, v, d, hair, filteredHair] {
          RenderTarget& t = r.views.target(v);
          r.filter.enqueue(*gp.filter,
                           {t.viewTarget(), &d.state->groom, &r.views.gbufferSlices[v],
                            &g.buffer(hair), &g.buffer(filteredHair)},
                           &r.profiler);
        });
  g.addPass(
      "composite " + name,
      [&, views, v, filteredHair](FrameGraph::Setup& st) {
        st.read(views->record[v]).read(gp.params).read(views->gbuffers).read(filteredHair);
        st.readWrite(views->colour[v]).readWrite(views->depths).kernel("composite_over");
      },
      [&, v, d, filteredHair, filtered] {
        RenderTarget& t = r.views.target(v);
        r.composite.enqueue({t.viewTarget(), &d.state->groom, &g.buffer(filteredHair),
                             &r.views.gbufferSlices[v], &t.color, &r.views.depthSlices[v],
                             plan.options.msaa, filtered ? 2 : plan.options.msaa, PixelRect{}},
                            &r.profiler);
      });
}

// The groom's passes in every view it is in front of.
void addGroomPasses(FrameGraph& g, Renderer::Impl& r, FramePlan& plan,
                    const std::shared_ptr<Views>& views, GroomPlan& gp) {
  const RenderOptions& o = plan.options;
  const GroomDraw d = gp.draw;
  const std::size_t V = views->count;
  auto gv = std::make_shared<GroomViews>();
  gv->inFront.assign(V, false);
  gv->lodView = V;
  for (std::size_t v = V; v-- > 0;) {
    gv->inFront[v] = d.groom->inFront(d.instance->transform, views->draws[v].worldToView);
    if (gv->inFront[v]) gv->lodView = v;
  }
  if (gv->lodView == V) return;
  gp.active = 1;
  const FilterParams& fp = *gp.filter;
  const bool filtered = o.msaa == 1 && isOn(o.filter, fp.enabled);
  // the shared strand pass writes no identity layer, so "auto" falls back to Lipp's filter
  // here; Huang's asked for by name is refused
  if (filtered && o.filterMethod.value_or(fp.method) == FilterParams::Method::Huang)
    throw Error("groom \"" + d.instance->name +
                "\": Huang's filter takes one view at a time; render the views one by one "
                "(--views NAME) or use Lipp's filter");
  // a faint strand file is widened where its hair is filtered (io/faint_groom.h)
  std::vector<ViewDraw> draws = views->draws;
  for (ViewDraw& vd : draws) vd.widenFaint = filtered && !plan.cover && !gp.points;
  addSharedStrandPass(g, r, plan, views, gp, gv, draws);
  for (std::size_t v = 0; v < V; ++v)
    if (gv->inFront[v]) addViewPasses(g, r, plan, views, gp, gv, draws, v, filtered);
  g.addPass(
      "record " + std::to_string(gp.index),
      [&](FrameGraph::Setup& st) { st.read(gp.params).sideEffect(); },
      [gv, d] { d.state->params = gv->records[gv->lodView]; });
}

// Every view's colour (and depth) and the frame's statistics read back.
void addReadBack(FrameGraph& g, Renderer::Impl& r, FramePlan& plan,
                 const std::shared_ptr<Views>& views, PendingFrame& out) {
  const std::size_t V = views->count;
  g.addPass(
      "read-back",
      [&, views](FrameGraph::Setup& st) {
        st.read(views->depths).readWrite(plan.frameStats).read(plan.shadowMaps).sideEffect();
        st.kernel("copy_uints");
        for (std::size_t v = 0; v < views->count; ++v) st.read(views->colour[v]);
      },
      [&r, &out, V, pixels = views->pixels, at = plan.shadowAt, words = plan.stats.words,
       w = plan.scene.width, h = plan.scene.height, depth = plan.options.readBackDepth] {
        ViewTargets& vt = r.views;
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

}  // namespace

void buildViewsFrame(FrameGraph& g, Renderer::Impl& r, FramePlan& plan,
                     const std::vector<Camera>& cameras, PendingFrame& out) {
  const std::shared_ptr<Views> views = importViews(g, r, plan, cameras);
  addShadowPasses(g, r, plan);
  addOpaquePasses(g, r, plan, views);
  for (GroomPlan& gp : plan.grooms) addGroomPasses(g, r, plan, views, gp);
  addReadBack(g, r, plan, views, out);
}

}  // namespace clhair
