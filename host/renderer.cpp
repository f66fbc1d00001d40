// renderer.cpp — the frame loop. Per frame: the target and the scene on the device are
// brought up to date, the grooms are resolved to their device forms and instance slots,
// the deep opacity maps are rebuilt if their inputs changed, the opaque scene is drawn,
// and then every groom in turn runs lod -> scan + sizing -> strands -> shade -> filter ->
// composite over the same target (the traced reference's frames take each groom's centre
// layer from a GBufferSource instead of the strand pass). The pieces (host/frame/,
// host/groom/, host/stages/) each own one job; this file only orders them and reads the
// frame back.
#include "renderer_impl.h"

#include <algorithm>
#include <optional>

#include <glm/geometric.hpp>

#include "cl/buffers.h"
#include "frame/aov_builder.h"
#include "frame/view_math.h"

namespace clhair {

// Under a segment budget, grooms whose bounding sphere spans less than this share of the
// image height also drop every other control point (Kulikov 2025: far models draw half
// their vertices).
constexpr float kBudgetFarShare = 0.2f;

namespace {

// Whether a groom placed by `objToWorld` is far under the segment budget (kBudgetFarShare).
bool farGroom(const GroomGpu& g, const glm::mat4& objToWorld, const glm::mat4& worldToView,
              const gpu::ClhViewGpu& view) {
  const glm::vec3 lo = g.boundsMin(), hi = g.boundsMax();
  const glm::vec3 c = glm::vec3(objToWorld * glm::vec4(0.5f * (lo + hi), 1.0f));
  const float scale =
      std::max({glm::length(glm::vec3(objToWorld[0])), glm::length(glm::vec3(objToWorld[1])),
                glm::length(glm::vec3(objToWorld[2]))});
  const float radius = 0.5f * glm::length(hi - lo) * scale;
  const float z = (worldToView * glm::vec4(c, 1.0f)).z;
  if (!(z > radius)) return false;  // the camera is near or inside it
  return view.fy * 2.0f * radius / z < kBudgetFarShare * static_cast<float>(view.height);
}

}  // namespace

Renderer::Renderer(Device device) : impl_(std::make_unique<Impl>(std::move(device))) {}
Renderer::~Renderer() = default;

const Device& Renderer::device() const { return impl_->device; }

Frame Renderer::render(const Scene& s, const RenderOptions& options) {
  return impl_->frame(s, options, nullptr);
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
  r.frameLod.bind(draws);  // every draw's LOD records in one buffer, for the segment budget

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
  // every groom's LOD pre-pass, then the segment budget over all of them on the device
  std::vector<const GroomDraw*> drawn;
  std::vector<char> active(draws.size(), 0), far(draws.size(), 0);
  for (std::size_t k = 0; k < draws.size(); ++k) {
    const GroomDraw& d = draws[k];
    d.groom->useAo(options.ambientOcclusion != 0);
    if (!d.groom->prepare(*d.state, d.instance->transform, pass)) continue;
    // the budget is a stage of LOD: a groom drawn without LOD keeps every strand
    active[k] = static_cast<char>(d.state->params.lod_enabled ? CLH_BUDGET_DRAW_BUDGETED
                                                              : CLH_BUDGET_DRAW_FIXED);
    far[k] = farGroom(*d.groom, d.instance->transform, pass.worldToView, view) ? 1 : 0;
    drawn.push_back(&d);
    d.groom->lod(*d.state, t.view, &r.profiler);
  }
  const std::uint64_t budget = options.segmentBudget < 0
                                   ? s.segmentBudget
                                   : static_cast<std::uint64_t>(options.segmentBudget);
  r.frameLod.enqueue(draws, active, far, budget, &r.profiler);
  for (std::size_t k = 0; k < draws.size(); ++k) {
    if (!active[k]) continue;
    const GroomDraw& d = draws[k];
    GroomInstanceGpu& inst = *d.state;
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
  {
    const FrameLod::Result lod = r.frameLod.read(draws.size());
    frame.stats.segmentBudget = budget;
    frame.stats.overBudget = lod.over;
    frame.stats.budgetScale = lod.scale;
    frame.stats.segmentsBeforeBudget = lod.lodSegments;
    for (std::size_t k = 0; k < draws.size(); ++k) {
      GroomDrawStats g;
      g.instance = k;
      g.name = draws[k].instance->name;
      g.drawn = active[k] != 0;
      if (g.drawn) {
        g.strands = lod.draw[4 * k];
        g.segments = lod.draw[4 * k + 1];
        g.visibleStrands = lod.draw[4 * k + 2];
        g.halved = (lod.draw[4 * k + 3] & CLH_BUDGET_HALVED) != 0;
      }
      frame.stats.strandsDrawn += g.strands;
      frame.stats.segmentsPlanned += g.segments;
      frame.stats.grooms.push_back(std::move(g));
    }
  }
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
