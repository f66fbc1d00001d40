// renderer.cpp — the frame loop. Per frame: the target and the scene on the device are
// brought up to date, the grooms are resolved to their device forms and instance slots,
// the deep opacity maps are rebuilt if their inputs changed, the opaque scene is drawn,
// and then every groom in turn runs lod -> scan + sizing -> strands -> shade -> filter ->
// composite over the same target (the traced reference's frames take each groom's centre
// layer from a GBufferSource instead of the strand pass). The pieces (host/frame/,
// host/groom/, host/stages/) each own one job; this file only orders them and reads the
// frame back.
#include "renderer_impl.h"

#include <optional>

#include <glm/matrix.hpp>

#include "cl/buffers.h"
#include "clhair/visibility_sh.h"
#include "frame/aov_builder.h"
#include "frame/view_math.h"

namespace clhair {

Renderer::Renderer(Device device) : impl_(std::make_unique<Impl>(std::move(device))) {}
Renderer::~Renderer() = default;

const Device& Renderer::device() const { return impl_->device; }

Frame Renderer::render(const Scene& s, const RenderOptions& options) {
  return impl_->frame(s, options, nullptr);
}

void Renderer::Impl::bindVisibility(const GroomInstance& gi, bool enabled, bool lodAggregate,
                                    ShadeStage::Params& sp) {
  gpu::ClhVisibilityGpu v{};
  v.lod_aggregate = lodAggregate ? 1u : 0u;
  const cl::Buffer* table = nullptr;
  if (enabled && gi.visibility) {
    auto it = visibilityTables.find(gi.visibility.get());
    if (it == visibilityTables.end()) {
      const std::vector<float>& sh = gi.visibility->sh;
      if (sh.size() != std::size_t(CLH_VIS_CELLS) * CLH_VIS_COEFFS)
        throw Error("groom \"" + gi.name + "\": its baked visibility holds " +
                    std::to_string(sh.size()) + " coefficients, need " +
                    std::to_string(std::size_t(CLH_VIS_CELLS) * CLH_VIS_COEFFS));
      cl::Buffer b = makeBuffer<cl_float4>(dev, "baked visibility", CLH_VIS_CELLS);
      upload(dev, b, reinterpret_cast<const cl_float4*>(sh.data()), CLH_VIS_CELLS);
      it = visibilityTables.emplace(gi.visibility.get(), std::make_pair(gi.visibility, b)).first;
    }
    table = &it->second.second;
    const glm::mat4 inv = glm::inverse(gi.transform);
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 4; ++col) v.world_to_obj[4 * row + col] = inv[col][row];
    v.absorption = gi.visibilityAbsorption;
    v.cells = CLH_VIS_CELLS;
    v.enabled = 1;
  }
  if (!table) {
    if (!visibilityNone()) {
      const cl_float4 zero{};
      visibilityNone = makeBuffer<cl_float4>(dev, "no baked visibility", 1, &zero);
    }
    table = &visibilityNone;
  }
  if (!visibilityParams())
    visibilityParams = makeBuffer<gpu::ClhVisibilityGpu>(dev, "baked visibility record", 1);
  upload(dev, visibilityParams, &v, 1);
  sp.visibility = &visibilityParams;
  sp.visibilityTable = table;
  sp.visibilityCells = table == &visibilityNone ? 1u : static_cast<std::uint32_t>(CLH_VIS_CELLS);
}

Frame Renderer::Impl::frame(const Scene& s, const RenderOptions& options, GBufferSource* source) {
  Impl& r = *this;
  RenderTarget& t = r.target;
  if (source && options.msaa != 1)
    throw Error("a given G-buffer has one sample per pixel, not MSAA " +
                std::to_string(options.msaa));
  t.ensure(s.width, s.height, options.msaa);
  r.scene.upload(s);
  gpu::ClhViewGpu view = makeView(s.camera, s.width, s.height);
  view.samples = static_cast<gpu::clh_u32>(options.msaa);
  view.cx += options.jitterX;
  view.cy += options.jitterY;
  upload(r.dev, t.view, &view, 1);
  const std::size_t pixels = t.pixels();
  const DispatchMode mode = r.resolveMode(options.dispatch);
  Frame frame;
  r.profiler.hostTiming = options.stageCores;
  if (options.rasterStats) {
    const cl_uint zero[4] = {0, 0, 0, 0};
    upload(r.dev, t.stats, zero, 4);
  }
  r.shadows.reserve(s);  // before the grooms: see ShadowPass::reserve
  r.grooms.beginFrame();
  std::vector<GroomDraw> draws = r.resolveGrooms(s);

  const bool lodCorrection =
      options.shadowLodCorrection < 0 ? s.shadows.lodCorrection : options.shadowLodCorrection == 1;
  r.shadows.update(s, options, lodCorrection, draws, r.scene, &r.profiler);
  const ShadowMapInputs maps = r.shadows.maps();
  r.scene.drawOpaque(t.viewTarget(), maps, t.color, t.depth, true, &r.profiler);
  std::vector<std::uint64_t> words;
  if (source) {
    std::vector<float> opaqueDepth(pixels);
    readBack(r.dev, "the opaque scene's depth", t.depth, opaqueDepth.data(), pixels);
    source->opaqueDrawn(view, opaqueDepth);
  }
  // layers for compositing: gathered groom by groom from what each leaves on the device
  const bool aovs = options.aovs && !options.rasterOnly;
  std::optional<AovBuilder> aovBuilder;
  std::vector<std::uint64_t> aovWords;
  std::vector<float> aovHair, aovDepth;
  if (aovs) {
    aovDepth.resize(pixels);
    readBack(r.dev, "the opaque scene's depth", t.depth, aovDepth.data(), pixels);
    aovBuilder.emplace(view, aovDepth);
  }

  ViewPass pass;
  pass.view = &t.view;
  pass.worldToView = worldToView(s.camera);
  pass.lod = options.lod;
  pass.lodLambdaScale = options.lodLambdaScale;
  pass.trueWidth = options.trueWidth;
  pass.shadowLodCorrection = lodCorrection;
  StrandRaster raster;
  raster.view = &t.view;
  raster.sceneDepth = &t.depth;
  raster.gbuffer = &t.gbuffer;
  raster.counters = &t.stats;
  raster.pixels = pixels;
  raster.msaa = options.msaa;
  raster.stats = options.rasterStats;
  raster.mode = mode;
  std::vector<const GroomDraw*> drawn;
  for (std::size_t k = 0; k < draws.size(); ++k) {
    const GroomDraw& d = draws[k];
    GroomInstanceGpu& inst = *d.state;
    d.groom->useAo(options.ambientOcclusion != 0);
    if (!d.groom->prepare(inst, d.instance->transform, pass)) continue;
    drawn.push_back(&d);
    d.groom->lod(inst, t.view, &r.profiler);
    t.clearGBuffer(&r.profiler);
    if (source) {
      source->centreLayer(static_cast<std::uint32_t>(k), inst.params, words);
      if (words.size() != pixels)
        throw Error("a given G-buffer layer has " + std::to_string(words.size()) + " words for " +
                    std::to_string(pixels) + " pixels");
      upload(r.dev, t.gbuffer, words.data(), pixels);
    } else {
      raster.strands =
          mode == DispatchMode::ReadBack ? d.groom->readTotal(inst) : d.groom->strandCount();
      d.groom->raster(inst, raster, &r.profiler);
    }
    if (options.captureGBuffer) {  // the raster's inputs, before compositing changes the depth
      const auto* gb = reinterpret_cast<const std::uint8_t*>(&inst.params);
      const auto* vb = reinterpret_cast<const std::uint8_t*>(&view);
      frame.rasterGroom.assign(gb, gb + sizeof(gpu::ClhGroomGpu));
      frame.rasterView.assign(vb, vb + sizeof(gpu::ClhViewGpu));
      frame.rasterDepth.resize(pixels);
      readBack(r.dev, "the depth the hair was tested against", t.depth, frame.rasterDepth.data(),
               pixels);
    }
    if (options.rasterOnly) continue;
    ShadeStage::Params sp;
    sp.target = t.viewTarget();
    sp.lighting = r.scene.lighting(maps);
    sp.groom = &inst.groom;
    sp.offsets = &inst.offsets;
    sp.records = inst.records;
    sp.gbuffer = &t.gbuffer;
    sp.hair = &t.hair;
    sp.msaa = options.msaa;
    r.bindVisibility(*d.instance, options.bakedVisibility != 0, options.lodAggregate != 0, sp);
    r.shade.enqueue(sp, &r.profiler);
    const FilterParams& fp = d.instance->hasFilter ? d.instance->filter : s.filter;
    const bool filtered =
        options.msaa == 1 && (options.filter < 0 ? fp.enabled : options.filter == 1);
    if (filtered)
      r.filter.enqueue(fp, {t.viewTarget(), &inst.groom, &t.gbuffer, &t.hair, &t.filtered},
                       &r.profiler);
    r.composite.enqueue({t.viewTarget(), &inst.groom, filtered ? &t.filtered : &t.hair, &t.gbuffer,
                         &t.color, &t.depth, options.msaa, filtered ? 2 : options.msaa},
                        &r.profiler);
    if (aovs) {
      aovWords.resize(pixels * options.msaa);
      aovHair.resize(pixels * 4);
      readBack(r.dev, "the centre G-buffer layers", t.gbuffer, aovWords.data(), aovWords.size());
      readBack(r.dev, "the shaded hair", filtered ? t.filtered : t.hair, aovHair.data(),
               aovHair.size());
      readBack(r.dev, "the depth after compositing", t.depth, aovDepth.data(), pixels);
      aovBuilder->addGroom(k, inst.params, aovWords, options.msaa, aovHair, aovDepth);
    }
  }

  frame.color.width = s.width;
  frame.color.height = s.height;
  frame.color.rgba.resize(pixels * 4);
  frame.depth.resize(pixels);
  readBack(r.dev, "the frame", t.color, frame.color.rgba.data(), pixels * 4);
  readBack(r.dev, "the frame's depth", t.depth, frame.depth.data(), pixels);
  for (const GroomDraw* d : drawn) frame.stats.strandsDrawn += d->groom->readTotal(*d->state);
  frame.stats.shadowStrandsDrawn = r.shadows.strandsDrawn();
  if (aovs) frame.aovs = aovBuilder->finish(frame.depth, s, options.previous);
  if (options.captureGBuffer) {
    frame.gbufferLayers = t.layers();
    frame.gbuffer.assign(pixels * t.layers(), ~std::uint64_t(0));
    if (!drawn.empty())
      readBack(r.dev, "the G-buffer", t.gbuffer, frame.gbuffer.data(), frame.gbuffer.size());
  }
  if (options.rasterStats) {
    cl_uint st[4];
    readBack(r.dev, "raster statistics", t.stats, st, 4);
    frame.stats.pixelWrites = st[0];
    frame.stats.atomicsIssued = st[1];
    frame.stats.atomicsSkipped = st[2];
    frame.stats.segmentsDrawn = st[3];
  }
  frame.timings = r.profiler.collect();
  r.grooms.trim();
  return frame;
}

}  // namespace clhair
