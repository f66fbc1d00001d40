// strand_passes.cpp — a groom's G-buffer clear and strand raster, or its given centre layer,
// and the capture of its raster inputs (passes.h).
#include "cl/buffers.h"
#include "passes/passes.h"

namespace clhair {

StrandRaster cameraRaster(Renderer::Impl&, const FramePlan& plan, const GroomPlan& gp) {
  RenderTarget& t = *plan.camera().target;
  const GroomDraw& d = gp.draw;
  StrandRaster raster;
  raster.view = &t.view;
  raster.sceneDepth = &t.depth;
  raster.gbuffer = &t.gbuffer;
  raster.counters = &t.stats;
  raster.pixels = plan.pixels;
  raster.msaa = plan.options.msaa;
  raster.mode = plan.mode;
  raster.stats = plan.options.rasterStats;
  raster.cover = plan.cover;
  raster.strands =
      plan.mode == DispatchMode::ReadBack ? d.groom->readTotal(*d.state) : d.groom->strandCount();
  raster.layers = t.usedLayers();
  raster.ids = gp.ids;
  raster.pointIds = gp.points;
  return raster;
}

void addStrandPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp) {
  const bool given = plan.source != nullptr;
  g.addPass((given ? "given G-buffer " : "strands ") + std::to_string(gp.index),
            [&, given](FrameGraph::Setup& s) {
              s.readWrite(plan.camera().gbuffer).kernel("clear_words").kernel("clear_box");
              if (plan.options.rasterOnly) s.sideEffect();  // what the benchmark times
              if (given) return;
              s.read(plan.camera().record)
                  .read(plan.camera().depth)
                  .read(gp.tables)
                  .read(gp.params)
                  .read(gp.lod);
              s.readWrite(plan.rasterCounters);
              const GroomKernels k = gp.draw.groom->kernels();
              s.kernel(plan.mode == DispatchMode::Persistent ? k.rasterPersistent : k.raster);
              if (plan.mode == DispatchMode::ReadBack)
                s.hostWait("the groom's strand total (--dispatch readback)");
              if (plan.options.still != 0) {  // a still's strands, assembled once
                s.readWrite(gp.stored).kernel("strands_store").kernel("strands_raster_stored");
                s.hostWait("the still's LOD records, in its first pass");
              }
            },
            [&, given] {
              RenderTarget& t = *plan.camera().target;
              const GroomDraw& d = gp.draw;
              t.useLayers(gp.layers);
              t.clearGBuffer(gp.box, &r.profiler);
              if (given) {
                std::vector<std::uint64_t> words;
                plan.source->centreLayer(static_cast<std::uint32_t>(gp.index), d.state->params,
                                         words);
                if (words.size() != plan.pixels)
                  throw Error("a given G-buffer layer has " + std::to_string(words.size()) +
                              " words for " + std::to_string(plan.pixels) + " pixels");
                upload(r.dev, t.gbuffer, words.data(), plan.pixels);
                return;
              }
              const StrandRaster raster = cameraRaster(r, plan, gp);
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
  g.addPass(
      "capture " + std::to_string(gp.index),
      [&](FrameGraph::Setup& s) { s.read(plan.camera().depth).read(gp.params).sideEffect(); },
      [&] {
        // the raster's inputs, before compositing changes the depth
        Frame& frame = out.frames[0];
        const auto* gb = reinterpret_cast<const std::uint8_t*>(&gp.draw.state->params);
        const auto* vb = reinterpret_cast<const std::uint8_t*>(&plan.camera().view);
        frame.rasterGroom.assign(gb, gb + sizeof(gpu::ClhGroomGpu));
        frame.rasterView.assign(vb, vb + sizeof(gpu::ClhViewGpu));
        frame.rasterDepth.resize(plan.pixels);
        out.read(r.dev, r.pinned, plan.camera().target->depth, 0, frame.rasterDepth.data(),
                 plan.pixels * sizeof(float));
      });
}

}  // namespace clhair
