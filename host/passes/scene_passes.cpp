// scene_passes.cpp — the frame's resources, the deep opacity maps and the opaque scene
// (passes.h).
#include <algorithm>

#include "cl/buffers.h"
#include "passes/passes.h"

namespace clhair {

namespace {

std::string groomLabel(const GroomPlan& gp) { return "groom " + std::to_string(gp.index); }

// The opaque pass's kernels (analytic primitives, then meshes).
void opaqueKernels(FrameGraph::Setup& s) {
  s.kernel("opaque_render").kernel("mesh_raster").kernel("mesh_resolve").kernel("clear_words");
}

// The frame's statistics buffer, zeroed ahead of the frame: the counters of passes that do
// not run read as 0.
void importStats(FrameGraph& g, Renderer::Impl& r, FramePlan& plan) {
  r.target.clearUints(r.frameStats, std::max<std::size_t>(plan.stats.words, 1), &r.profiler);
  plan.frameStats = g.import("frame statistics", {&r.frameStats}, true, true);
}

// Each view's record uploaded and its target's buffers imported (in a frame of several
// views, every view's record in one table too, which their strand pass reads).
void importViews(FrameGraph& g, Renderer::Impl& r, FramePlan& plan) {
  std::vector<gpu::ClhViewGpu> records;
  for (ViewPlan& vp : plan.views) {
    RenderTarget& t = *vp.target;
    uploadChanged(r.dev, t.view, t.viewSent, &vp.view, 1);
    records.push_back(vp.view);
    vp.record = g.import("view record" + vp.suffix, {&t.view}, true);
    vp.color = g.import("colour" + vp.suffix, {&t.color}, false, true);
    vp.depth = g.import("depth" + vp.suffix, {vp.depthBuffer}, false, true);
    vp.gbuffer = g.import("G-buffer" + vp.suffix, {vp.gbufferBuffer}, true);
  }
  if (!plan.severalViews()) return;
  ViewTargets& vt = r.views;
  uploadChanged(r.dev, vt.records, vt.recordsSent, records.data(), records.size());
  plan.viewRecords = g.import("view records", {&vt.records}, true);
  plan.viewGrooms = g.import("groom records of the views", {&vt.grooms}, false);
}

}  // namespace

void importFrame(FrameGraph& g, Renderer::Impl& r, FramePlan& plan) {
  const Scene& s = plan.scene;
  const RenderOptions& o = plan.options;
  // host records first (staged uploads ahead of every pass of the frame)
  importViews(g, r, plan);
  r.scene.upload(s);
  if (o.rasterStats) {
    const cl_uint zero[4] = {0, 0, 0, 0};
    upload(r.dev, r.target.stats, zero, 4);
  }
  for (const GroomPlan& gp : plan.grooms)
    if (gp.active)
      r.visibility.prepare(
          gp.index, *gp.draw.instance, o.bakedVisibility, o.lodAggregate, o.multipleScattering,
          o.ambientOcclusion ? gp.draw.groom->aoField(s, gp.draw.instance->transform) : nullptr);

  plan.scene_ = g.import("scene", r.scene.buffers(), true);
  plan.shadowMaps = g.import("shadow maps", r.shadows.buffers(), !plan.shadowsRebuilt, true);
  plan.rasterCounters = g.import("raster counters", {&r.target.stats}, true);
  importStats(g, r, plan);
  plan.lodArena = g.import("LOD arena", r.frameLod.buffers(), true);
  plan.visibility = g.import("baked visibility", r.visibility.buffers(), true);
  plan.linkState = g.import("hair linking state", r.link.buffers(), false);
  plan.filterParams = g.import("filter parameters", {&r.filter.params()}, false);
  plan.motionParams = g.import("motion parameters", {&r.target.motionParams}, false);
  for (GroomPlan& gp : plan.grooms) {
    const std::string label = groomLabel(gp);
    GroomInstanceGpu& inst = *gp.draw.state;
    gp.tables = g.import(label + " tables", gp.draw.groom->tables(), true);
    gp.params = g.import(label + " record", {&inst.groom}, true);
    gp.lod = g.import(label + " LOD", {&inst.lod, &inst.counts, &inst.offsets}, false);
    if (o.still != 0) {
      const StoredStrands& st = inst.stored;
      gp.stored = g.import(label + " stored strands",
                           {&st.lod, &st.offsets, &st.pointBase, &st.points, &st.tangents, &st.uvs},
                           true, true);
    }
    if (!gp.active || o.rasterOnly) continue;
    const std::size_t colour = plan.pixels * 4 * sizeof(float);
    for (const ViewPlan& vp : plan.views) {
      GroomView& gv = gp.views[vp.index];
      if (!gv.inFront) continue;
      gv.hair = g.create(label + " hair" + vp.suffix, colour);
      if (gp.filtered) gv.filteredHair = g.create(label + " filtered hair" + vp.suffix, colour);
    }
    if (gp.motion) gp.motionPlane = g.create(label + " motion", plan.pixels * 8);
  }
}

void addShadowPasses(FrameGraph& g, Renderer::Impl& r, FramePlan& plan) {
  if (!plan.shadowsRebuilt) return;
  // the grooms' passes from every light: their LOD, the light's (capped by the camera's) and
  // their strands
  auto groomKernels = [&plan](FrameGraph::Setup& s, bool light) {
    for (const GroomPlan& gp : plan.grooms) {
      s.reads({gp.tables}).writes({gp.params, gp.lod});
      const GroomKernels k = gp.draw.groom->kernels();
      s.kernel(k.lod).kernel("scan_bundles");
      if (light) s.kernel(k.raster).kernel(k.rasterPersistent).kernel(k.opacity);
    }
  };
  g.addPass(
      "shadow maps",
      [&, groomKernels](FrameGraph::Setup& s) {
        s.writes({plan.shadowMaps});
        // the camera's LOD caps the lights' (a frame of one view)
        if (!plan.severalViews()) s.reads({plan.camera().record});
        groomKernels(s, false);
        s.kernel("clear_uints").kernel("copy_uints");
      },
      [&](const FrameGraph::Resources&) {
        std::vector<GroomDraw> draws;
        for (const GroomPlan& gp : plan.grooms) draws.push_back(gp.draw);
        // the camera's LOD caps the light passes (a frame of one view)
        const ViewDraw* camera = plan.severalViews() ? nullptr : &plan.camera().draw;
        r.shadows.begin(plan.scene, plan.options, plan.lodCorrection, draws, camera, &r.profiler);
      });
  for (const std::size_t light : ShadowMaps::mappedLights(plan.scene, plan.grooms.size()))
    g.addPass(
        "shadow map: light " + std::to_string(light),
        [&, groomKernels](FrameGraph::Setup& s) {
          s.reads({plan.scene_}).readsWrites({plan.shadowMaps});
          groomKernels(s, true);
          opaqueKernels(s);
          s.kernel("shadow_resolve_depth").kernel("shadow_clear").kernel("lod_cap");
          s.kernel("copy_uints");
          if (plan.mode == DispatchMode::ReadBack)
            s.hostWait("each groom's strand total from the light (--dispatch readback)");
        },
        [&, light](const FrameGraph::Resources&) {
          r.shadows.drawLight(plan.scene, light, r.scene, plan.mode, &r.profiler);
        });
  g.addPass(
      "shadow maps: the lights' records",
      [&](FrameGraph::Setup& s) { s.readsWrites({plan.shadowMaps}); },
      [&](const FrameGraph::Resources&) { r.shadows.finish(); });
}

void addOpaquePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, ViewPlan& vp) {
  struct Data {
    FrameGraph::Handle view, color, depth;
  };
  g.addPass<Data>(
      "opaque" + vp.suffix,
      [&](FrameGraph::Setup& s, Data& d) {
        d.view = s.read(vp.record);
        s.reads({plan.scene_, plan.shadowMaps});
        d.color = s.write(vp.color);
        d.depth = s.write(vp.depth);
        opaqueKernels(s);
      },
      [&](const Data& d, const FrameGraph::Resources& res) {
        r.scene.drawOpaque(viewTarget(plan, res[d.view]), r.shadows.maps(), res[d.color],
                           res[d.depth], true, &r.profiler);
      });
  if (!plan.source) return;
  // the traced reference's source needs the opaque depth on the host to trace against it
  struct Depth {
    FrameGraph::Handle depth;
  };
  g.addPass<Depth>(
      "opaque depth to the reference",
      [&](FrameGraph::Setup& s, Depth& d) {
        d.depth = s.read(vp.depth);
        s.sideEffect().hostWait("the opaque depth, for the traced reference");
      },
      [&](const Depth& d, const FrameGraph::Resources& res) {
        std::vector<float> depth(plan.pixels);
        readBack(r.dev, "the opaque scene's depth", res[d.depth], depth.data(), plan.pixels);
        plan.source->opaqueDrawn(vp.view, depth);
      });
}

}  // namespace clhair
