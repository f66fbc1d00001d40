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

namespace {

// The view of `camera` drawn into `t` (its depth and G-buffer `depth`, `gbuffer`).
ViewPlan viewPlan(const FramePlan& plan, std::size_t v, const Camera& camera, RenderTarget& t,
                  cl::Buffer* depth, cl::Buffer* gbuffer, bool several) {
  const Scene& s = plan.scene;
  const RenderOptions& o = plan.options;
  ViewPlan vp;
  vp.index = v;
  vp.suffix = several ? ", view " + std::to_string(v) : "";
  vp.target = &t;
  vp.depthBuffer = depth;
  vp.gbufferBuffer = gbuffer;
  vp.view = makeView(camera, s.width, s.height);
  vp.view.samples = static_cast<gpu::clh_u32>(o.msaa);
  vp.view.cx += o.jitterX;
  vp.view.cy += o.jitterY;
  ViewDraw& d = vp.draw;
  d.view = &t.view;
  d.worldToView = worldToView(camera);
  d.lod = o.lod;
  d.lodLambdaScale = o.lodLambdaScale * lodResolutionScale(s.height);
  d.lodStrandScale = o.lodLambdaScale;
  d.trueWidth = o.trueWidth;
  d.shadowLodCorrection = plan.lodCorrection;
  d.pixels = faintView(vp.view);
  return vp;
}

// The options a frame of several views refuses.
void checkSeveralViews(const Scene& s, const RenderOptions& o) {
  if (o.aovs || o.captureGBuffer || o.rasterOnly)
    throw Error("several views render the beauty only (no --aov, G-buffer capture or raster-only)");
  if (coverMode(s, o))
    throw Error("the coverage raster renders one view at a time (choose one with --views NAME)");
}

// Groom `g` in a frame of several views: the views it is in front of, the first of them (its
// LOD and culling), and its filter (Lipp's: the shared strand pass writes no identity layer,
// so "auto" falls back to it; Huang's asked for by name is refused).
void planInViews(const FramePlan& plan, GroomPlan& g) {
  const RenderOptions& o = plan.options;
  const GroomDraw& d = g.draw;
  const std::size_t V = plan.views.size();
  g.layers = o.msaa + 1;
  g.lodView = V;
  for (std::size_t v = V; v-- > 0;) {
    g.views[v].inFront = d.groom->inFront(d.instance->transform, plan.views[v].draw.worldToView);
    if (g.views[v].inFront) g.lodView = v;
  }
  if (g.lodView == V) return;
  g.active = static_cast<char>(CLH_BUDGET_DRAW_FIXED);
  const FilterParams& fp = *g.filter;
  g.filtered = o.msaa == 1 && isOn(o.filter, fp.enabled);
  if (g.filtered && o.filterMethod.value_or(fp.method) == FilterParams::Method::Huang)
    throw Error("groom \"" + d.instance->name +
                "\": Huang's filter takes one view at a time; render the views one by one "
                "(--views NAME) or use Lipp's filter");
  g.depthLayers = static_cast<std::uint32_t>(g.filtered ? 2 : o.msaa);
}

// Groom `g` in a frame of one view: whether it is in front of the camera, its budget role,
// filter, layers, screen box and motion pass.
void planInView(FramePlan& plan, GroomPlan& g) {
  const RenderOptions& options = plan.options;
  const GroomDraw& d = g.draw;
  const ViewPlan& camera = plan.camera();
  const bool given = plan.source != nullptr;
  const FilterParams& fp = *g.filter;
  g.layers = gbufferLayers(fp, options, given, plan.cover);
  if (!d.groom->inFront(d.instance->transform, camera.draw.worldToView)) return;
  g.views[0].inFront = true;
  // the budget is a stage of LOD: a groom drawn without LOD keeps every strand
  const bool lodOn = isOn(options.lod, d.groom->lodEnabled());
  g.active = static_cast<char>(lodOn ? CLH_BUDGET_DRAW_BUDGETED : CLH_BUDGET_DRAW_FIXED);
  g.far = farGroom(*d.groom, d.instance->transform, camera.draw.worldToView, camera.view) ? 1 : 0;
  plan.lastDrawn = g.index;
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
    g.box =
        screenBox(d.groom->boundsMin(), d.groom->boundsMax(),
                  camera.draw.worldToView * d.instance->transform, camera.view, kScreenBoxMargin);
  // Huang's filter leaves its result right inside the box only; the AOVs read all of it
  g.hairBox = plan.aovs ? PixelRect{} : g.box;
  const Scene* before = plan.aovs ? options.previous : nullptr;
  g.motion = before && !given && g.index < before->grooms.size() &&
             deformsBetween(*d.instance, before->grooms[g.index]);
  if (g.motion && plan.cover)
    throw Error("groom \"" + d.instance->name +
                "\" deforms: the coverage raster has no motion pass for its motion layer "
                "(use the lines raster)");
}

}  // namespace

void planFrame(FramePlan& plan, const std::vector<GroomDraw>& draws, DispatchMode mode,
               const std::vector<Camera>& cameras, const std::vector<RenderTarget*>& targets,
               const std::vector<cl::Buffer*>& depths, const std::vector<cl::Buffer*>& gbuffers) {
  const Scene& s = plan.scene;
  const RenderOptions& options = plan.options;
  const bool given = plan.source != nullptr;
  const bool several = cameras.size() > 1;
  if (several) checkSeveralViews(s, options);
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
  plan.pixels = static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height);
  plan.views.clear();
  for (std::size_t v = 0; v < cameras.size(); ++v)
    plan.views.push_back(
        viewPlan(plan, v, cameras[v], *targets.at(v), depths.at(v), gbuffers.at(v), several));

  plan.grooms.assign(draws.size(), GroomPlan{});
  plan.lastDrawn = draws.size();
  for (std::size_t k = 0; k < draws.size(); ++k) {
    GroomPlan& g = plan.grooms[k];
    const GroomDraw& d = draws[k];
    g.index = k;
    g.draw = d;
    g.filter = d.instance->hasFilter ? &d.instance->filter : &s.filter;
    g.views.assign(cameras.size(), GroomView{});
    if (several)
      planInViews(plan, g);
    else
      planInView(plan, g);
  }
}

}  // namespace clhair
