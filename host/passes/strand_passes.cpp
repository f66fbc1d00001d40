// strand_passes.cpp — a groom's G-buffer clear and strand raster, or its given centre layer,
// and the capture of its raster inputs (passes.h).
#include "cl/buffers.h"
#include "passes/passes.h"

namespace clhair {

StrandRaster cameraRaster(Renderer::Impl&, const FramePlan& plan, const GroomPlan& gp,
                          const ViewPlan& vp, const FrameGraph::Resources& res) {
  const GroomDraw& d = gp.draw;
  StrandRaster raster;
  raster.view = &res[vp.record];
  raster.sceneDepth = &res[vp.depth];
  raster.gbuffer = &res[vp.gbuffer];
  raster.counters = &res[plan.rasterCounters];
  raster.pixels = plan.pixels;
  raster.msaa = plan.options.msaa;
  raster.mode = plan.mode;
  raster.stats = plan.options.rasterStats;
  raster.cover = plan.cover;
  raster.strands =
      plan.mode == DispatchMode::ReadBack ? d.groom->readTotal(*d.state) : d.groom->strandCount();
  raster.layers = vp.target->usedLayers();
  raster.ids = gp.ids;
  raster.pointIds = gp.points;
  return raster;
}

void addStrandPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp) {
  const bool given = plan.source != nullptr;
  struct Data {
    FrameGraph::Handle gbuffer;
  };
  g.addPass<Data>(
      (given ? "given G-buffer " : "strands ") + std::to_string(gp.index),
      [&, given](FrameGraph::Setup& s, Data& d) {
        const ViewPlan& camera = plan.camera();
        d.gbuffer = s.readWrite(camera.gbuffer);
        s.kernel("clear_words").kernel("clear_box");
        if (plan.options.rasterOnly) s.sideEffect();  // what the benchmark times
        if (given) return;
        s.reads({camera.record, camera.depth, gp.tables, gp.params, gp.lod});
        s.readsWrites({plan.rasterCounters});
        const GroomKernels k = gp.draw.groom->kernels();
        s.kernel(plan.mode == DispatchMode::Persistent ? k.rasterPersistent : k.raster);
        if (plan.mode == DispatchMode::ReadBack)
          s.hostWait("the groom's strand total (--dispatch readback)");
        if (plan.options.still != 0) {  // a still's strands, assembled once
          s.readsWrites({gp.stored}).kernel("strands_store").kernel("strands_raster_stored");
          s.hostWait("the still's LOD records, in its first pass");
        }
      },
      [&, given](const Data& data, const FrameGraph::Resources& res) {
        RenderTarget& t = *plan.camera().target;
        const GroomDraw& d = gp.draw;
        t.useLayers(gp.layers);
        t.clearGBuffer(gp.box, &r.profiler);
        if (given) {
          std::vector<std::uint64_t> words;
          plan.source->centreLayer(static_cast<std::uint32_t>(gp.index), d.state->params, words);
          if (words.size() != plan.pixels)
            throw Error("a given G-buffer layer has " + std::to_string(words.size()) +
                        " words for " + std::to_string(plan.pixels) + " pixels");
          upload(r.dev, res[data.gbuffer], words.data(), plan.pixels);
          return;
        }
        const StrandRaster raster = cameraRaster(r, plan, gp, plan.camera(), res);
        const RenderOptions& o = plan.options;
        if (o.still == 0 ||
            !d.groom->rasterStill(*d.state, raster, o.still,
                                  static_cast<std::uint32_t>(std::max(o.finalSubset, 1)),
                                  static_cast<std::uint32_t>(o.stillPass), &r.profiler))
          d.groom->raster(*d.state, raster, &r.profiler);
      });
}

void addCapturePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp,
                    PendingFrame& out) {
  struct Data {
    FrameGraph::Handle depth;
  };
  g.addPass<Data>(
      "capture " + std::to_string(gp.index),
      [&](FrameGraph::Setup& s, Data& d) {
        d.depth = s.read(plan.camera().depth);
        s.reads({gp.params}).sideEffect();
      },
      [&](const Data& d, const FrameGraph::Resources& res) {
        // the raster's inputs, before compositing changes the depth
        Frame& frame = out.frames[0];
        const auto* gb = reinterpret_cast<const std::uint8_t*>(&gp.draw.state->params);
        const auto* vb = reinterpret_cast<const std::uint8_t*>(&plan.camera().view);
        frame.rasterGroom.assign(gb, gb + sizeof(gpu::ClhGroomGpu));
        frame.rasterView.assign(vb, vb + sizeof(gpu::ClhViewGpu));
        frame.rasterDepth.resize(plan.pixels);
        out.read(r.dev, r.pinned, res[d.depth], 0, frame.rasterDepth.data(),
                 plan.pixels * sizeof(float));
      });
}

}  // namespace clhair
