// readback_pass.cpp — the frame's result read back without blocking (passes.h): colour and
// depth, the statistics the passes gathered on the device (the budget's outcome, the shadow
// passes' strand totals, the raster counters, the linking counters) in one buffer, the AOV
// planes and the captured G-buffer. Finishers decode them when the frame completes.
#include <functional>
#include <memory>

#include "frame/aov_builder.h"
#include "passes/passes.h"

namespace clhair {

namespace {

void copyWords(Renderer::Impl& r, const cl::Buffer& from, cl::Buffer& stats, std::size_t words,
               std::size_t at) {
  if (words == 0 || !from()) return;
  r.target.copyUints(from, 0, stats, at, words, &r.profiler);
}

// The statistics words, every view's colour and depth and the captured G-buffer into the
// frame (non-blocking reads, done when the frame completes).
void readImages(const FrameGraph::Resources& res, Renderer::Impl& r, FramePlan& plan,
                PendingFrame& out, std::size_t shadowWords) {
  const std::size_t D = plan.grooms.size();
  const bool one = !plan.severalViews();
  cl::Buffer& stats = res[plan.frameStats];
  if (one) copyWords(r, r.frameLod.state(), stats, FrameLod::stateWords(D), plan.budgetAt);
  copyWords(r, r.shadows.totals(), stats, shadowWords, plan.shadowAt);
  if (one && plan.options.rasterStats)
    copyWords(r, res[plan.rasterCounters], stats, 4, plan.rasterStatsAt);
  out.stats.assign(plan.stats.words, 0u);
  out.read(r.dev, r.pinned, stats, 0, out.stats.data(), out.stats.size() * 4);
  for (const ViewPlan& vp : plan.views) {
    Frame& f = out.frames[vp.index];
    f.color.width = plan.scene.width;
    f.color.height = plan.scene.height;
    f.color.rgba.resize(plan.pixels * 4);
    if (plan.options.readBackDepth || plan.aovs) f.depth.resize(plan.pixels);
    out.read(r.dev, r.pinned, res[vp.color], 0, f.color.rgba.data(), f.color.rgba.size() * 4);
    if (!f.depth.empty())
      out.read(r.dev, r.pinned, res[vp.depth], 0, f.depth.data(), f.depth.size() * 4);
  }
  if (plan.options.captureGBuffer) {
    const RenderTarget& t = *plan.camera().target;
    Frame& f = out.frames[0];
    f.gbufferLayers = t.usedLayers();
    f.gbuffer.assign(plan.pixels * static_cast<std::size_t>(t.usedLayers()), ~std::uint64_t(0));
    if (plan.lastDrawn < D)
      out.read(r.dev, r.pinned, res[plan.camera().gbuffer], 0, f.gbuffer.data(),
               f.gbuffer.size() * 8);
  }
}

// The AOV planes, and the finisher that turns them into the frame's AOVs.
void readAovs(const FrameGraph::Resources& res, const AovHandles& h, Renderer::Impl& r,
              FramePlan& plan, PendingFrame& out) {
  auto planes = std::make_shared<AovPlanesHost>();
  const std::size_t n = plan.pixels;
  planes->owner.resize(n);
  planes->ownerMotion.resize(n);
  planes->alpha.resize(n);
  planes->hair.resize(n * 4);
  planes->tangent.resize(n * 4);
  planes->strand.resize(n * 4);
  planes->ids = plan.options.strandIds;
  out.read(r.dev, r.pinned, res[h.owner], 0, planes->owner.data(), n * 4);
  out.read(r.dev, r.pinned, res[h.ownerMotion], 0, planes->ownerMotion.data(), n * 8);
  out.read(r.dev, r.pinned, res[h.alpha], 0, planes->alpha.data(), n * 4);
  out.read(r.dev, r.pinned, res[h.hair], 0, planes->hair.data(), n * 16);
  out.read(r.dev, r.pinned, res[h.tangent], 0, planes->tangent.data(), n * 16);
  out.read(r.dev, r.pinned, res[h.strand], 0, planes->strand.data(), n * 16);
  const AovMotionInputs in =
      AovMotionInputs::of(plan.camera().view, plan.scene, plan.options.previous);
  out.finishers.push_back([planes, in](PendingFrame& p) {
    Frame& frame = p.frames[0];
    std::vector<float> opaque = std::move(frame.aovs.opaque);
    frame.aovs = finishAovs(*planes, frame.depth, in);
    frame.aovs.opaque = std::move(opaque);
  });
}

// What the statistics finisher needs of the plan, copied (the plan is gone by then).
struct StatsSource {
  struct Drawn {
    std::string name;
    bool drawn = false, huang = false, points = false, lod = false;
  };
  std::vector<Drawn> drawn;
  std::uint64_t budget = 0;
  bool screenRule = true;
  std::uint32_t mapsBuilt = 0;
  int mapRes = 0;
  std::size_t budgetAt = 0, linkAt = 0, pointsAt = 0, shadowAt = 0, rasterStatsAt = 0;
  std::size_t shadowWords = 0;
};

StatsSource statsSource(Renderer::Impl& r, const FramePlan& plan, std::size_t shadowWords) {
  StatsSource src;
  for (const GroomPlan& gp : plan.grooms)
    src.drawn.push_back({gp.draw.instance->name, gp.active != 0,
                         gp.huang && !plan.options.rasterOnly, gp.active != 0 && gp.points,
                         gp.active == CLH_BUDGET_DRAW_BUDGETED});
  src.budget = plan.budget;
  src.screenRule = plan.options.budgetRule != BudgetRule::Uniform;
  if (plan.shadowsRebuilt)
    src.mapsBuilt =
        static_cast<std::uint32_t>(ShadowMaps::mappedLights(plan.scene, plan.grooms.size()).size());
  src.mapRes = r.shadows.resolution();
  src.budgetAt = plan.budgetAt;
  src.linkAt = plan.linkAt;
  src.pointsAt = plan.pointsAt;
  src.shadowAt = plan.shadowAt;
  src.rasterStatsAt = plan.rasterStatsAt;
  src.shadowWords = shadowWords;
  return src;
}

// One groom draw's statistics from the budget's outcome.
GroomDrawStats groomStats(const StatsSource::Drawn& d, std::size_t k, std::size_t D,
                          const FrameLod::Result& lod) {
  GroomDrawStats g;
  g.instance = k;
  g.name = d.name;
  g.drawn = d.drawn;
  g.lod = d.lod;
  if (!g.drawn || lod.draw.size() < 4 * D) return g;
  g.strands = lod.draw[4 * k];
  g.segments = lod.draw[4 * k + 1];
  g.visibleStrands = lod.draw[4 * k + 2];
  g.halved = (lod.draw[4 * k + 3] & CLH_BUDGET_HALVED) != 0;
  g.requested = lod.plan[k].request;
  g.floor = lod.plan[k].floor;
  g.share = lod.plan[k].share;
  g.screenArea = lod.plan[k].area;
  g.keepClaim = lod.plan[k].claim * lod.claims;
  return g;
}

// The frame's statistics decoded from the words read back.
void decodeStats(const StatsSource& at, const std::vector<std::uint32_t>& w, FrameStats& st) {
  const std::size_t D = at.drawn.size();
  std::vector<std::uint32_t> lodWords(
      w.begin() + static_cast<std::ptrdiff_t>(at.budgetAt),
      w.begin() + static_cast<std::ptrdiff_t>(at.budgetAt + FrameLod::stateWords(D)));
  const FrameLod::Result lod = FrameLod::decode(lodWords, D);
  st.segmentBudget = at.budget;
  st.overBudget = lod.over;
  st.budgetScale = lod.scale;
  st.budgetScreenRule = at.screenRule;
  st.budgetLevel = lod.level;
  st.segmentsBeforeBudget = lod.lodSegments;
  st.shadowMapsBuilt = at.mapsBuilt;
  st.shadowResolution = at.mapRes;
  for (std::size_t k = 0; k < D; ++k) {
    GroomDrawStats g = groomStats(at.drawn[k], k, D, lod);
    st.strandsDrawn += g.strands;
    st.segmentsPlanned += g.segments;
    st.grooms.push_back(std::move(g));
    if (at.drawn[k].points) st.pointsShaded += w[at.pointsAt + k];
    if (!at.drawn[k].huang) continue;
    const std::uint32_t* c = &w[at.linkAt + 4 * k];
    st.linkSelecting += c[0];
    st.linkedPixels += c[1];
    st.linkStrands += c[2];
    st.linkTurnedAway += c[3];
  }
  for (std::size_t i = 0; i < at.shadowWords; ++i) st.shadowStrandsDrawn += w[at.shadowAt + i];
  const std::uint32_t* rs = &w[at.rasterStatsAt];
  st.pixelWrites = rs[0];
  st.atomicsIssued = rs[1];
  st.atomicsSkipped = rs[2];
  st.segmentsDrawn = rs[3];
}

// A frame of several views: each view's strands drawn and the lights' strand totals.
std::function<void(PendingFrame&)> viewsStats(const FramePlan& plan) {
  return [V = plan.views.size(), D = plan.grooms.size(), totalsAt = plan.linkAt,
          shadowAt = plan.shadowAt](PendingFrame& p) {
    std::uint64_t shadow = 0;
    for (std::size_t i = shadowAt; i < p.stats.size(); ++i) shadow += p.stats[i];
    for (std::size_t v = 0; v < V; ++v) {
      FrameStats& st = p.frames[v].stats;
      for (std::size_t k = 0; k < D; ++k) st.strandsDrawn += p.stats[totalsAt + v * D + k];
      st.shadowStrandsDrawn = shadow;
    }
  };
}

}  // namespace

void addReadBackPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, PendingFrame& out) {
  const std::size_t shadowWords = plan.stats.words - plan.shadowAt;
  const AovHandles* aovs = g.blackboard().get<AovHandles>(kAovPlanes);
  g.addPass(
      "read-back",
      [&](FrameGraph::Setup& s) {
        for (const ViewPlan& vp : plan.views) s.reads({vp.color, vp.depth});
        s.readsWrites({plan.frameStats}).reads({plan.lodArena, plan.shadowMaps});
        s.reads({plan.rasterCounters}).sideEffect().kernel("copy_uints");
        if (aovs)
          for (const FrameGraph::Handle h : aovs->all()) s.read(h);
        if (plan.options.captureGBuffer) s.read(plan.camera().gbuffer);
      },
      [&, shadowWords, aovs](const FrameGraph::Resources& res) {
        readImages(res, r, plan, out, shadowWords);
        if (aovs) readAovs(res, *aovs, r, plan, out);
      });
  // the statistics, decoded once the words are on the host
  if (plan.severalViews()) {
    out.finishers.insert(out.finishers.begin(), viewsStats(plan));
    return;
  }
  out.finishers.insert(out.finishers.begin(),
                       [at = statsSource(r, plan, shadowWords)](PendingFrame& p) {
                         decodeStats(at, p.stats, p.frames[0].stats);
                       });
}

}  // namespace clhair
