// test_budget.cpp — the segment budget, the per-asset strand cap and `clhair render --stats`.
//
// Budget: three instances of the tiny hair mesh and a strand file of equal-length strands,
// drawn with LOD at a lambda so large that every bundle keeps full detail (the budget is a
// stage of LOD), with a budget of half their segments: the factor is exactly 1/2, so every
// bundle or chunk keeps floor(N / 2) strands (at least one), counted here from the groom's
// own bundle table; the total the LOD records schedule and the segments the raster counts
// are both within the budget. A budget far below one strand per bundle leaves each groom
// one strand per bundle (none starves); a groom small on screen drops every other control
// point. Coverage: the hair's summed alpha under the budget, and with the strand cap and its
// thickness compensation, stays within 10 % of the full groom's (without compensation the
// cap loses more than that). --stats: per-groom strands and segments against counts taken
// from the files (strand count x (control points - 1); the cyHair file's points - strands).
// The default budget and LOD's λ by image size. Bad budgets and caps are one error line.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "groom/groom_data.h"
#include "groom/presets.h"
#include "test_util.h"

namespace clhair::test {
namespace {

using nlohmann::json;

// A strand file of `n` strands of `points` points each, as a fringe above the origin.
std::shared_ptr<const StrandGroom> fringe(std::uint32_t n, std::uint32_t points) {
  StrandGroom g;
  g.name = "fringe";
  g.lod.enabled = true;
  g.lod.lambda = 1000.0f;        // L = 1: full detail, the budget alone reduces
  g.lod.strandsPerPixel = 0.0f;  // the strands from L (Lipp Eq. 1), not from the screen
  for (std::uint32_t s = 0; s < n; ++s) {
    g.pointCounts.push_back(points);
    const float x = -0.02f + 0.04f * (static_cast<float>(s) + 0.5f) / static_cast<float>(n);
    for (std::uint32_t k = 0; k < points; ++k)
      g.points.emplace_back(x, 0.03f - 0.03f * static_cast<float>(k) / (points - 1), 0.01f);
  }
  return std::make_shared<const StrandGroom>(std::move(g));
}

Scene smallScene(const std::shared_ptr<const HairMesh>& tiny, int instances, bool strands) {
  Scene s;
  s.width = 64;
  s.height = 48;
  s.camera.position = {0.0f, 0.03f, 0.2f};
  s.camera.target = {0.0f, 0.025f, 0.0f};
  s.lights.push_back(Light{});
  for (int i = 0; i < instances; ++i) s.grooms.emplace_back("tiny " + std::to_string(i), tiny);
  if (strands) s.grooms.emplace_back("fringe", fringe(128, 5));
  return s;
}

// The tiny preset drawn with LOD at L = 1 everywhere (lambda 1000): full detail, under the
// budget.
std::shared_ptr<const HairMesh> tinyMesh() {
  HairMesh m = makeGroomPreset("tiny");
  m.lod.enabled = true;
  m.lod.lambda = 1000.0f;
  m.lod.strandsPerPixel = 0.0f;  // the strands from L (Lipp Eq. 1), not from the screen
  return std::make_shared<const HairMesh>(std::move(m));
}

TEST(Budget, ProportionalReductionIsExactAndHolds) {
  Renderer r(sharedDevice());
  auto tiny = tinyMesh();
  const Scene s = smallScene(tiny, 3, true);
  RenderOptions o;
  o.budgetRule = BudgetRule::Uniform;  // the uniform rule (the screen rule: test_budget_screen.cpp)
  o.segmentBudget = 0;
  const Frame full = r.render(s, o);
  const std::uint64_t perTiny = tiny->strandCount * (tiny->controlPoints - 1);
  ASSERT_EQ(full.stats.grooms.size(), 4u);
  for (int i = 0; i < 3; ++i) ASSERT_EQ(full.stats.grooms[i].segments, perTiny);
  ASSERT_EQ(full.stats.grooms[3].segments, 128u * 4u);
  const std::uint64_t total = 3 * perTiny + 512;
  ASSERT_EQ(full.stats.segmentsPlanned, total);

  // half the segments: f = 1/2 exactly
  o.segmentBudget = static_cast<std::int64_t>(total / 2);
  o.rasterStats = true;
  const Frame half = r.render(s, o);
  EXPECT_TRUE(half.stats.overBudget);
  EXPECT_EQ(half.stats.budgetScale, 0.5f);
  std::uint32_t tinyKept = 0;
  for (const gpu::ClhBundle& b : prepareGroom(*tiny).bundles)
    tinyKept += std::max(1u, b.strand_count / 2u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(half.stats.grooms[i].strands, tinyKept) << i;
    EXPECT_EQ(half.stats.grooms[i].segments, tinyKept * (tiny->controlPoints - 1)) << i;
    EXPECT_FALSE(half.stats.grooms[i].halved);
  }
  EXPECT_EQ(half.stats.grooms[3].strands, 64u);  // two chunks of 64 keep 32 each
  EXPECT_EQ(half.stats.grooms[3].segments, 256u);
  EXPECT_LE(half.stats.segmentsPlanned, total / 2);
  EXPECT_GT(half.stats.segmentsDrawn, 0u);
  EXPECT_LE(half.stats.segmentsDrawn, total / 2);  // what the raster walked

  // far below one strand per bundle: every groom keeps one strand per bundle or chunk
  o.segmentBudget = 10;
  const Frame starved = r.render(s, o);
  for (int i = 0; i < 3; ++i)
    EXPECT_EQ(starved.stats.grooms[i].strands, prepareGroom(*tiny).bundles.size()) << i;
  EXPECT_EQ(starved.stats.grooms[3].strands, 2u);

  // grooms drawn without LOD keep every strand and do not count
  o.lod = Toggle::Off;
  o.segmentBudget = static_cast<std::int64_t>(total / 2);
  const Frame lodOff = r.render(s, o);
  EXPECT_FALSE(lodOff.stats.overBudget);
  EXPECT_EQ(lodOff.stats.segmentsPlanned, total);
}

TEST(Budget, FarGroomsDropEveryOtherControlPoint) {
  Renderer r(sharedDevice());
  auto tiny = tinyMesh();
  Scene s = smallScene(tiny, 1, false);
  s.camera.position = {0.0f, 0.03f, 3.0f};  // the groom is a few pixels tall
  RenderOptions o;
  o.segmentBudget = 0;
  const Frame full = r.render(s, o);
  ASSERT_TRUE(full.stats.grooms[0].drawn);
  for (int rule : {0, 1}) {  // both rules halve far grooms first (Kulikov 2025)
    o.budgetRule = rule ? BudgetRule::Screen : BudgetRule::Uniform;
    o.segmentBudget = static_cast<std::int64_t>(full.stats.segmentsPlanned - 1);
    const GroomDrawStats g = r.render(s, o).stats.grooms[0];
    EXPECT_TRUE(g.halved) << rule;
    // C = 17 -> 9: 8 segments per strand, and halving alone fits, so no strand is dropped
    EXPECT_EQ(g.strands, full.stats.grooms[0].strands) << rule;
    EXPECT_EQ(g.segments, std::uint64_t(g.strands) * ((tiny->controlPoints - 1) / 2)) << rule;
  }
}

// Summed hair alpha of a frame (the grooms' coverage).
double coverage(Renderer& r, const Scene& s, std::int64_t budget) {
  RenderOptions o;
  o.aovs = true;
  o.segmentBudget = budget;
  const Frame f = r.render(s, o);
  double sum = 0.0;
  for (float a : f.aovs.hairAlpha) sum += a;
  return sum;
}

Scene coverageScene(const HairMesh& mesh, int width, int height) {
  Scene s;
  s.width = width;
  s.height = height;
  s.lights.push_back(Light{});
  s.grooms.emplace_back("curly", std::make_shared<const HairMesh>(mesh));
  s.camera = framePreset(s, CameraPreset::Close);
  return s;
}

TEST(Budget, CoverageStaysWithinTenPercentUnderTheBudget) {
  Renderer r(sharedDevice());
  HairMesh m = makeGroomPreset("curly_medium");
  m.strandCount = 2000;
  m.appearance.minHitDiameterPx = 0.5f;
  m.lod.enabled = true;
  m.lod.lambda = 1000.0f;  // full detail: the budget alone reduces
  m.lod.strandsPerPixel = 0.0f;
  const Scene s = coverageScene(m, 96, 72);
  const double full = coverage(r, s, 0);
  ASSERT_GT(full, 50.0);
  // the segment budget at a quarter of the frame's segments
  const std::int64_t quarter = m.strandCount * (m.controlPoints - 1) / 4;
  const double budgeted = coverage(r, s, quarter);
  EXPECT_NEAR(budgeted / full, 1.0, 0.10) << "budget " << quarter;
  std::printf("coverage: full %.1f, budget of a quarter of the segments %.1f\n", full, budgeted);
}

TEST(Budget, StrandCapKeepsCoverageByWideningTheFibres) {
  // sparse enough that coverage grows with the strands (it would saturate in a dense groom)
  Renderer r(sharedDevice());
  HairMesh m = makeGroomPreset("curly_medium");
  m.strandCount = 400;
  m.appearance.minHitDiameterPx = 0.5f;
  const double full = coverage(r, coverageScene(m, 128, 96), 0);
  ASSERT_GT(full, 50.0);
  HairMesh capped = m;
  EXPECT_FLOAT_EQ(capStrands(capped, 200), 2.0f);
  EXPECT_EQ(capped.strandCount, 200);
  const double cap = coverage(r, coverageScene(capped, 128, 96), 0);
  EXPECT_NEAR(cap / full, 1.0, 0.10);
  // the same cap without the compensation loses more than the tolerance
  HairMesh thin = m;
  thin.strandCount = 200;
  const double uncompensated = coverage(r, coverageScene(thin, 128, 96), 0);
  EXPECT_LT(uncompensated / full, 0.9);
  std::printf("coverage: full %.1f, cap 1/2 %.1f, cap without widening %.1f\n", full, cap,
              uncompensated);
}

// ---- the CLI ---------------------------------------------------------------------------

void writeJson(const std::string& path, const json& j) { std::ofstream(path) << j.dump(2); }

json cliScene() {
  return json{
      {"resolution", {64, 48}},
      {"camera", {{"preset", "far"}}},
      {"lights", {{{"type", "directional"}, {"direction", {0.3, 0.8, 0.5}}}}},
      {"grooms",
       {{{"file", assetPath("grooms/tiny.hairmesh.json")}},
        {{"strands_file", assetPath("grooms/head_bob.hair")}, {"scale", 0.001}, {"up", "z"}}}}};
}

TEST(Budget, StatsMatchCountsFromTheFiles) {
  const std::string dir = scratchDir();
  writeJson(dir + "/scene.json", cliScene());
  const CommandResult r = runCli("render " + quote(dir + "/scene.json") + " -o " +
                                 quote(dir + "/out.png") + " --stats --lod off --segment-budget 0");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  // independent counts: the hair mesh's strands x (control points - 1), the strand file's
  // points - strands (every stored segment at LOD off)
  std::ifstream in(assetPath("grooms/tiny.hairmesh.json"));
  const json tiny = json::parse(in);
  const std::uint64_t ts = tiny["strands"], tc = tiny["control_points"];
  const StrandGroom bob = loadStrandGroom(assetPath("grooms/head_bob.hair"), 1ull << 30);
  std::uint64_t bobPoints = 0;
  for (std::uint32_t c : bob.pointCounts) bobPoints += c;
  const std::uint64_t bs = bob.pointCounts.size(), bseg = bobPoints - bs;
  auto expectLine = [&](const std::string& re) {
    EXPECT_TRUE(std::regex_search(r.output, std::regex(re))) << re << "\n" << r.output;
  };
  expectLine("groom 0 \"tiny\": " + std::to_string(ts) + " strands, " +
             std::to_string(ts * (tc - 1)) + " segments");
  expectLine("groom 1 \"[^\"]*\": " + std::to_string(bs) + " strands, " + std::to_string(bseg) +
             " segments");
  expectLine("total: 2 of 2 grooms drawn, " + std::to_string(ts + bs) + " strands, " +
             std::to_string(ts * (tc - 1) + bseg) + " segments \\(no segment budget\\)");
}

// The default budget is a safety limit that grows with the pixel count (DESIGN.md, "LOD from
// the screen"): 64 segments per pixel, at least 2 M; a scene that gives a budget keeps it.
TEST(Budget, DefaultBudgetGrowsWithThePixels) {
  EXPECT_EQ(defaultSegmentBudget(960, 540), 33'177'600u);  // 64 x 518 400
  EXPECT_EQ(defaultSegmentBudget(160, 90), 2'000'000u);    // 0.92 M: the least
  EXPECT_EQ(defaultSegmentBudget(1920, 1080), 132'710'400u);
  EXPECT_EQ(defaultSegmentBudget(1280, 720), 58'982'400u);
  EXPECT_EQ(defaultSegmentBudget(200000, 200000), kMaxSegmentBudget);
  Renderer r(sharedDevice());
  Scene s = smallScene(tinyMesh(), 1, false);
  s.width = 1280;
  s.height = 720;
  EXPECT_EQ(r.render(s).stats.segmentBudget, 58'982'400u);
  s.width = 160;
  s.height = 90;
  EXPECT_EQ(r.render(s).stats.segmentBudget, 2'000'000u);  // 0.92 M: the least
  s.segmentBudget = 1000;                                  // the scene's own
  EXPECT_EQ(r.render(s).stats.segmentBudget, 1000u);
  RenderOptions o;
  o.segmentBudget = 0;  // the option's
  EXPECT_EQ(r.render(s, o).stats.segmentBudget, 0u);
  // from the scene file: absent, the default of the size; given, kept
  const std::string dir = scratchDir();
  json j = cliScene();
  writeJson(dir + "/scene.json", j);
  EXPECT_FALSE(loadScene(dir + "/scene.json").segmentBudget.has_value());
  j["segment_budget"] = 0;
  writeJson(dir + "/scene.json", j);
  EXPECT_EQ(loadScene(dir + "/scene.json").segmentBudget, std::optional<std::uint64_t>(0));
}

// LOD's λ grows with the image height above 540 lines: at 1920x1080 a groom keeps the
// strands it keeps at 960x540 with twice its λ, so a kept strand's gap spans the same pixels
// (the strands from L, Lipp Eq. 1: strands_per_pixel 0).
TEST(Budget, LodLambdaGrowsWithTheHeightAbove540) {
  EXPECT_FLOAT_EQ(lodResolutionScale(540), 1.0f);
  EXPECT_FLOAT_EQ(lodResolutionScale(90), 1.0f);
  EXPECT_FLOAT_EQ(lodResolutionScale(1080), 2.0f);
  StrandGroom g = *fringe(128, 5);
  g.lod.lambda = 0.5f;  // L well below 1: the strands kept follow λ
  Scene s = smallScene(tinyMesh(), 0, false);
  s.grooms.emplace_back("fringe", std::make_shared<const StrandGroom>(std::move(g)));
  Renderer r(sharedDevice());
  RenderOptions o;
  o.segmentBudget = 0;
  auto strandsAt = [&](int w, int h, float lambdaScale) {
    s.width = w;
    s.height = h;
    o.lodLambdaScale = lambdaScale;
    return r.render(s, o).stats.strandsDrawn;
  };
  const std::uint64_t at540 = strandsAt(960, 540, 1.0f), at540x2 = strandsAt(960, 540, 2.0f),
                      at1080 = strandsAt(1920, 1080, 1.0f);
  EXPECT_LT(at540, 64u);  // LOD reduces
  EXPECT_GE(at1080, at540 + at540 / 2);
  EXPECT_NEAR(static_cast<double>(at1080), static_cast<double>(at540x2), 2.0);  // ceil per chunk
}

TEST(Budget, BadBudgetsAndCapsAreOneErrorLine) {
  const std::string dir = scratchDir();
  const std::string out = dir + "/out.png";
  const std::vector<std::pair<std::string, json>> scene = {
      {"segment_budget", -1},  {"segment_budget", 1e300}, {"segment_budget", "NaN"},
      {"segment_budget", 2.5}, {"segment_budget", 5e9},   {"max_strands", -3},
      {"max_strands", 1e12}};
  for (const auto& [key, value] : scene) {
    json s = cliScene();
    s[key] = value;
    writeJson(dir + "/scene.json", s);
    const CommandResult r = runCli("render " + quote(dir + "/scene.json") + " -o " + quote(out));
    SCOPED_TRACE(key + " = " + value.dump() + ":\n" + r.output);
    EXPECT_NE(r.exitCode, 0);
    const std::string line = onlyErrorLine(r.output);
    EXPECT_NE(line.find(key), std::string::npos) << line;
    EXPECT_FALSE(std::filesystem::exists(out));
  }
  writeJson(dir + "/scene.json", cliScene());
  const std::vector<std::pair<std::string, std::string>> flags = {
      {"--segment-budget", "-5"},  {"--segment-budget", "nan"}, {"--segment-budget", "99999999999"},
      {"--segment-budget", "1e6"}, {"--budget-rule", "x"},      {"--budget-rule", "Screen"},
      {"--budget-rule", ""}};
  for (const auto& [flag, v] : flags) {
    const CommandResult r = runCli("render " + quote(dir + "/scene.json") + " -o " + quote(out) +
                                   " " + flag + " '" + v + "'");
    SCOPED_TRACE(flag + " " + v + ":\n" + r.output);
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(onlyErrorLine(r.output).find(flag), std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(out));
  }
  // the accepted spellings render
  for (const std::string v : {"screen", "uniform"}) {
    const CommandResult r = runCli("render " + quote(dir + "/scene.json") + " -o " + quote(out) +
                                   " --budget-rule " + v);
    EXPECT_EQ(r.exitCode, 0) << v << "\n" << r.output;
    EXPECT_TRUE(std::filesystem::exists(out)) << v;
    std::filesystem::remove(out);
  }
}

}  // namespace
}  // namespace clhair::test
