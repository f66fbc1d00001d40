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

// The buffers of a groom's lists once the graph has allocated them.
struct PointHandles {
  PointStage::Sizes sizes;
  FrameGraph::Handle bits, blocks, ranks, records, colors;
  PointStage::Lists lists(FrameGraph& g) const {
    PointStage::Lists l;
    l.sizes = sizes;
    l.bits = &g.buffer(bits);
    l.blocks = &g.buffer(blocks);
    l.offsets = &g.buffer(ranks);
    l.records = &g.buffer(records);
    l.colors = &g.buffer(colors);
    return l;
  }
};

}  // namespace

void addPointShadePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp) {
  RenderTarget& t = *plan.camera().target;
  const PixelRect box = gp.box.clipped(t.viewTarget().width, t.viewTarget().height);
  const std::string label = "groom " + std::to_string(gp.index);
  // the lists live while the frame's graph does (the passes below capture them by value)
  PointHandles h;
  h.sizes = PointStage::sizes(gp.draw.groom->pointSpace(), box.pixels(), plan.options.msaa);
  h.bits = g.create(label + " marked points", h.sizes.bitsBytes());
  h.blocks = g.create(label + " point blocks", h.sizes.blocksBytes());
  h.ranks = g.create(label + " point ranks", h.sizes.offsetsBytes());
  h.records = g.create(label + " point records", h.sizes.recordsBytes());
  h.colors = g.create(label + " point colours", h.sizes.colorsBytes());
  gp.views[0].result = gp.views[0].hair;
  const std::string n = std::to_string(gp.index);

  g.addPass(
      "point marks " + n,
      [&, h](FrameGraph::Setup& s) {
        s.read(plan.camera().gbuffer)
            .write(h.bits)
            .write(h.blocks)
            .write(h.ranks)
            .write(plan.frameStats);
        s.kernel("points_mark").kernel("points_count").kernel("points_scan");
        s.kernel("points_offsets").kernel("clear_uints").kernel("copy_uints");
      },
      [&, h, box] {
        const PointStage::Lists l = h.lists(g);
        r.points.mark(t.viewTarget(), t.gbuffer, gp.layers, plan.options.msaa, box, l, &r.profiler);
        r.points.rank(l, &r.profiler);
        // the groom's marked points, for the frame's statistics
        r.target.copyUints(*l.offsets, l.sizes.words, r.frameStats, plan.pointsAt + gp.index, 1,
                           &r.profiler);
      });

  g.addPass(
      "point inputs " + n,
      [&, h](FrameGraph::Setup& s) {
        s.read(plan.camera().record)
            .read(plan.camera().depth)
            .read(gp.tables)
            .read(gp.params)
            .read(gp.lod);
        s.read(plan.camera().gbuffer).readWrite(plan.rasterCounters);
        s.read(h.bits).read(h.ranks).write(h.records);
        s.kernel(gp.draw.groom->kernels().raster);
        if (plan.mode == DispatchMode::ReadBack)
          s.hostWait("the groom's strand total for the point pass (--dispatch readback)");
      },
      [&, h] {
        const PointStage::Lists l = h.lists(g);
        const PointLists pass = l.pass();
        StrandRaster inputs = cameraRaster(r, plan, gp);
        inputs.pointIds = false;
        inputs.points = &pass;
        inputs.stats = false;
        if (inputs.mode == DispatchMode::Persistent) inputs.mode = DispatchMode::OverLaunch;
        gp.draw.groom->raster(*gp.draw.state, inputs, &r.profiler);
      });

  g.addPass(
      "shade points " + n,
      [&, h](FrameGraph::Setup& s) {
        s.read(plan.camera().record)
            .read(plan.scene_)
            .read(plan.shadowMaps)
            .read(plan.camera().gbuffer);
        s.read(gp.params).read(gp.lod).read(plan.visibility);
        s.read(h.records).read(h.bits).read(h.ranks).write(h.colors).write(gp.views[0].hair);
        s.kernel("shade_points").kernel("points_resolve");
      },
      [&, h] {
        const PointStage::Lists l = h.lists(g);
        // the inputs of per-sample shading (its G-buffer and hair are not read)
        const ShadeStage::Params sp =
            shadeParams(r, t, gp, t.gbuffer, g.buffer(gp.views[0].hair), plan.options.msaa);
        r.shade.enqueuePoints(sp, l, &r.profiler);
        r.points.resolve(t.viewTarget(), t.gbuffer, gp.layers, plan.options.msaa, gp.hairBox, l,
                         g.buffer(gp.views[0].hair), &r.profiler);
      });
}

}  // namespace clhair
