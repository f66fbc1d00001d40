// point_passes.cpp — a groom shaded once per visible strand point (passes.h; DESIGN.md,
// "Shading once per visible strand point"), in place of the per-sample shading pass:
//   point marks   the points of every sample's segment marked in a bitmap over the groom's
//                 point space, and their ranks (a marked point's slot);
//   point inputs  the strand kernels' point pass: the strands that own a marked point are
//                 assembled again (strands are never stored) and write the marked points'
//                 world position and G-buffer word at their slots;
//   shade points  each listed point shaded once (BSDF, every light with its map,
//                 environment, AO, baked visibility), then every sample takes the colour
//                 interpolated along its segment, the pixel their mean, alpha the share of
//                 samples hit.
// The lists are buffers of the frame's graph, sized by the groom's point space and by two
// points per sample of its screen box.
#include "passes/passes.h"

namespace clhair {

namespace {

// The handles of a groom's lists, and their buffers in a pass (those the pass declared; the
// others are left null).
struct PointHandles {
  PointStage::Sizes sizes;
  FrameGraph::Handle bits, blocks, ranks, records, colors;
  PointStage::Lists lists(const FrameGraph::Resources& res) const {
    const auto of = [&](FrameGraph::Handle h) { return res.declared(h) ? &res[h] : nullptr; };
    PointStage::Lists l;
    l.sizes = sizes;
    l.bits = of(bits);
    l.blocks = of(blocks);
    l.offsets = of(ranks);
    l.records = of(records);
    l.colors = of(colors);
    return l;
  }
};

// The groom's lists, created in the graph for its screen box `box`.
PointHandles createLists(FrameGraph& g, const FramePlan& plan, const GroomPlan& gp,
                         const PixelRect& box) {
  const std::string label = "groom " + std::to_string(gp.index);
  PointHandles h;
  h.sizes = PointStage::sizes(gp.draw.groom->pointSpace(), box.pixels(), plan.options.msaa);
  h.bits = g.create(label + " marked points", h.sizes.bitsBytes());
  h.blocks = g.create(label + " point blocks", h.sizes.blocksBytes());
  h.ranks = g.create(label + " point ranks", h.sizes.offsetsBytes());
  h.records = g.create(label + " point records", h.sizes.recordsBytes());
  h.colors = g.create(label + " point colours", h.sizes.colorsBytes());
  return h;
}

}  // namespace

void addPointShadePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp) {
  const PixelRect box = gp.box.clipped(plan.scene.width, plan.scene.height);
  // the lists live while the frame's graph does (the passes below capture them by value)
  const PointHandles h = createLists(g, plan, gp, box);
  gp.views[0].result = gp.views[0].hair;
  const std::string n = std::to_string(gp.index);

  struct Data {
    FrameGraph::Handle view, gbuffer, stats;
  };
  g.addPass<Data>(
      "point marks " + n,
      [&, h](FrameGraph::Setup& s, Data& d) {
        d.view = s.read(plan.camera().record);
        d.gbuffer = s.read(plan.camera().gbuffer);
        s.writes({h.bits, h.blocks, h.ranks});
        d.stats = s.write(plan.frameStats);
        s.kernel("points_mark").kernel("points_count").kernel("points_scan");
        s.kernel("points_offsets").kernel("clear_uints").kernel("copy_uints");
      },
      [&, h, box](const Data& d, const FrameGraph::Resources& res) {
        const PointStage::Lists l = h.lists(res);
        r.points.mark(viewTarget(plan, res[d.view]), res[d.gbuffer], gp.layers, plan.options.msaa,
                      box, l, &r.profiler);
        r.points.rank(l, &r.profiler);
        // the groom's marked points, for the frame's statistics
        r.target.copyUints(*l.offsets, l.sizes.words, res[d.stats], plan.pointsAt + gp.index, 1,
                           &r.profiler);
      });

  g.addPass(
      "point inputs " + n,
      [&, h](FrameGraph::Setup& s) {
        const ViewPlan& camera = plan.camera();
        s.reads({camera.record, camera.depth, gp.tables, gp.params, gp.lod, camera.gbuffer});
        s.readsWrites({plan.rasterCounters}).reads({h.bits, h.ranks}).writes({h.records});
        s.kernel(gp.draw.groom->kernels().raster);
        if (plan.mode == DispatchMode::ReadBack)
          s.hostWait("the groom's strand total for the point pass (--dispatch readback)");
      },
      [&, h](const FrameGraph::Resources& res) {
        const PointStage::Lists l = h.lists(res);
        const PointLists pass = l.pass();
        StrandRaster inputs = cameraRaster(r, plan, gp, plan.camera(), res);
        inputs.pointIds = false;
        inputs.points = &pass;
        inputs.stats = false;
        if (inputs.mode == DispatchMode::Persistent) inputs.mode = DispatchMode::OverLaunch;
        gp.draw.groom->raster(*gp.draw.state, inputs, &r.profiler);
      });

  struct Shade {
    GroomInView in;
    FrameGraph::Handle hair;
  };
  g.addPass<Shade>(
      "shade points " + n,
      [&, h](FrameGraph::Setup& s, Shade& d) {
        d.in = readGroomInView(s, plan.camera(), gp);
        s.reads({plan.scene_, plan.shadowMaps, gp.lod, plan.visibility});
        s.reads({h.records, h.bits, h.ranks}).writes({h.colors});
        d.hair = s.write(gp.views[0].hair);
        s.kernel("shade_points").kernel("points_resolve");
      },
      [&, h](const Shade& d, const FrameGraph::Resources& res) {
        const PointStage::Lists l = h.lists(res);
        // the inputs of per-sample shading (its G-buffer and hair are not read)
        const ShadeStage::Params sp = shadeParams(r, plan, gp, res[d.in.view], res[d.in.groom],
                                                  res[d.in.gbuffer], res[d.hair]);
        r.shade.enqueuePoints(sp, l, &r.profiler);
        r.points.resolve(viewTarget(plan, res[d.in.view]), res[d.in.gbuffer], gp.layers,
                         plan.options.msaa, gp.hairBox, l, res[d.hair], &r.profiler);
      });
}

}  // namespace clhair
