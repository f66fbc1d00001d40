// test_link_frames.cpp — strand identities and hair linking in rendered frames (Huang et al.
// 2025; kernels/link.cl): the identity layer leaves the centre layer word for word as it was
// and carries the centre word's depth; its strands are the groom's (two known strands give
// two ids, read back from the CLI's EXR with OpenImageIO); linking of a sub-pixel strand file
// keeps the hair's total coverage; the default filter is Huang's in one view and Lipp's when
// named; for a hair mesh the regenerated centre lines of the source strands run through their
// drawn pixels. The synthetic G-buffer tests of the link kernels are in test_link.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "cl/device_impl.h"
#include "clhair/gpu_types.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "io/cyhair.h"
#include "stages/link_stage.h"
#include "test_util.h"

namespace clhair {

using namespace gpu;

namespace {

constexpr clh_u64 kEmpty = CLH_GBUF_EMPTY;

// Two straight strands: 0 vertical on the left, 1 slanted on the right, root at the bottom.
Scene twoStrands(float width) {
  StrandGroom g;
  g.name = "two";
  g.appearance.strandWidth = width;
  for (int s = 0; s < 2; ++s) {
    g.pointCounts.push_back(9);
    for (int k = 0; k < 9; ++k)
      g.points.emplace_back(-0.03f + 0.06f * s + 0.004f * s * k, -0.05f + 0.0125f * k, 0.0f);
  }
  Scene sc;
  sc.width = 48;
  sc.height = 40;
  sc.camera.position = glm::vec3(0.0f, 0.0f, 0.3f);
  sc.camera.target = glm::vec3(0.0f);
  sc.camera.fovYDegrees = 35.0f;
  Light l;
  l.direction = glm::normalize(glm::vec3(0.3f, 1.0f, 0.6f));
  sc.lights.push_back(l);
  sc.grooms.push_back(GroomInstance("two", std::make_shared<const StrandGroom>(std::move(g))));
  return sc;
}

}  // namespace

TEST(StrandId, IdentityLayerLeavesTheCentreLayerAndNamesItsStrands) {
  Renderer r(test::sharedDevice());
  for (const bool mesh : {false, true}) {
    SCOPED_TRACE(mesh ? "hair mesh" : "strand file");
    Scene s = twoStrands(0.004f);
    std::uint32_t total = 2;
    if (mesh) {
      auto m = std::make_shared<const HairMesh>(
          loadHairMesh(test::assetPath("grooms/tiny.hairmesh.json")));
      total = static_cast<std::uint32_t>(m->strandCount);
      s.grooms[0] = GroomInstance("tiny", m);
      s.camera.position = glm::vec3(0.0f, 0.03f, 0.2f);
      s.camera.target = glm::vec3(0.0f, 0.025f, 0.0f);
    }
    RenderOptions o;
    o.filter = Toggle::Off;
    o.captureGBuffer = true;
    const Frame plain = r.render(s, o);
    o.aovs = true;
    o.strandIds = true;
    const Frame ided = r.render(s, o);
    ASSERT_EQ(plain.gbufferLayers, 2);
    ASSERT_EQ(ided.gbufferLayers, int(CLH_LAYER_ID) + 1);
    const std::size_t pixels = std::size_t(s.width) * s.height;
    std::size_t hits = 0;
    std::set<std::uint32_t> strands;
    for (std::size_t p = 0; p < pixels; ++p) {
      ASSERT_EQ(ided.gbuffer[p], plain.gbuffer[p]) << "centre word changed at " << p;
      ASSERT_EQ(ided.gbuffer[pixels + p], plain.gbuffer[pixels + p]) << "conservative at " << p;
      const std::uint64_t id = ided.gbuffer[CLH_LAYER_ID * pixels + p];
      ASSERT_EQ(id == kEmpty, plain.gbuffer[p] == kEmpty) << p;
      if (id == kEmpty) {
        EXPECT_EQ(ided.aovs.strand[p * 3 + 1], -1.0f);
        continue;
      }
      ++hits;
      EXPECT_EQ(clh_gbuf_depth(ided.gbuffer[p]), clh_gbuf_depth(id)) << p;
      EXPECT_EQ(clh_id_linked(id), 0u);
      strands.insert(clh_id_strand(id));
      EXPECT_EQ(ided.aovs.strand[p * 3 + 1], float(clh_id_strand(id)));
      EXPECT_EQ(ided.aovs.strand[p * 3], 0.0f);
    }
    EXPECT_GT(hits, 10u);
    if (!mesh) {
      EXPECT_EQ(strands, (std::set<std::uint32_t>{0u, 1u}));
    } else {
      EXPECT_GT(strands.size(), 10u);
      EXPECT_LT(*strands.rbegin(), total);
    }
  }
}

TEST(Link, RenderedSubPixelStrandIsLinkedWithItsCoverageKept) {
  // strand 1 of twoStrands at a fifth of a pixel's width hits a pixel centre every few rows
  Renderer r(test::sharedDevice());
  const Scene s = twoStrands(0.001f);
  FilterParams f;
  f.method = FilterParams::Method::Huang;
  f.aniso = false;
  Scene linked = s, unlinked = s;
  linked.filter = f;
  f.link = false;
  f.alphaFix = false;
  unlinked.filter = f;
  RenderOptions o;
  o.aovs = true;
  o.trueWidth = true;  // the strand at its width, not widened as a faint groom (faint_groom.h)
  const Frame a = r.render(linked, o), b = r.render(unlinked, o);
  EXPECT_GT(a.stats.linkedPixels, 5u);
  EXPECT_EQ(b.stats.linkedPixels, 0u);
  double coverageA = 0.0, coverageB = 0.0;
  std::size_t pixelsA = 0, pixelsB = 0;
  for (std::size_t p = 0; p < a.aovs.hairAlpha.size(); ++p) {
    coverageA += a.aovs.hairAlpha[p];
    coverageB += b.aovs.hairAlpha[p];
    pixelsA += a.aovs.hairAlpha[p] > 0.0f;
    pixelsB += b.aovs.hairAlpha[p] > 0.0f;
  }
  EXPECT_GT(pixelsB, 3u);
  EXPECT_GT(pixelsA, pixelsB + 5) << "linking filled nothing";
  EXPECT_NEAR(coverageA, coverageB, 0.01 * coverageB) << "the alpha fix did not keep coverage";
}

TEST(Link, DefaultFilterIsHuangsInAFrameOfOneViewAndLippsWhenNamed) {
  // DESIGN.md, "The default filter": "auto" is Huang's filter in a frame of one view at
  // MSAA 1 with the lines raster (a strand file here: its curve pass reads the strand);
  // Lipp's when the scene or the option names it
  Renderer r(test::sharedDevice());
  const Scene s = twoStrands(0.001f);
  EXPECT_EQ(s.filter.method, FilterParams::Method::Auto);
  Scene huang = s, lipp = s;
  huang.filter.method = FilterParams::Method::Huang;
  lipp.filter.method = FilterParams::Method::Lipp;
  RenderOptions o;
  o.trueWidth = true;  // the strand at its width, not widened as a faint groom (faint_groom.h)
  const Frame byDefault = r.render(s, o), named = r.render(huang, o), lipps = r.render(lipp, o);
  EXPECT_GT(byDefault.stats.linkSelecting, 0u);
  EXPECT_GT(byDefault.stats.linkedPixels, 5u);
  EXPECT_EQ(byDefault.color.rgba, named.color.rgba) << "the default is not Huang's filter";
  EXPECT_EQ(lipps.stats.linkSelecting, 0u);
  EXPECT_NE(byDefault.color.rgba, lipps.color.rgba);
  RenderOptions lippOption = o;  // --filter lipp over the scene's "auto"
  lippOption.filterMethod = FilterParams::Method::Lipp;
  EXPECT_EQ(r.render(s, lippOption).color.rgba, lipps.color.rgba);
  // a crowd: "auto" stays Huang's however many groom instances (each one's linking runs over
  // its screen box); by name Lipp's stays Lipp's
  Scene five = s, fiveLipp = lipp;
  five.grooms.assign(5, s.grooms[0]);
  fiveLipp.grooms.assign(5, s.grooms[0]);
  EXPECT_GT(r.render(five, o).stats.linkSelecting, 0u);
  EXPECT_EQ(r.render(fiveLipp, o).stats.linkSelecting, 0u);
  // MSAA 4 and the coverage raster (no filter): Views.EachViewIsTheSingleViewRenderAtMsaa4
  // and Coverage.FrontoParallelStrandHasTheStripsCoverageAndAlphaProfile, in frames those
  // tests render anyway
}

TEST(Link, SourceStrandsCentreLinesRunThroughTheirDrawnPixels) {
  // the curve pass regenerates (hair mesh) or reads (strand file) the source strands from
  // their identity: their centre lines must be those strands
  Renderer r(test::sharedDevice());
  for (const bool mesh : {true, false}) {
    SCOPED_TRACE(mesh ? "hair mesh" : "strand file");
    Scene s = twoStrands(0.001f);
    if (mesh) {
      s.grooms[0] = GroomInstance("tiny", std::make_shared<const HairMesh>(loadHairMesh(
                                              test::assetPath("grooms/tiny.hairmesh.json"))));
      s.camera.position = glm::vec3(0.0f, 0.03f, 0.25f);
      s.camera.target = glm::vec3(0.0f, 0.025f, 0.0f);
      s.width = 96;
      s.height = 72;
    }
    s.filter.method = FilterParams::Method::Huang;
    s.filter.aniso = false;
    RenderOptions o;
    o.filter = Toggle::On;
    o.lod = Toggle::Off;
    o.captureGBuffer = true;
    o.trueWidth = true;  // not widened as a faint groom (faint_groom.h): linking has gaps
    const Frame f = r.render(s, o);
    ASSERT_EQ(f.gbufferLayers, int(CLH_LAYER_LINKED) + 1);
    EXPECT_GT(f.stats.linkedPixels, 0u);
    const int w = s.width, h = s.height;
    const std::size_t plane = std::size_t(w) * h;
    std::set<std::uint32_t> sources;
    for (std::size_t p = 0; p < plane; ++p) {
      const std::uint64_t c = f.gbuffer[CLH_LAYER_CURVE_ID * plane + p];
      if (c != kEmpty) sources.insert(clh_id_strand(c));
    }
    ASSERT_FALSE(sources.empty());
    // where a source strand's centre line crosses a pixel it drew, both words name it at
    // the same place along it: the line is that strand, regenerated or read
    std::size_t same = 0, agree = 0;
    for (std::size_t p = 0; p < plane; ++p) {
      const std::uint64_t id = f.gbuffer[CLH_LAYER_ID * plane + p];
      const std::uint64_t c = f.gbuffer[CLH_LAYER_CURVE_ID * plane + p];
      if (id == kEmpty || c == kEmpty || clh_id_linked(id) || clh_id_strand(c) != clh_id_strand(id))
        continue;
      ++same;
      agree += std::abs(int(clh_id_pos(c)) - int(clh_id_pos(id))) <= 330;  // 1 % of its length
    }
    EXPECT_GE(same, 5u);
    EXPECT_EQ(agree, same);
    // and the linked pixels lie on their strand's line
    std::size_t linked = 0;
    for (std::size_t p = 0; p < plane; ++p) {
      const std::uint64_t id = f.gbuffer[CLH_LAYER_ID * plane + p];
      if (id == kEmpty || !clh_id_linked(id)) continue;
      ++linked;
      EXPECT_EQ(clh_id_strand(f.gbuffer[CLH_LAYER_CURVE_ID * plane + p]), clh_id_strand(id));
    }
    EXPECT_EQ(linked, f.stats.linkedPixels);
  }
}

TEST(StrandId, CliWritesTwoKnownStrandsAsTwoIdsWithUFromRootToTip) {
  const std::string dir = test::scratchDir();
  const Scene still = twoStrands(0.004f);
  CyHair hair;
  for (std::uint32_t n : still.grooms[0].strands->pointCounts) hair.segments.push_back(n - 1);
  for (const glm::vec3& q : still.grooms[0].strands->points)
    hair.points.insert(hair.points.end(), {q.x, q.y, q.z});
  writeCyHair(hair, dir + "/two.hair");
  const nlohmann::json scene = {
      {"resolution", {48, 40}},
      {"camera", {{"position", {0.0, 0.0, 0.3}}, {"target", {0.0, 0.0, 0.0}}, {"fov", 35}}},
      {"lights", {{{"type", "directional"}, {"direction", {0.3, 1.0, 0.6}}}}},
      {"grooms", {{{"strands_file", "two.hair"}, {"appearance", {{"strand_width", 0.004}}}}}}};
  std::ofstream(dir + "/scene.json") << scene.dump(2);
  const test::CommandResult run =
      test::runCli("render " + test::quote(dir + "/scene.json") + " -q --aov strand -o " +
                   test::quote(dir + "/s.exr"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  auto in = OIIO::ImageInput::open(dir + "/s.exr");
  ASSERT_TRUE(in) << OIIO::geterror();
  const OIIO::ImageSpec spec = in->spec();
  ASSERT_EQ(spec.width, 48);
  std::map<std::string, int> channel;
  for (int c = 0; c < spec.nchannels; ++c) channel[spec.channelnames[c]] = c;
  for (const char* name : {"strand.groom", "strand.id", "strand.u"}) {
    ASSERT_EQ(channel.count(name), 1u) << name;
    EXPECT_EQ(spec.channelformat(channel[name]), OIIO::TypeDesc::FLOAT) << name;
  }
  std::vector<float> px(std::size_t(spec.width) * spec.height * spec.nchannels);
  ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
  auto value = [&](int x, int y, const char* name) {
    return px[(std::size_t(y) * spec.width + x) * spec.nchannels + channel[name]];
  };
  std::map<int, int> count;
  std::map<int, std::pair<float, float>> lowUpper;  // per id: u at its lowest and highest row
  for (int y = 0; y < spec.height; ++y)
    for (int x = 0; x < spec.width; ++x) {
      const float id = value(x, y, "strand.id");
      ASSERT_TRUE(id == -1.0f || id == 0.0f || id == 1.0f) << id;
      if (id < 0.0f) {
        EXPECT_EQ(value(x, y, "strand.groom"), -1.0f);
        continue;
      }
      ++count[int(id)];
      EXPECT_EQ(value(x, y, "strand.groom"), 0.0f);
      EXPECT_EQ(x < 24, id == 0.0f) << "strand 0 is the left one, at " << x << "," << y;
      const float u = value(x, y, "strand.u");
      if (!lowUpper.count(int(id))) lowUpper[int(id)] = {u, u};
      lowUpper[int(id)].second = u;  // rows run top to bottom: the last is the lowest
    }
  EXPECT_GT(count[0], 10);
  EXPECT_GT(count[1], 10);
  for (const auto& [id, u] : lowUpper) EXPECT_GT(u.first, u.second + 0.5f) << "tip above root";
}

}  // namespace clhair
