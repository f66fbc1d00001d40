// test_budget_screen.cpp — the segment budget's screen rule (kernels/budget.cl, DESIGN.md
// "The segment budget").
//
// Allocation: the three budget kernels run on a hand-made arena of three grooms of known
// screen boxes, bundles and control points; the shares are the rule's, computed here by
// hand (S_d = min(R_d, max(G_d, floor(mu A_d))), the largest mu that fits), exactly, every
// record keeps at least one strand, and the drawn segments stay within each share. A groom
// over the keep fraction keeps its whole request when the others' cuts pay for it.
// Crowd: one groom filling the frame beside 99 tiny ones keeps its LOD count under a budget
// the tiny ones' cuts pay for; the uniform rule under the same budget cuts it.
// Smoothness: over a slow dolly with a small wobble, a groom crossing the keep fraction
// changes its share by small steps, where a hard threshold flips it back and forth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "cl/device_impl.h"
#include "clhair/gpu_types.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "groom/presets.h"
#include "test_util.h"

namespace clhair::test {
namespace {

using namespace gpu;

// One bundle of a hand-made groom: its LOD strands, control points and screen box.
struct HandBundle {
  std::uint32_t strands, points;
  float x0, y0, x1, y1;
};

// The budget kernels over hand-made draws (kind 0: hair meshes, all budgeted).
class HandArena {
 public:
  explicit HandArena(const std::vector<std::vector<HandBundle>>& grooms) : grooms_(grooms) {
    std::size_t words = 0;  // in uints; records take 4 each
    for (const auto& g : grooms) {
      const auto n = static_cast<std::uint32_t>(g.size());
      ClhBudgetDraw d{};
      d.records = n;
      d.records_at = static_cast<clh_u32>(words / 4);
      words += 4 * n;
      d.counts_at = static_cast<clh_u32>(words);
      words += clh_lod_counts_length(n);
      d.offsets_at = static_cast<clh_u32>(words);
      words += clh_lod_offsets_length(n);
      words = (words + 3) / 4 * 4;  // records stay 16-byte aligned
      d.kind = 0;
      d.active = CLH_BUDGET_DRAW_BUDGETED;
      d.min_points = 3;
      d.far = 0;
      draws_.push_back(d);
    }
    arena_.assign(words, 0u);
    for (std::size_t k = 0; k < grooms.size(); ++k) {
      const ClhBudgetDraw& d = draws_[k];
      const std::uint32_t n = d.records;
      std::uint32_t drawn = 0, visible = 0, segments = 0;
      for (std::uint32_t b = 0; b < n; ++b) {
        const HandBundle& hb = grooms[k][b];
        const ClhLodRecord r = clh_lod_record_make(hb.strands, hb.points, 1.0f, 0.0f);
        std::memcpy(&arena_[4 * (d.records_at + b)], &r, sizeof r);
        std::uint32_t* counts = &arena_[d.counts_at];
        counts[b] = hb.strands;
        counts[clh_lod_full_count_at(n, b)] = hb.strands;
        counts[clh_lod_segment_count_at(n, b)] = hb.strands * (hb.points - 1);
        const float box[4] = {hb.x0, hb.y0, hb.x1, hb.y1};
        for (std::uint32_t c = 0; c < 4; ++c)
          std::memcpy(&counts[clh_lod_box_at(n, b, c)], &box[c], 4);
        arena_[d.offsets_at + b] = drawn;
        drawn += hb.strands;
        visible += hb.strands;
        segments += hb.strands * (hb.points - 1);
      }
      arena_[d.offsets_at + clh_lod_drawn_total_at(n)] = drawn;
      arena_[d.offsets_at + clh_lod_visible_total_at(n)] = visible;
      arena_[d.offsets_at + clh_lod_segment_total_at(n)] = segments;
    }
  }

  // Runs budget_measure, budget_plan and budget_apply; fills state and the records.
  void run(std::uint64_t budget, float imageArea) {
    auto& dev = *sharedDevice().impl();
    cl::Program p = dev.program("budget.cl", "-DSCAN_WG=256");
    cl::Kernel measure(p, "budget_measure"), plan(p, "budget_plan"), apply(p, "budget_apply");
    const auto D = static_cast<cl_uint>(draws_.size());
    ClhBudgetRule rule{};
    rule.rule = CLH_BUDGET_RULE_SCREEN;
    rule.image_area = imageArea;
    rule.keep_lo = 0.15f;
    rule.keep_hi = 0.25f;
    rule.room_lo = 0.5f;
    state.assign(CLH_BUDGET_HEADER + CLH_BUDGET_DRAW_WORDS * D, 0u);
    cl::Buffer bd(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, D * sizeof(ClhBudgetDraw),
                  draws_.data());
    cl::Buffer ba(dev.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, arena_.size() * 4,
                  arena_.data());
    cl::Buffer br(dev.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof rule, &rule);
    cl::Buffer bs(dev.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, state.size() * 4,
                  state.data());
    const cl::NDRange wg(256), perDraw(256 * D);
    measure.setArg(0, bd), measure.setArg(1, D), measure.setArg(2, ba), measure.setArg(3, ba);
    measure.setArg(4, bs);
    dev.queue.enqueueNDRangeKernel(measure, cl::NullRange, perDraw, wg);
    plan.setArg(0, bd), plan.setArg(1, D), plan.setArg(2, ba), plan.setArg(3, ba);
    plan.setArg(4, static_cast<cl_ulong>(budget)), plan.setArg(5, br), plan.setArg(6, bs);
    dev.queue.enqueueNDRangeKernel(plan, cl::NullRange, wg, wg);
    apply.setArg(0, bd), apply.setArg(1, D), apply.setArg(2, ba), apply.setArg(3, ba);
    apply.setArg(4, br), apply.setArg(5, bs);
    dev.queue.enqueueNDRangeKernel(apply, cl::NullRange, perDraw, wg);
    dev.queue.enqueueReadBuffer(bs, CL_TRUE, 0, state.size() * 4, state.data());
    dev.queue.enqueueReadBuffer(ba, CL_TRUE, 0, arena_.size() * 4, arena_.data());
  }

  const std::uint32_t* draw(std::size_t k) const {
    return &state[CLH_BUDGET_HEADER + CLH_BUDGET_DRAW_WORDS * k];
  }
  std::uint32_t share(std::size_t k) const { return draw(k)[10]; }
  std::uint32_t request(std::size_t k) const { return draw(k)[4]; }
  std::uint32_t floor(std::size_t k) const { return draw(k)[6]; }
  std::uint32_t segments(std::size_t k) const { return draw(k)[1]; }
  ClhLodRecord record(std::size_t k, std::size_t b) const {
    ClhLodRecord r;
    std::memcpy(&r, &arena_[4 * (draws_[k].records_at + b)], sizeof r);
    return r;
  }

  std::vector<std::uint32_t> state;

 private:
  std::vector<std::vector<HandBundle>> grooms_;
  std::vector<ClhBudgetDraw> draws_;
  std::vector<std::uint32_t> arena_;
};

// Every record of every groom keeps at least one strand and at most its request, and each
// groom draws within its share (and within one strand of it: the running total rounds
// down once per groom).
void expectFloorsAndShares(const HandArena& a, const std::vector<std::vector<HandBundle>>& g) {
  for (std::size_t k = 0; k < g.size(); ++k) {
    EXPECT_GE(a.share(k), a.floor(k)) << k;
    EXPECT_LE(a.segments(k), a.share(k)) << k;
    EXPECT_GT(a.segments(k) + g[k][0].points - 1, a.share(k)) << k;
    for (std::size_t b = 0; b < g[k].size(); ++b) {
      const ClhLodRecord r = a.record(k, b);
      EXPECT_GE(r.strands, 1u) << k << " " << b;
      EXPECT_LE(r.strands, g[k][b].strands) << k << " " << b;
      EXPECT_EQ(r.coverage, static_cast<float>(g[k][b].strands) / static_cast<float>(r.strands));
    }
  }
}

TEST(BudgetScreen, HandComputedSharesAreTheRules) {
  // a 100 x 100 image; every groom under the keep fraction (no claims)
  //   A: 4 bundles of 100 strands at C = 9, box 20 x 20: R = 3200, F = 32, A = 400
  //   B: 2 bundles of 50 strands at C = 17, box 20 x 10: R = 1600, F = 32, A = 200
  //   C: 1 bundle of 10 strands at C = 5, box 10 x 10: R = 40, F = 4, A = 100
  const std::vector<std::vector<HandBundle>> g = {
      {{100, 9, 0, 0, 20, 20},
       {100, 9, 5, 5, 15, 15},
       {100, 9, 0, 0, 10, 20},
       {100, 9, 10, 0, 20, 5}},
      {{50, 17, 30, 30, 50, 40}, {50, 17, 35, 30, 45, 40}},
      {{10, 5, 60, 60, 70, 70}}};
  HandArena a(g);
  // budget 2000: C is capped at its request 40 (mu > 0.4); A and B share 1960 in proportion
  // 400 : 200: the largest mu with floor(400 mu) + floor(200 mu) <= 1960 lies just under
  // 3.27, where they are 1307 and 653 (1307 + 653 + 40 = 2000)
  a.run(2000, 100.0f * 100.0f);
  EXPECT_EQ(a.state[1], 1u);  // over the budget
  EXPECT_EQ(a.request(0), 3200u);
  EXPECT_EQ(a.request(1), 1600u);
  EXPECT_EQ(a.request(2), 40u);
  EXPECT_EQ(a.floor(0), 32u);
  EXPECT_EQ(a.floor(1), 32u);
  EXPECT_EQ(a.floor(2), 4u);
  EXPECT_EQ(a.share(0), 1307u);
  EXPECT_EQ(a.share(1), 653u);
  EXPECT_EQ(a.share(2), 40u);
  expectFloorsAndShares(a, g);
  // A keeps 4 + floor(1275 / 3168 * 396) = 163 strands: 1304 segments
  EXPECT_EQ(a.segments(0), 1304u);

  // a budget under the floors' sum: every groom at its floor, one strand per bundle
  HandArena starved(g);
  starved.run(50, 100.0f * 100.0f);
  for (std::size_t k = 0; k < g.size(); ++k) {
    EXPECT_EQ(starved.share(k), starved.floor(k)) << k;
    EXPECT_EQ(starved.segments(k), starved.floor(k)) << k;
  }
}

TEST(BudgetScreen, AGroomOverTheKeepFractionKeepsItsRequest) {
  // Big: 8 bundles of 200 strands at C = 9, box 60 x 60 (36 % of the image, claim 1):
  // R = 12800, F = 64; two small grooms of one bundle of 100 strands at C = 9 and box
  // 10 x 10: R = 800, F = 8 each.
  std::vector<HandBundle> big;
  for (int b = 0; b < 8; ++b) big.push_back({200, 9, 0, 0, 60, 60});
  const std::vector<std::vector<HandBundle>> g = {
      big, {{100, 9, 70, 70, 80, 80}}, {{100, 9, 85, 85, 95, 95}}};
  // budget 13000: the room above the floors (12920) covers the claim (12736), so the big
  // groom keeps all 12800 and the small ones share the 200 left: 100 each
  HandArena a(g);
  a.run(13000, 100.0f * 100.0f);
  EXPECT_EQ(a.share(0), 12800u);
  EXPECT_EQ(a.segments(0), 12800u);
  EXPECT_EQ(a.share(1), 100u);
  EXPECT_EQ(a.share(2), 100u);
  expectFloorsAndShares(a, g);
  // by area alone (no claim) it would get 3600 / 3800 of the budget: 12315
  // budget 9000: room 8920 / 12736 = 0.70, so the claim holds at phi = 0.40: G = 64 +
  // floor(0.40 x 12736) = 5167 (+- 2 for the rounding of phi), under what the area gives
  // (9000 - 16 = 8984 of which 3600 / 3800), so the big groom's share is its area's
  HandArena b(g);
  b.run(9000, 100.0f * 100.0f);
  EXPECT_NEAR(static_cast<double>(b.draw(0)[13]), 5167.0, 2.0);  // G, the claim's floor
  EXPECT_GE(b.share(0), b.draw(0)[13]);
  EXPECT_GE(b.share(0) + b.share(1) + b.share(2), 9000u - 3u);
  EXPECT_LE(b.share(0) + b.share(1) + b.share(2), 9000u);
  expectFloorsAndShares(b, g);
}

// ---- whole frames ----------------------------------------------------------------------

// The tiny patch with `strands` strands at full detail under LOD (lambda 1000: L = 1, so
// the budget alone reduces it).
std::shared_ptr<const HairMesh> densePatch(int strands) {
  HairMesh m = makeGroomPreset("tiny");
  m.strandCount = strands;
  m.lod.enabled = true;
  m.lod.lambda = 1000.0f;
  m.lod.strandsPerPixel = 0.0f;  // the strands from L (Lipp Eq. 1), not from the screen
  return std::make_shared<const HairMesh>(std::move(m));
}

std::shared_ptr<const HairMesh> tinyPatch() {
  HairMesh m = makeGroomPreset("tiny");
  m.lod.enabled = true;
  m.lod.lambda = 1000.0f;
  m.lod.strandsPerPixel = 0.0f;  // the strands from L (Lipp Eq. 1), not from the screen
  return std::make_shared<const HairMesh>(std::move(m));
}

// One dense patch in front of the camera (it fills the 64 x 48 frame) and 99 tiny patches
// in a grid 1.5 m behind it, a few pixels each.
Scene bigBesideTiny() {
  Scene s;
  s.width = 64;
  s.height = 48;
  s.camera.position = {0.0f, 0.025f, 0.075f};
  s.camera.target = {0.0f, 0.025f, 0.0f};
  s.lights.push_back(Light{});
  s.grooms.emplace_back("big", densePatch(2000));
  auto tiny = tinyPatch();
  for (int i = 0; i < 99; ++i) {
    const float x = -0.45f + 0.1f * static_cast<float>(i % 10);
    const float y = -0.3f + 0.08f * static_cast<float>(i / 10);
    s.grooms.emplace_back("tiny " + std::to_string(i), tiny,
                          glm::translate(glm::mat4(1.0f), glm::vec3(x, y, -1.5f)));
  }
  return s;
}

TEST(BudgetScreen, AGroomFillingTheFrameKeepsItsCountBesideNinetyNineTiny) {
  Renderer r(sharedDevice());
  const Scene s = bigBesideTiny();
  RenderOptions o;
  o.rasterOnly = true;  // the LOD records and the budget are all this looks at
  o.segmentBudget = 0;
  const Frame free = r.render(s, o);
  ASSERT_EQ(free.stats.grooms.size(), 100u);
  const GroomDrawStats big = free.stats.grooms[0];
  std::uint64_t tinyRequest = 0, tinyFloor = 0;
  for (std::size_t k = 1; k < 100; ++k) {
    ASSERT_TRUE(free.stats.grooms[k].drawn) << k;
    tinyRequest += free.stats.grooms[k].segments;
  }
  // a budget the tiny ones' cuts pay for: the big groom's request and a quarter of the
  // tiny ones' (under the budget they draw every other control point, half their request)
  const std::uint64_t budget = big.segments + tinyRequest / 4;
  o.segmentBudget = static_cast<std::int64_t>(budget);
  const Frame screen = r.render(s, o);
  ASSERT_TRUE(screen.stats.overBudget);
  const GroomDrawStats& b = screen.stats.grooms[0];
  ASSERT_GT(b.screenArea / (64.0f * 48.0f), 0.25f) << "the big groom fills the frame";
  EXPECT_EQ(b.keepClaim, 1.0f);
  EXPECT_EQ(b.strands, big.strands);  // its LOD count
  EXPECT_EQ(b.segments, big.segments);
  std::uint64_t tinyDrawn = 0;
  for (std::size_t k = 1; k < 100; ++k) {
    const GroomDrawStats& g = screen.stats.grooms[k];
    tinyFloor += g.floor;
    tinyDrawn += g.segments;
    EXPECT_GE(g.segments, g.floor) << k;  // one strand per drawn bundle at least
    EXPECT_LE(g.segments, free.stats.grooms[k].segments) << k;
  }
  EXPECT_LT(tinyFloor, tinyRequest / 4) << "the tiny ones can give way";
  EXPECT_LT(tinyDrawn, tinyRequest);
  EXPECT_LE(screen.stats.segmentsPlanned, budget);
  // the uniform rule under the same budget cuts the big groom with the others
  o.budgetRule = BudgetRule::Uniform;
  const Frame uniform = r.render(s, o);
  EXPECT_LT(uniform.stats.grooms[0].strands, big.strands);
  std::printf("big groom: %u strands of %u under the screen rule, %u under the uniform rule\n",
              b.strands, big.strands, uniform.stats.grooms[0].strands);
}

TEST(BudgetScreen, ShareChangesSmoothlyWhereAGroomCrossesTheKeepFraction) {
  // A dense patch the camera approaches slowly, with a small wobble (the distance goes
  // 0.1 % closer per frame and 0.3 % back and forth), beside a second dense patch: the first
  // crosses a screen share of 0.2, where its claim to keep its LOD count sets in. With the
  // claim's ramp (0.15 .. 0.25) its share moves by small steps; with a hard threshold at
  // 0.2 (the ramp switched off) it jumps back and forth with the wobble.
  Renderer r(sharedDevice());
  Scene s;
  s.width = 64;
  s.height = 48;
  s.lights.push_back(Light{});
  s.grooms.emplace_back("subject", densePatch(1500));
  s.grooms.emplace_back("other", densePatch(3000),
                        glm::translate(glm::mat4(1.0f), glm::vec3(-0.07f, 0.0f, -0.02f)));
  auto at = [&](float distance) {
    Scene f = s;
    f.camera.position = {0.02f, 0.025f, distance};
    f.camera.target = {0.02f, 0.025f, 0.0f};
    return f;
  };
  RenderOptions o;
  o.rasterOnly = true;
  o.segmentBudget = 0;
  // the distance where the subject's box covers 0.2 of the frame (box area ~ 1 / d^2,
  // refined twice)
  float dMid = 0.2f;
  for (int i = 0; i < 3; ++i) {
    const float share = r.render(at(dMid), o).stats.grooms[0].screenArea / (64.0f * 48.0f);
    ASSERT_GT(share, 0.0f);
    dMid *= std::sqrt(share / 0.2f);
  }
  // the budget: the subject's request, the other's floor and a tenth of the rest (the
  // subject's claim fits; by area alone it would get about two thirds of its request)
  const Frame free = r.render(at(dMid), o);
  const GroomDrawStats& other = free.stats.grooms[1];
  o.segmentBudget = static_cast<std::int64_t>(free.stats.grooms[0].segments + other.floor +
                                              (other.segments - other.floor) / 10);
  // frame k of the dolly: 0.1 % closer per frame, 0.3 % back and forth
  auto distanceAt = [&](int k) {
    return dMid * (1.008f - 0.001f * static_cast<float>(k)) * (k % 2 ? 1.003f : 0.997f);
  };
  auto shares = [&](float keepLow, float keepHigh, std::vector<double>* share,
                    std::vector<double>* span) {
    o.budgetKeepLow = keepLow;
    o.budgetKeepHigh = keepHigh;
    for (int k = 0; k < 16; ++k) {
      const float d = distanceAt(k);
      const GroomDrawStats g = r.render(at(d), o).stats.grooms[0];
      share->push_back(static_cast<double>(g.share));
      span->push_back(static_cast<double>(g.requested) - static_cast<double>(g.floor));
    }
  };
  // the largest step, and the direction reversals of steps over 10 % of R - F
  auto jumps = [](const std::vector<double>& share, const std::vector<double>& span,
                  double* largest) {
    int reversals = 0;
    double last = 0.0;
    *largest = 0.0;
    for (std::size_t k = 1; k < share.size(); ++k) {
      const double step = (share[k] - share[k - 1]) / std::max(span[k], 1.0);
      *largest = std::max(*largest, std::abs(step));
      if (std::abs(step) > 0.1) {
        if (last != 0.0 && (step > 0.0) != (last > 0.0)) ++reversals;
        last = step;
      }
    }
    return reversals;
  };
  std::vector<double> ramp, rampSpan, hard, hardSpan;
  shares(0.15f, 0.25f, &ramp, &rampSpan);
  shares(0.2f, 0.2f, &hard, &hardSpan);
  double rampStep = 0.0, hardStep = 0.0;
  const int rampFlips = jumps(ramp, rampSpan, &rampStep);
  const int hardFlips = jumps(hard, hardSpan, &hardStep);
  std::printf("largest share step / (R - F): ramp %.3f (%d reversals), hard threshold %.3f (%d)\n",
              rampStep, rampFlips, hardStep, hardFlips);
  EXPECT_EQ(rampFlips, 0);
  EXPECT_LT(rampStep, 0.1);
  // the share is a function of the frame alone: frame 5 of the ramp's sequence, drawn by a
  // renderer that drew nothing before, gets the same share (no state from earlier frames)
  Renderer fresh(sharedDevice());
  o.budgetKeepLow = 0.15f;
  o.budgetKeepHigh = 0.25f;
  const float d5 = distanceAt(5);
  const FrameStats alone = fresh.render(at(d5), o).stats;
  EXPECT_EQ(static_cast<double>(alone.grooms[0].share), ramp[5]);
  EXPECT_EQ(alone.segmentsPlanned, r.render(at(d5), o).stats.segmentsPlanned);
  // the measurement sees a flipping share: a hard threshold flips it back and forth
  EXPECT_GE(hardFlips, 2);
}

}  // namespace
}  // namespace clhair::test
