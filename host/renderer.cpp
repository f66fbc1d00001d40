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
#include <glm/matrix.hpp>

#include "cl/buffers.h"
#include "clhair/coverage.h"
#include "clhair/visibility_sh.h"
#include "frame/aov_builder.h"
#include "frame/view_math.h"

namespace clhair {

// Under a segment budget, grooms whose bounding sphere spans less than this share of the
// image height also drop every other control point (Kulikov 2025: far models draw half
// their vertices).
constexpr float kBudgetFarShare = 0.2f;

namespace {

// Whether a groom instance moves its strands between two still frames other than by its
// transform: another cage (cage animation, wind) or another per-frame strand file.
bool deformsBetween(const GroomInstance& now, const GroomInstance& before) {
  if (now.strands || before.strands) return now.strands != before.strands;
  const auto &a = now.deformed, &b = before.deformed;
  if (a == b || !now.mesh) return false;
  if (a && b) return *a != *b;
  return *(a ? a : b) != now.mesh->positions;
}

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

// The camera's pass of a groom (LOD, widths) into render target `t` seen from `camera`.
ViewPass cameraPass(RenderTarget& t, const Camera& camera, const RenderOptions& options,
                    bool lodCorrection) {
  ViewPass pass;
  pass.view = &t.view;
  pass.worldToView = worldToView(camera);
  pass.lod = options.lod;
  pass.lodLambdaScale = options.lodLambdaScale;
  pass.trueWidth = options.trueWidth;
  pass.shadowLodCorrection = lodCorrection;
  return pass;
}

// The strand raster's buffers in render target `t`.
StrandRaster rasterInto(RenderTarget& t, std::size_t pixels, int msaa, DispatchMode mode) {
  StrandRaster raster;
  raster.view = &t.view;
  raster.sceneDepth = &t.depth;
  raster.gbuffer = &t.gbuffer;
  raster.counters = &t.stats;
  raster.pixels = pixels;
  raster.msaa = msaa;
  raster.mode = mode;
  return raster;
}

}  // namespace

Renderer::Renderer(Device device) : impl_(std::make_unique<Impl>(std::move(device))) {}
Renderer::~Renderer() = default;

const Device& Renderer::device() const { return impl_->device; }

Frame Renderer::render(const Scene& s, const RenderOptions& options) {
  return impl_->frame(s, options, nullptr);
}

// Whether a frame draws in the coverage mode (clhair/coverage.h), and the option checks
// that mode asks for.
static bool coverMode(const Scene& s, const RenderOptions& options) {
  const bool cover = options.raster < 0 ? s.raster == RasterMode::Coverage : options.raster == 1;
  if (cover && options.msaa != 1)
    throw Error(
        "the coverage raster takes one sample per pixel (its coverage is analytic), not "
        "MSAA " +
        std::to_string(options.msaa));
  if (cover && options.strandIds)
    throw Error("the coverage raster has no strand identity layer (use the lines raster)");
  return cover;
}

// Whether a frame of one view filters a groom with Huang's filter (rather than Lipp's): as
// --filter says, else as the groom's method, where "auto" is Huang's (whatever the number of
// grooms: each one's passes run over its screen box, DESIGN.md "The default filter").
static bool huangMethod(const FilterParams& fp, const RenderOptions& options) {
  if (options.filterMethod >= 0) return options.filterMethod == 1;
  return fp.method != FilterParams::Method::Lipp;
}

// G-buffer layers a groom with filter settings `fp` uses: the samples and the conservative
// layer, then the identity layer (Huang's filter, strand identities) and the hair linking
// layers (gpu_types.h); in the coverage mode its three layers and the coverage plane.
static int gbufferLayers(const FilterParams& fp, const RenderOptions& options, bool given,
                         bool cover) {
  if (cover) return static_cast<int>(CLH_LAYER_COVERAGE) + 1;
  const bool filtered =
      options.msaa == 1 && (options.filter < 0 ? fp.enabled : options.filter == 1);
  const bool huang = filtered && !options.rasterOnly && huangMethod(fp, options);
  const bool ids = huang || options.strandIds;
  if (ids && options.msaa != 1)
    throw Error("strand identities (the strand.id layer) need MSAA 1, not " +
                std::to_string(options.msaa));
  if (huang && fp.link && !given) return static_cast<int>(CLH_LAYER_LINKED) + 1;
  return ids ? static_cast<int>(CLH_LAYER_ID) + 1 : options.msaa + 1;
}

std::vector<Frame> Renderer::renderViews(const Scene& s, const std::vector<Camera>& cameras,
                                         const RenderOptions& options) {
  if (cameras.size() > static_cast<std::size_t>(kMaxViews))
    throw Error(std::to_string(cameras.size()) + " views; at most " + std::to_string(kMaxViews));
  if (cameras.size() < 2) {
    Scene one = s;
    if (!cameras.empty()) one.camera = cameras[0];
    return {impl_->frame(one, options, nullptr)};
  }
  return impl_->views(s, cameras, options);
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

void Renderer::Impl::shadeGroom(RenderTarget& t, const GroomInstance& gi, GroomInstanceGpu& inst,
                                const ShadowMapInputs& maps, const RenderOptions& options,
                                bool cover, const cl::Buffer* gbuffer) {
  ShadeStage::Params sp;
  sp.target = t.viewTarget();
  sp.lighting = scene.lighting(maps);
  sp.groom = &inst.groom;
  sp.offsets = &inst.offsets;
  sp.records = inst.records;
  sp.gbuffer = gbuffer ? gbuffer : &t.gbuffer;
  sp.hair = &t.hair;
  sp.msaa = options.msaa;
  sp.cover = cover;
  bindVisibility(gi, options.bakedVisibility != 0, options.lodAggregate != 0, sp);
  shade.enqueue(sp, &profiler);
}

Frame Renderer::Impl::frame(const Scene& s, const RenderOptions& options, GBufferSource* source) {
  Impl& r = *this;
  RenderTarget& t = r.target;
  if (source && options.msaa != 1)
    throw Error("a given G-buffer has one sample per pixel, not MSAA " +
                std::to_string(options.msaa));
  const bool cover = coverMode(s, options);
  if (source && cover) throw Error("a given G-buffer has no coverage layers");
  t.ensure(s.width, s.height, options.msaa);
  // the G-buffer layers the grooms will ask for, allocated once before any is drawn
  int layersNeeded = options.msaa + 1;
  for (const GroomInstance& gi : s.grooms)
    layersNeeded = std::max(layersNeeded, gbufferLayers(gi.hasFilter ? gi.filter : s.filter,
                                                        options, source != nullptr, cover));
  t.useLayers(layersNeeded);
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
  std::vector<std::uint64_t> aovWords, aovIds, motionWords;
  std::vector<float> aovHair, aovDepth;
  if (aovs) {
    aovDepth.resize(pixels);
    readBack(r.dev, "the opaque scene's depth", t.depth, aovDepth.data(), pixels);
    aovBuilder.emplace(view, aovDepth);
  }
  std::vector<float> aovOpaque;
  if (aovs) {  // the colour under the hair: temporal reprojection recomposes the frame on it
    aovOpaque.resize(pixels * 4);
    readBack(r.dev, "the opaque scene's colour", t.color, aovOpaque.data(), aovOpaque.size());
  }
  // the previous camera's intrinsics for motion passes keep this frame's sub-pixel shift
  const Scene* before = aovs ? options.previous : nullptr;
  gpu::ClhMotionGpu motionParams{};
  glm::mat4 prevWorldToView(1.0f);
  if (before) {
    const gpu::ClhViewGpu pv = makeView(before->camera, s.width, s.height);
    const gpu::ClhViewGpu still = makeView(s.camera, s.width, s.height);
    motionParams.fx = pv.fx;
    motionParams.fy = pv.fy;
    motionParams.cx = pv.cx + (view.cx - still.cx);
    motionParams.cy = pv.cy + (view.cy - still.cy);
    prevWorldToView = worldToView(before->camera);
  }

  ViewPass pass = cameraPass(t, s.camera, options, lodCorrection);
  StrandRaster raster = rasterInto(t, pixels, options.msaa, mode);
  raster.stats = options.rasterStats;
  raster.cover = cover;
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
  r.frameLod.enqueue(draws, active, far, budget, &r.profiler, budgetRule(options, view));
  for (std::size_t k = 0; k < draws.size(); ++k) {
    if (!active[k]) continue;
    const GroomDraw& d = draws[k];
    GroomInstanceGpu& inst = *d.state;
    const FilterParams& fp = d.instance->hasFilter ? d.instance->filter : s.filter;
    // the coverage mode has no filter: its alpha comes from the coverage layer
    const bool filtered =
        !cover && options.msaa == 1 && (options.filter < 0 ? fp.enabled : options.filter == 1);
    const bool huang = filtered && !options.rasterOnly && huangMethod(fp, options);
    const bool linking = huang && fp.link && !source;
    const bool ids = huang || options.strandIds;
    // the layers the composite takes the hair's depth from: the samples, plus the
    // conservative layer after Lipp's filter (the centre layer holds the linked pixels after
    // Huang's)
    const std::uint32_t depthLayers =
        static_cast<std::uint32_t>(filtered && !huang ? 2 : options.msaa);
    // the pixels the groom can draw into: the G-buffer clear before it and the passes that
    // concern only its pixels run there (a given G-buffer may hold words anywhere)
    const PixelRect box =
        options.screenBoxes && !source
            ? screenBox(d.groom->boundsMin(), d.groom->boundsMax(),
                        pass.worldToView * d.instance->transform, view, kScreenBoxMargin)
            : PixelRect{};
    t.useLayers(gbufferLayers(fp, options, source != nullptr, cover));
    t.clearGBuffer(box, &r.profiler);
    if (source) {
      source->centreLayer(static_cast<std::uint32_t>(k), inst.params, words);
      if (words.size() != pixels)
        throw Error("a given G-buffer layer has " + std::to_string(words.size()) + " words for " +
                    std::to_string(pixels) + " pixels");
      upload(r.dev, t.gbuffer, words.data(), pixels);
    } else {
      raster.strands =
          mode == DispatchMode::ReadBack ? d.groom->readTotal(inst) : d.groom->strandCount();
      raster.layers = t.usedLayers();
      raster.ids = ids;
      d.groom->raster(inst, raster, &r.profiler);
    }
    // Huang's filter leaves its result right inside the box only; the AOVs read all of it
    const PixelRect hairBox = aovs ? PixelRect{} : box;
    LinkStage::Params lp{t.viewTarget(),         &inst.groom,    &t.gbuffer,
                         d.groom->strandCount(), t.usedLayers(), hairBox};
    if (huang) {
      if (!r.linkStage) r.linkStage = std::make_unique<LinkStage>(r.dev);
      r.linkStage->select(fp, lp, &r.profiler);
      if (linking) {
        StrandRaster curve = raster;
        curve.ids = false;
        curve.curve = true;
        curve.stats = false;
        curve.linkFlags = &r.linkStage->flags();
        curve.linkWords = r.linkStage->flagWords();
        d.groom->raster(inst, curve, &r.profiler);
        r.linkStage->propagate(lp, &r.profiler);
      }
      r.linkStage->merge(lp, linking, &r.profiler);
    }
    // a deforming groom's motion: its strands again at the previous frame, after hair linking
    // (a linked pixel's motion is that of the strand linked into it) and before the composite
    // changes the depth they were tested against; resolved on the word the composite takes
    // the pixel's depth from, so Z and motion describe one fragment
    bool motionDrawn = false;
    if (before && !source && k < before->grooms.size() &&
        deformsBetween(*d.instance, before->grooms[k])) {
      if (cover)
        throw Error("groom \"" + d.instance->name +
                    "\" deforms: the coverage raster has no motion pass for its motion layer "
                    "(use the lines raster)");
      storeMat34(motionParams.prev_obj_to_view, prevWorldToView * before->grooms[k].transform);
      motionParams.depth_layers = depthLayers;
      upload(r.dev, t.motionParams, &motionParams, 1);
      MotionPass mp;
      mp.params = &t.motionParams;
      mp.motion = &t.clearedMotion(&r.profiler);
      if (d.groom->motion(inst, before->grooms[k], mp, raster, &r.profiler)) {
        motionWords.resize(pixels);
        readBack(r.dev, "the motion plane", *mp.motion, motionWords.data(), pixels);
        motionDrawn = true;
      }
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
    r.shadeGroom(t, *d.instance, inst, maps, options, cover);
    cl::Buffer* result = &t.hair;
    if (huang) {
      result = r.linkStage->finish(lp, fp.aniso, t.hair, t.filtered, &r.profiler);
      const LinkCounters c = r.linkStage->counters();
      frame.stats.linkSelecting += c.selecting;
      frame.stats.linkedPixels += c.filled;
      frame.stats.linkStrands += c.strands;
      frame.stats.linkTurnedAway += c.turnedAway;
    } else if (filtered) {
      r.filter.enqueue(fp, {t.viewTarget(), &inst.groom, &t.gbuffer, &t.hair, &t.filtered},
                       &r.profiler);
      result = &t.filtered;
    }
    r.composite.enqueue(
        {t.viewTarget(), &inst.groom, result, &t.gbuffer, &t.color, &t.depth, options.msaa,
         static_cast<int>(depthLayers), huang ? hairBox : PixelRect{}},
        &r.profiler);
    if (aovs) {
      aovWords.resize(pixels * options.msaa);
      aovHair.resize(pixels * 4);
      readBack(r.dev, "the centre G-buffer layers", t.gbuffer, aovWords.data(), aovWords.size());
      readBack(r.dev, "the shaded hair", *result, aovHair.data(), aovHair.size());
      if (options.strandIds) {  // the identity layer of this groom
        aovIds.resize(pixels);
        readBack(r.dev, "the strand identities", t.gbuffer, aovIds.data(), pixels,
                 pixels * CLH_LAYER_ID);
      }
      readBack(r.dev, "the depth after compositing", t.depth, aovDepth.data(), pixels);
      aovBuilder->addGroom(k, inst.params, aovWords, options.msaa, aovHair, aovDepth,
                           motionDrawn ? &motionWords : nullptr,
                           options.strandIds ? &aovIds : nullptr);
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
    frame.stats.budgetScreenRule = options.budgetRule != 0;
    frame.stats.budgetLevel = lod.level;
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
        g.requested = lod.plan[k].request;
        g.floor = lod.plan[k].floor;
        g.share = lod.plan[k].share;
        g.screenArea = lod.plan[k].area;
        g.keepClaim = lod.plan[k].claim * lod.claims;
      }
      frame.stats.strandsDrawn += g.strands;
      frame.stats.segmentsPlanned += g.segments;
      frame.stats.grooms.push_back(std::move(g));
    }
  }
  frame.stats.shadowStrandsDrawn = r.shadows.strandsDrawn();
  if (aovs) {
    frame.aovs = aovBuilder->finish(frame.depth, s, options.previous);
    frame.aovs.opaque = std::move(aovOpaque);
  }
  if (options.captureGBuffer) {
    frame.gbufferLayers = t.usedLayers();
    frame.gbuffer.assign(pixels * t.usedLayers(), ~std::uint64_t(0));
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

// Several views: the frame loop above with every per-view step (opaque scene, shading,
// filter, composite, read-back) done once per view, and each hair mesh's strands assembled
// once per groom and drawn into every view's G-buffer (strands_raster_views). The strands
// (LOD, culling) are those of the first view in which the groom is in front of the camera.
// Strand files draw each view on their own (their strands are read, not generated).
std::vector<Frame> Renderer::Impl::views(const Scene& s, const std::vector<Camera>& cameras,
                                         const RenderOptions& options) {
  Impl& r = *this;
  if (options.aovs || options.captureGBuffer || options.rasterOnly)
    throw Error("several views render the beauty only (no --aov, G-buffer capture or raster-only)");
  if (coverMode(s, options))
    throw Error("the coverage raster renders one view at a time (choose one with --views NAME)");
  const std::size_t V = cameras.size();
  while (r.viewTargets.size() + 1 < V)
    r.viewTargets.push_back(std::make_unique<RenderTarget>(r.dev));
  auto targetOf = [&](std::size_t v) -> RenderTarget& {
    return v == 0 ? r.target : *r.viewTargets[v - 1];
  };
  std::vector<gpu::ClhViewGpu> records(V);
  for (std::size_t v = 0; v < V; ++v) {
    RenderTarget& t = targetOf(v);
    t.ensure(s.width, s.height, options.msaa);
    records[v] = makeView(cameras[v], s.width, s.height);
    records[v].samples = static_cast<gpu::clh_u32>(options.msaa);
    records[v].cx += options.jitterX;
    records[v].cy += options.jitterY;
    upload(r.dev, t.view, &records[v], 1);
  }
  const std::size_t pixels = r.target.pixels();
  const std::size_t layers = static_cast<std::size_t>(options.msaa) + 1;
  // Every view's scene depth and G-buffer are slices of one buffer each, which the strand
  // pass draws into side by side; each slice starts on the device's sub-buffer alignment
  // and is a sub-buffer of its own, the depth and G-buffer of that view's opaque pass,
  // shading, filter, composite and read-back: nothing is copied between the two.
  if (!r.viewAlign) {
    const cl_uint bits = clCall("querying the sub-buffer alignment", [&] {
      return r.dev.device.getInfo<CL_DEVICE_MEM_BASE_ADDR_ALIGN>();
    });
    r.viewAlign = std::max<std::size_t>(bits / 8, sizeof(cl_ulong));
  }
  auto strideOf = [&](std::size_t count, std::size_t bytes) {  // elements per slice, padded
    return (count * bytes + r.viewAlign - 1) / r.viewAlign * r.viewAlign / bytes;
  };
  const std::size_t depthStride = strideOf(pixels, sizeof(cl_float));
  const std::size_t gbufferStride = strideOf(pixels * layers, sizeof(cl_ulong));
  if (r.viewDepthWords != V * depthStride || r.viewGBufferWords != V * gbufferStride ||
      r.viewDepthSlices.size() != V || r.viewSlicePixels != pixels * layers) {
    r.viewDepths = makeBuffer<cl_float>(r.dev, "the scene depth of every view", V * depthStride);
    r.viewGBuffers = makeBuffer<cl_ulong>(r.dev, "the G-buffers of every view", V * gbufferStride);
    r.viewDepthWords = V * depthStride;
    r.viewGBufferWords = V * gbufferStride;
    r.viewSlicePixels = pixels * layers;
    r.viewDepthSlices.clear();
    r.viewGBufferSlices.clear();
    auto slice = [&](cl::Buffer& whole, std::size_t origin, std::size_t size) {
      cl_buffer_region region{origin, size};
      return clCall("creating a view's slice", [&] {
        return whole.createSubBuffer(CL_MEM_READ_WRITE, CL_BUFFER_CREATE_TYPE_REGION, &region);
      });
    };
    for (std::size_t v = 0; v < V; ++v) {
      r.viewDepthSlices.push_back(
          slice(r.viewDepths, v * depthStride * sizeof(cl_float), pixels * sizeof(cl_float)));
      r.viewGBufferSlices.push_back(slice(r.viewGBuffers, v * gbufferStride * sizeof(cl_ulong),
                                          pixels * layers * sizeof(cl_ulong)));
    }
  }
  if (r.viewSlots != V) {
    r.viewRecords = makeBuffer<gpu::ClhViewGpu>(r.dev, "view parameters of every view", V);
    r.viewGrooms = makeBuffer<gpu::ClhGroomGpu>(r.dev, "groom parameters of every view", V);
    r.viewSlots = V;
  }
  upload(r.dev, r.viewRecords, records.data(), V);
  r.scene.upload(s);
  const DispatchMode mode = r.resolveMode(options.dispatch);
  r.profiler.hostTiming = options.stageCores;
  std::vector<Frame> frames(V);
  r.shadows.reserve(s);
  r.grooms.beginFrame();
  std::vector<GroomDraw> draws = r.resolveGrooms(s);
  // the instances' LOD records live in the frame's LOD buffer (no segment budget across
  // views: each groom's LOD is that of its first view)
  r.frameLod.bind(draws);
  const bool lodCorrection =
      options.shadowLodCorrection < 0 ? s.shadows.lodCorrection : options.shadowLodCorrection == 1;
  r.shadows.update(s, options, lodCorrection, draws, r.scene, &r.profiler);
  const ShadowMapInputs maps = r.shadows.maps();
  for (std::size_t v = 0; v < V; ++v) {
    RenderTarget& t = targetOf(v);
    r.scene.drawOpaque(t.viewTarget(), maps, t.color, r.viewDepthSlices[v], true, &r.profiler);
  }
  std::vector<ViewPass> passes(V);
  for (std::size_t v = 0; v < V; ++v)
    passes[v] = cameraPass(targetOf(v), cameras[v], options, lodCorrection);
  std::vector<std::uint32_t> drawnTotal(V, 0);
  for (std::size_t k = 0; k < draws.size(); ++k) {
    const GroomDraw& d = draws[k];
    GroomInstanceGpu& inst = *d.state;
    d.groom->useAo(options.ambientOcclusion != 0);
    // each view's record (transform, depth mapping); the LOD view's last, so that the
    // instance holds it for the LOD pass and the assembly
    std::vector<gpu::ClhGroomGpu> recs(V);
    std::vector<bool> inFront(V, false);
    std::size_t lodView = V;
    for (std::size_t v = V; v-- > 0;) {
      inFront[v] = d.groom->prepare(inst, d.instance->transform, passes[v]);
      recs[v] = inst.params;
      if (inFront[v]) lodView = v;
    }
    if (lodView == V) continue;
    for (std::size_t v = 0; v < V; ++v)
      if (!inFront[v]) {  // every point behind the eye: nothing is drawn in this view
        std::fill(std::begin(recs[v].obj_to_view), std::end(recs[v].obj_to_view), 0.0f);
        recs[v].obj_to_view[11] = -1.0f;
        recs[v].depth_near = recs[lodView].depth_near;
        recs[v].depth_far = recs[lodView].depth_far;
      }
    if (lodView != 0) d.groom->prepare(inst, d.instance->transform, passes[lodView]);
    d.groom->lod(inst, targetOf(lodView).view, &r.profiler);
    // every view's G-buffer cleared (its scene depth is already in place)
    r.target.clearWords(r.viewGBuffers, V * gbufferStride, &r.profiler);
    upload(r.dev, r.viewGrooms, recs.data(), V);
    StrandRaster raster = rasterInto(targetOf(lodView), pixels, options.msaa, mode);
    raster.sceneDepth = &r.viewDepths;
    raster.gbuffer = &r.viewGBuffers;
    raster.depthStride = depthStride;
    raster.gbufferStride = gbufferStride;
    raster.strands =
        mode == DispatchMode::ReadBack ? d.groom->readTotal(inst) : d.groom->strandCount();
    const bool together = d.groom->rasterViews(inst, raster, r.viewGrooms, r.viewRecords,
                                               static_cast<std::uint32_t>(V), &r.profiler);
    if (together) {
      const std::uint32_t total = d.groom->readTotal(inst);
      for (std::size_t v = 0; v < V; ++v)
        if (inFront[v]) drawnTotal[v] += total;
    }
    for (std::size_t v = 0; v < V; ++v) {
      if (!inFront[v]) continue;
      RenderTarget& t = targetOf(v);
      cl::Buffer& depth = r.viewDepthSlices[v];
      cl::Buffer& gbuffer = r.viewGBufferSlices[v];
      if (!together) {  // this groom draws each view on its own: its own LOD per view
        d.groom->prepare(inst, d.instance->transform, passes[v]);
        d.groom->lod(inst, t.view, &r.profiler);
        r.target.clearWords(gbuffer, pixels * layers, &r.profiler);
        StrandRaster own = rasterInto(t, pixels, options.msaa, mode);
        own.sceneDepth = &depth;
        own.gbuffer = &gbuffer;
        own.strands =
            mode == DispatchMode::ReadBack ? d.groom->readTotal(inst) : d.groom->strandCount();
        d.groom->raster(inst, own, &r.profiler);
        drawnTotal[v] += d.groom->readTotal(inst);
      } else {
        upload(r.dev, inst.groom, &recs[v], 1);  // shading reads this view's depth mapping
      }
      r.shadeGroom(t, *d.instance, inst, maps, options, false, &gbuffer);
      const FilterParams& fp = d.instance->hasFilter ? d.instance->filter : s.filter;
      const bool filtered =
          options.msaa == 1 && (options.filter < 0 ? fp.enabled : options.filter == 1);
      // the shared strand pass writes no identity layer, so "auto" falls back to Lipp's
      // filter here; Huang's asked for by name is refused
      if (filtered && (options.filterMethod < 0 ? fp.method == FilterParams::Method::Huang
                                                : options.filterMethod == 1))
        throw Error("groom \"" + d.instance->name +
                    "\": Huang's filter takes one view at a time; render the views one by one "
                    "(--views NAME) or use Lipp's filter");
      if (filtered)
        r.filter.enqueue(fp, {t.viewTarget(), &inst.groom, &gbuffer, &t.hair, &t.filtered},
                         &r.profiler);
      r.composite.enqueue(
          {t.viewTarget(), &inst.groom, filtered ? &t.filtered : &t.hair, &gbuffer, &t.color,
           &depth, options.msaa, filtered ? 2 : options.msaa, PixelRect{}},
          &r.profiler);
    }
    inst.params = recs[lodView];
  }
  for (std::size_t v = 0; v < V; ++v) {
    RenderTarget& t = targetOf(v);
    Frame& frame = frames[v];
    frame.color.width = s.width;
    frame.color.height = s.height;
    frame.color.rgba.resize(pixels * 4);
    frame.depth.resize(pixels);
    readBack(r.dev, "the frame", t.color, frame.color.rgba.data(), pixels * 4);
    readBack(r.dev, "the frame's depth", r.viewDepthSlices[v], frame.depth.data(), pixels);
    frame.stats.strandsDrawn = drawnTotal[v];
    frame.stats.shadowStrandsDrawn = r.shadows.strandsDrawn();
  }
  frames[0].timings = r.profiler.collect();
  r.grooms.trim();
  return frames;
}

}  // namespace clhair
