// frame_plan.cpp — see frame_plan.h.
#include "frame/frame_plan.h"

#include <algorithm>

#include <glm/geometric.hpp>

#include "frame/frame_lod.h"
#include "frame/render_target.h"
#include "stages/view_math.h"

namespace clhair {

namespace {

// Under a segment budget, grooms whose bounding sphere spans less than this share of the
// image height also drop every other control point (Kulikov 2025: far models draw half
// their vertices).
constexpr float kBudgetFarShare = 0.2f;

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

// Whether a groom instance moves its strands between two still frames other than by its
// transform: another cage (cage animation, wind) or another per-frame strand file.
bool deformsBetween(const GroomInstance& now, const GroomInstance& before) {
  if (now.strands || before.strands) return now.strands != before.strands;
  const auto &a = now.deformed, &b = before.deformed;
  if (a == b || !now.mesh) return false;
  if (a && b) return *a != *b;
  return *(a ? a : b) != now.mesh->positions;
}

}  // namespace

bool coverMode(const Scene& s, const RenderOptions& options) {
  const bool cover = options.raster.value_or(s.raster) == RasterMode::Coverage;
  if (cover && options.msaa != 1)
    throw Error(
        "the coverage raster takes one sample per pixel (its coverage is analytic), not "
        "MSAA " +
        std::to_string(options.msaa));
  if (cover && (options.strandIds || options.cryptomatte))
    throw Error(std::string("the coverage raster has no strand identity layer") +
                (options.cryptomatte ? " for the Cryptomatte layers" : "") +
                " (use the lines raster)");
  return cover;
}

bool huangMethod(const FilterParams& fp, const RenderOptions& options) {
  // Auto: Huang's in one view
  return options.filterMethod.value_or(fp.method) != FilterParams::Method::Lipp;
}

bool pointShading(const RenderOptions& options, bool given, bool cover) {
  return options.pointShading == Toggle::On && !given && !cover && !options.rasterOnly;
}

int gbufferLayers(const FilterParams& fp, const RenderOptions& options, bool given, bool cover) {
  if (cover) return static_cast<int>(CLH_LAYER_COVERAGE) + 1;
  // the samples, the conservative layer, then one identity layer per sample
  if (pointShading(options, given, cover)) return 2 * options.msaa + 1;
  const bool filtered = options.msaa == 1 && isOn(options.filter, fp.enabled);
  const bool huang = filtered && !options.rasterOnly && huangMethod(fp, options);
  const bool ids = huang || options.strandIds || options.cryptomatte;
  if (ids && options.msaa != 1)
    throw Error(std::string("strand identities (") +
                (options.cryptomatte ? "the Cryptomatte layers" : "the strand.id layer") +
                ") need MSAA 1, not " + std::to_string(options.msaa));
  if (huang && fp.link && !given) return static_cast<int>(CLH_LAYER_LINKED) + 1;
  return ids ? static_cast<int>(CLH_LAYER_ID) + 1 : options.msaa + 1;
}

void layoutStats(FramePlan& plan, std::size_t views, std::size_t shadowSlots) {
  const std::size_t D = plan.grooms.size();
  plan.stats = StatsLayout{};
  plan.rasterStatsAt = plan.stats.take(4);
  plan.budgetAt = plan.stats.take(views == 1 ? FrameLod::stateWords(D) : 0);
  plan.linkAt = plan.stats.take(views == 1 ? 4 * D : views * D);
  plan.pointsAt = plan.stats.take(views == 1 ? D : 0);
  plan.shadowAt = plan.stats.take(CLH_MAX_SHADOWS * shadowSlots);
}

void planViews(FramePlan& plan, const std::vector<GroomDraw>& draws, DispatchMode mode) {
  const Scene& s = plan.scene;
  const RenderOptions& o = plan.options;
  if (o.aovs || o.captureGBuffer || o.rasterOnly)
    throw Error("several views render the beauty only (no --aov, G-buffer capture or raster-only)");
  if (coverMode(s, o))
    throw Error("the coverage raster renders one view at a time (choose one with --views NAME)");
  plan.mode = mode;
  plan.lodCorrection = isOn(o.shadowLodCorrection, s.shadows.lodCorrection);
  plan.pixels = static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height);
  plan.grooms.assign(draws.size(), GroomPlan{});
  for (std::size_t k = 0; k < draws.size(); ++k) {
    GroomPlan& g = plan.grooms[k];
    g.index = k;
    g.draw = draws[k];
    g.filter = draws[k].instance->hasFilter ? &draws[k].instance->filter : &s.filter;
    g.layers = o.msaa + 1;
  }
}

void planFrame(FramePlan& plan, const std::vector<GroomDraw>& draws, DispatchMode mode) {
  const Scene& s = plan.scene;
  const RenderOptions& options = plan.options;
  const bool given = plan.source != nullptr;
  if (given && options.msaa != 1)
    throw Error("a given G-buffer has one sample per pixel, not MSAA " +
                std::to_string(options.msaa));
  plan.cover = coverMode(s, options);
  if (given && plan.cover) throw Error("a given G-buffer has no coverage layers");
  plan.mode = mode;
  plan.aovs = options.aovs && !options.rasterOnly;
  plan.lodCorrection = isOn(options.shadowLodCorrection, s.shadows.lodCorrection);
  plan.budget = options.segmentBudget >= 0
                    ? static_cast<std::uint64_t>(options.segmentBudget)
                    : s.segmentBudget.value_or(defaultSegmentBudget(s.width, s.height));
  plan.view = makeView(s.camera, s.width, s.height);
  plan.view.samples = static_cast<gpu::clh_u32>(options.msaa);
  plan.view.cx += options.jitterX;
  plan.view.cy += options.jitterY;
  plan.pixels = static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height);
  ViewDraw& pass = plan.cameraPass;
  pass.view = &plan.target->view;
  pass.worldToView = worldToView(s.camera);
  pass.lod = options.lod;
  pass.lodLambdaScale = options.lodLambdaScale * lodResolutionScale(s.height);
  pass.lodStrandScale = options.lodLambdaScale;
  pass.trueWidth = options.trueWidth;
  pass.shadowLodCorrection = plan.lodCorrection;
  pass.pixels = faintView(plan.view);

  const Scene* before = plan.aovs ? options.previous : nullptr;
  plan.grooms.assign(draws.size(), GroomPlan{});
  plan.lastDrawn = draws.size();
  for (std::size_t k = 0; k < draws.size(); ++k) {
    GroomPlan& g = plan.grooms[k];
    const GroomDraw& d = draws[k];
    g.index = k;
    g.draw = d;
    const FilterParams& fp = d.instance->hasFilter ? d.instance->filter : s.filter;
    g.filter = &fp;
    g.layers = gbufferLayers(fp, options, given, plan.cover);
    if (!d.groom->inFront(d.instance->transform, pass.worldToView)) continue;
    // the budget is a stage of LOD: a groom drawn without LOD keeps every strand
    const bool lodOn = isOn(options.lod, d.groom->lodEnabled());
    g.active = static_cast<char>(lodOn ? CLH_BUDGET_DRAW_BUDGETED : CLH_BUDGET_DRAW_FIXED);
    g.far = farGroom(*d.groom, d.instance->transform, pass.worldToView, plan.view) ? 1 : 0;
    plan.lastDrawn = k;
    // the coverage mode has no filter: its alpha comes from the coverage layer
    g.points = pointShading(options, given, plan.cover);
    g.filtered = !plan.cover && !g.points && options.msaa == 1 && isOn(options.filter, fp.enabled);
    g.huang = g.filtered && !options.rasterOnly && huangMethod(fp, options);
    g.linking = g.huang && fp.link && !given;
    g.ids = g.huang || options.strandIds || options.cryptomatte;
    // the composite takes the hair's depth from the samples, plus the conservative layer
    // after Lipp's filter (the centre layer holds the linked pixels after Huang's)
    g.depthLayers = static_cast<std::uint32_t>(g.filtered && !g.huang ? 2 : options.msaa);
    // the pixels it can draw into: the G-buffer clear before it and the passes that concern
    // only its pixels run there (a given G-buffer may hold words anywhere)
    if (options.screenBoxes && !given)
      g.box = screenBox(d.groom->boundsMin(), d.groom->boundsMax(),
                        pass.worldToView * d.instance->transform, plan.view, kScreenBoxMargin);
    // Huang's filter leaves its result right inside the box only; the AOVs read all of it
    g.hairBox = plan.aovs ? PixelRect{} : g.box;
    g.motion = before && !given && k < before->grooms.size() &&
               deformsBetween(*d.instance, before->grooms[k]);
    if (g.motion && plan.cover)
      throw Error("groom \"" + d.instance->name +
                  "\" deforms: the coverage raster has no motion pass for its motion layer "
                  "(use the lines raster)");
  }
}

}  // namespace clhair
