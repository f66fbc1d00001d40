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

}  // namespace

void importStats(FrameGraph& g, Renderer::Impl& r, FramePlan& plan) {
  // zeroed ahead of the frame: the counters of passes that do not run read as 0
  r.target.clearUints(r.frameStats, std::max<std::size_t>(plan.stats.words, 1), &r.profiler);
  plan.frameStats = g.import("frame statistics", {&r.frameStats}, true, true);
}

void importFrame(FrameGraph& g, Renderer::Impl& r, FramePlan& plan) {
  RenderTarget& t = *plan.target;
  const Scene& s = plan.scene;
  const RenderOptions& o = plan.options;
  // host records first (staged uploads ahead of every pass of the frame)
  r.scene.upload(s);
  uploadChanged(r.dev, t.view, t.viewSent, &plan.view, 1);
  if (o.rasterStats) {
    const cl_uint zero[4] = {0, 0, 0, 0};
    upload(r.dev, t.stats, zero, 4);
  }
  for (const GroomPlan& gp : plan.grooms)
    if (gp.active)
      r.visibility.prepare(
          gp.index, *gp.draw.instance, o.bakedVisibility, o.lodAggregate, o.multipleScattering,
          o.ambientOcclusion ? gp.draw.groom->aoField(s, gp.draw.instance->transform) : nullptr);

  plan.viewRecord = g.import("view", {&t.view}, true);
  plan.scene_ = g.import("scene", r.scene.buffers(), true);
  plan.shadowMaps = g.import("shadow maps", r.shadows.buffers(), !plan.shadowsRebuilt, true);
  plan.color = g.import("colour", {&t.color}, false, true);
  plan.depth = g.import("depth", {&t.depth}, false, true);
  plan.gbuffer = g.import("G-buffer", {&t.gbuffer}, true);
  plan.rasterCounters = g.import("raster counters", {&t.stats}, true);
  importStats(g, r, plan);
  plan.lodArena = g.import("LOD arena", r.frameLod.buffers(), true);
  plan.visibility = g.import("baked visibility", r.visibility.buffers(), true);
  plan.linkState = g.import("hair linking state", r.link.buffers(), false);
  plan.filterParams = g.import("filter parameters", {&r.filter.params()}, false);
  plan.motionParams = g.import("motion parameters", {&t.motionParams}, false);
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
    gp.hair = g.create(label + " hair", colour);
    if (gp.filtered) gp.filteredHair = g.create(label + " filtered hair", colour);
    if (gp.motion) gp.motionPlane = g.create(label + " motion", plan.pixels * 8);
  }
}

void addShadowPasses(FrameGraph& g, Renderer::Impl& r, FramePlan& plan) {
  if (!plan.shadowsRebuilt) return;
  // the grooms' passes from every light: their LOD, the light's (capped by the camera's) and
  // their strands
  auto groomKernels = [&plan](FrameGraph::Setup& s, bool light) {
    for (const GroomPlan& gp : plan.grooms) {
      s.read(gp.tables).write(gp.params).write(gp.lod);
      const GroomKernels k = gp.draw.groom->kernels();
      s.kernel(k.lod).kernel("scan_bundles");
      if (light) s.kernel(k.raster).kernel(k.rasterPersistent).kernel(k.opacity);
    }
  };
  g.addPass(
      "shadow maps",
      [&, groomKernels](FrameGraph::Setup& s) {
        s.write(plan.shadowMaps);
        if (plan.viewRecord) s.read(plan.viewRecord);  // the camera's LOD caps the lights'
        groomKernels(s, false);
        s.kernel("clear_uints").kernel("copy_uints");
      },
      [&] {
        std::vector<GroomDraw> draws;
        for (const GroomPlan& gp : plan.grooms) draws.push_back(gp.draw);
        // the camera's LOD caps the light passes (a frame of one view)
        const ViewDraw* camera = plan.cameraPass.view ? &plan.cameraPass : nullptr;
        r.shadows.begin(plan.scene, plan.options, plan.lodCorrection, draws, camera, &r.profiler);
      });
  for (const std::size_t light : ShadowMaps::mappedLights(plan.scene, plan.grooms.size()))
    g.addPass(
        "shadow map: light " + std::to_string(light),
        [&, groomKernels](FrameGraph::Setup& s) {
          s.read(plan.scene_).readWrite(plan.shadowMaps);
          groomKernels(s, true);
          opaqueKernels(s);
          s.kernel("shadow_resolve_depth").kernel("shadow_clear").kernel("lod_cap");
          s.kernel("copy_uints");
          if (plan.mode == DispatchMode::ReadBack)
            s.hostWait("each groom's strand total from the light (--dispatch readback)");
        },
        [&, light] { r.shadows.drawLight(plan.scene, light, r.scene, plan.mode, &r.profiler); });
  g.addPass(
      "shadow maps: the lights' records",
      [&](FrameGraph::Setup& s) { s.readWrite(plan.shadowMaps); }, [&] { r.shadows.finish(); });
}

void addOpaquePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan) {
  g.addPass(
      "opaque",
      [&](FrameGraph::Setup& s) {
        s.read(plan.viewRecord).read(plan.scene_).read(plan.shadowMaps);
        s.write(plan.color).write(plan.depth);
        opaqueKernels(s);
      },
      [&] {
        RenderTarget& t = *plan.target;
        r.scene.drawOpaque(t.viewTarget(), r.shadows.maps(), t.color, t.depth, true, &r.profiler);
      });
  if (!plan.source) return;
  // the traced reference's source needs the opaque depth on the host to trace against it
  g.addPass(
      "opaque depth to the reference",
      [&](FrameGraph::Setup& s) {
        s.read(plan.depth).sideEffect().hostWait("the opaque depth, for the traced reference");
      },
      [&] {
        std::vector<float> depth(plan.pixels);
        readBack(r.dev, "the opaque scene's depth", plan.target->depth, depth.data(), plan.pixels);
        plan.source->opaqueDrawn(plan.view, depth);
      });
}

}  // namespace clhair
