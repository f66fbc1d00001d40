// test_reference.cpp — the traced reference (Renderer::renderReference with
// ReferenceMethod::Embree, host/groom/strand_tracer.h): its per-pixel hair coverage against
// the analytic coverage of straight fronto-parallel strands, its G-buffer words against the
// strand pass's where both hit, its agreement with the raster reference on thick strands
// (and the one place the raster reference is known to be biased), and opaque occluders.
//
// Coverage is read from two renders over a black and a white background: with hair colour
// H and coverage c a pixel is c H + (1 - c) B, so c = 1 - (white - black) exactly,
// whatever the shading.
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "clhair/renderer.h"
#include "groom/presets.h"
#include "groom/strand_tracer.h"
#include "stages/view_math.h"
#include "synthetic_groom.h"
#include "test_util.h"

namespace clhair {
namespace {

constexpr int kSpp = 64;
// The largest error of the fraction of kSpp samples that fall in an interval of the pixel,
// against the interval's length, over all intervals: the extreme discrepancy of the
// reference's x offsets (the first 64 of the R2 sequence's x coordinate: 0.0652).
constexpr double kDiscrepancy64 = 0.066;
// Traced against raster reference of 2 px strands, 16 samples each: mean absolute
// difference of linear colour over the hair's pixels. Measured 0.0040 on PoCL; the traced
// reference at twice the width measures 0.0116 against the same raster reference.
constexpr double kThickTolerance = 0.006;

// One straight vertical strand at world x = x, from y = -0.2 to 0.2 in the plane z = 0, of
// world diameter `width`.
GroomInstance verticalStrand(const std::string& name, float x, float width) {
  StrandGroom g;
  g.name = name;
  g.pointCounts = {5};
  for (int k = 0; k < 5; ++k) g.points.push_back(glm::vec3(x, -0.2f + 0.1f * k, 0.0f));
  g.appearance.strandWidth = width;
  g.lod.enabled = false;
  return GroomInstance(name, std::make_shared<const StrandGroom>(std::move(g)));
}

Scene strandScene(int w, int h) {
  Scene s;
  s.width = w;
  s.height = h;
  s.camera.position = glm::vec3(0.0f, 0.0f, 1.0f);
  s.camera.target = glm::vec3(0.0f);
  s.camera.fovYDegrees = 3.0f;  // 16 px span 0.026 units at distance 1
  s.ambient = glm::vec3(0.6f);
  return s;
}

// Per-pixel coverage of the hair (mean over r, g, b) from references over black and white.
std::vector<double> coverage(Renderer& r, Scene s, int spp, ReferenceMethod m) {
  s.background = glm::vec3(0.0f);
  const Frame black = r.renderReference(s, spp, m);
  s.background = glm::vec3(1.0f);
  const Frame white = r.renderReference(s, spp, m);
  std::vector<double> c(black.depth.size());
  for (std::size_t i = 0; i < c.size(); ++i) {
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) sum += white.color.rgba[4 * i + k] - black.color.rgba[4 * i + k];
    c[i] = 1.0 - sum / 3.0;
  }
  return c;
}

// Screen x and width in pixels of a vertical strand at world x in strandScene's view.
void project(const Scene& s, float x, float width, double& centre, double& px) {
  const gpu::ClhViewGpu v = makeView(s.camera, s.width, s.height);
  const double z = 1.0;  // the strands lie at view depth 1
  centre = v.cx + v.fx * x / z;
  px = v.fx * width / z;
}

// The fraction of the reference's samples of pixel column i that lie within the band.
double sampledCoverage(int i, double centre, double px, int spp) {
  int in = 0;
  for (int k = 0; k < spp; ++k) {
    const double g = 1.32471795724474602596;
    const double jx = std::fmod(0.5 + k / g, 1.0) - 0.5;
    // the image plane moves by +jx: the ray of pixel centre i + 1/2 is unshifted i + 1/2 - jx
    in += std::fabs(i + 0.5 - jx - centre) < 0.5 * px;
  }
  return static_cast<double>(in) / spp;
}

TEST(TracedReference, CoverageOfStraightStrandsIsAnalytic) {
  Scene s = strandScene(48, 20);
  const gpu::ClhViewGpu v = makeView(s.camera, s.width, s.height);
  // widths 0.35, 1.0 and 2.6 px, centred off the pixel grid
  const float xs[3] = {static_cast<float>((10.3 - v.cx) / v.fx),
                       static_cast<float>((22.75 - v.cx) / v.fx),
                       static_cast<float>((35.5 - v.cx) / v.fx)};
  const float widths[3] = {static_cast<float>(0.35 / v.fx), static_cast<float>(1.0 / v.fx),
                           static_cast<float>(2.6 / v.fx)};
  for (int k = 0; k < 3; ++k)
    s.grooms.push_back(verticalStrand("s" + std::to_string(k), xs[k], widths[k]));
  Renderer r(test::sharedDevice());
  const std::vector<double> c = coverage(r, s, kSpp, ReferenceMethod::Embree);
  double worstAnalytic = 0.0, worstSampled = 0.0;
  int worstX = -1, worstY = -1;
  for (int y = 6; y < 14; ++y)  // rows well inside the strands
    for (int x = 0; x < s.width; ++x) {
      double expected = 0.0, sampled = 0.0;
      for (int k = 0; k < 3; ++k) {
        double centre, px;
        project(s, xs[k], widths[k], centre, px);
        // the band's overlap with the pixel [x, x + 1)
        expected += std::max(0.0, std::min(x + 1.0, centre + 0.5 * px) -
                                      std::max(static_cast<double>(x), centre - 0.5 * px));
        sampled += sampledCoverage(x, centre, px, kSpp);
      }
      const double got = c[static_cast<std::size_t>(y) * s.width + x];
      if (std::fabs(got - expected) > worstAnalytic) {
        worstAnalytic = std::fabs(got - expected);
        worstX = x;
        worstY = y;
      }
      worstSampled = std::max(worstSampled, std::fabs(got - sampled));
    }
  RecordProperty("worst_vs_analytic", std::to_string(worstAnalytic));
  RecordProperty("worst_vs_samples", std::to_string(worstSampled));
  EXPECT_LE(worstAnalytic, kDiscrepancy64) << "at pixel " << worstX << ", " << worstY;
  // against the fraction of the very samples taken: one may fall the other way exactly at
  // a band edge
  EXPECT_LE(worstSampled, 1.5 / kSpp);
}

// The raster reference draws no strand wider than CLH_MAX_HIT_DIAMETER (3 px, the strand
// pass's cap): a 5 px strand covers 5 px of a row in the traced reference, 3 in the raster
// one. This is where the raster reference is biased and the traced one is not.
TEST(TracedReference, WideStrandsKeepTheirWidthWhereTheRasterReferenceCapsThem) {
  Scene s = strandScene(24, 12);
  const gpu::ClhViewGpu v = makeView(s.camera, s.width, s.height);
  const float x = static_cast<float>((12.0 - v.cx) / v.fx), width = static_cast<float>(5.0 / v.fx);
  s.grooms.push_back(verticalStrand("wide", x, width));
  Renderer r(test::sharedDevice());
  auto rowSum = [&](const std::vector<double>& c) {
    double sum = 0.0;
    for (int y = 4; y < 8; ++y)
      for (int i = 0; i < s.width; ++i) sum += c[static_cast<std::size_t>(y) * s.width + i];
    return sum / 4.0;
  };
  const double traced = rowSum(coverage(r, s, 16, ReferenceMethod::Embree));
  const double raster = rowSum(coverage(r, s, 16, ReferenceMethod::Raster));
  RecordProperty("traced_px", std::to_string(traced));
  RecordProperty("raster_px", std::to_string(raster));
  EXPECT_NEAR(traced, 5.0, 0.1);
  EXPECT_NEAR(raster, CLH_MAX_HIT_DIAMETER, 0.1);
}

// Where the traced ray and the strand pass's centre sample both hit a strand they carry
// the same word. Where strands cross, the two may pick different ones (the tracer sees the
// fibre's near surface, the raster its centre line), so at least `uvShare` of the pixels
// hit by both must hold the same u, v (a wrong root uv or hash would match about 1 in 4096);
// where they do, w and AO agree within 2 codes and the tangents within 18 degrees in at
// least 95 % of them (the raster computes one word per pixel column, at its centre, so it
// differs on segments seen nearly end-on). `s` has one groom.
void expectSameWords(const Scene& s, double uvShare) {
  Renderer r(test::sharedDevice());
  RenderOptions o;
  o.lod = Toggle::Off;
  o.filter = Toggle::Off;
  o.trueWidth = true;
  o.captureGBuffer = true;
  const Frame f = r.render(s, o);
  ASSERT_EQ(s.grooms.size(), 1u);
  gpu::ClhGroomGpu params;
  ASSERT_EQ(f.rasterGroom.size(), sizeof(params));
  std::memcpy(&params, f.rasterGroom.data(), sizeof(params));
  const StrandSet set = s.grooms[0].mesh ? r.generateStrands(*s.grooms[0].mesh)
                                         : r.generateStrands(*s.grooms[0].strands);
  StrandTracer tracer;
  tracer.addGroom(0, set, params);
  tracer.commit();
  tracer.trace(makeView(s.camera, s.width, s.height), f.rasterDepth);
  std::vector<std::uint64_t> words;
  tracer.centreLayer(0, params, words);
  ASSERT_EQ(words.size(), f.rasterDepth.size());
  std::size_t both = 0, uvEqual = 0, wClose = 0, aoClose = 0, tangentClose = 0;
  for (std::size_t i = 0; i < words.size(); ++i) {
    const std::uint64_t a = f.gbuffer[i], b = words[i];
    if (a == ~std::uint64_t(0) || b == ~std::uint64_t(0)) continue;
    ++both;
    if (gpu::clh_gbuf_u(a) != gpu::clh_gbuf_u(b) || gpu::clh_gbuf_v(a) != gpu::clh_gbuf_v(b))
      continue;
    ++uvEqual;
    wClose +=
        std::abs(static_cast<int>(gpu::clh_gbuf_w(a)) - static_cast<int>(gpu::clh_gbuf_w(b))) <= 2;
    aoClose += std::abs(static_cast<int>(gpu::clh_gbuf_ao(a)) -
                        static_cast<int>(gpu::clh_gbuf_ao(b))) <= 2;
    float ta[3], tb[3];
    gpu::clh_oct_decode(gpu::clh_gbuf_oct(a), ta);
    gpu::clh_oct_decode(gpu::clh_gbuf_oct(b), tb);
    tangentClose += ta[0] * tb[0] + ta[1] * tb[1] + ta[2] * tb[2] > 0.95f;
  }
  std::printf(
      "pixels hit by both %zu, same u, v %zu; of those w within 2 codes %zu, AO %zu, "
      "tangent %zu\n",
      both, uvEqual, wClose, aoClose, tangentClose);
  ::testing::Test::RecordProperty("both_hit", std::to_string(both));
  ::testing::Test::RecordProperty("same_uv", std::to_string(uvEqual));
  ASSERT_GT(both, 200u);
  EXPECT_GE(uvEqual, uvShare * both);
  EXPECT_GE(wClose, 0.95 * uvEqual);
  EXPECT_GE(aoClose, 0.95 * uvEqual);
  EXPECT_GE(tangentClose, 0.95 * uvEqual);
}

// A hair mesh framed close at 128x96, strands about 2 px wide, its AO baked.
Scene thickHairMeshScene(std::int64_t strands) {
  HairMesh m = makeGroomPreset("long_wavy");
  m.strandCount = strands;
  m.lod.enabled = false;
  Scene s;
  s.width = 128;
  s.height = 96;
  s.ambient = glm::vec3(0.5f);
  Light l;
  l.direction = glm::normalize(glm::vec3(0.3f, 1.0f, 0.6f));
  l.intensity = 2.0f;
  s.lights.push_back(l);
  s.grooms.push_back({"wavy", std::make_shared<const HairMesh>(m), glm::mat4(1.0f)});
  s.camera = framePreset(s, CameraPreset::Close, 30.0f, 15.0f);
  const gpu::ClhViewGpu v = makeView(s.camera, s.width, s.height);
  const float z = glm::length(s.camera.position - s.camera.target);
  m.appearance.strandWidth = 2.0f * z / v.fy;
  Renderer r(test::sharedDevice());
  m.ao = r.bakeAmbientOcclusion(m);
  s.grooms[0].mesh = std::make_shared<const HairMesh>(std::move(m));
  return s;
}

TEST(TracedReference, WordsMatchTheStrandPassOnAHairMesh) {
  Scene s = thickHairMeshScene(100);
  expectSameWords(s, 0.5);
}

TEST(TracedReference, WordsMatchTheStrandPassOnStoredStrandsWithFileColour) {
  StrandGroom g = test::syntheticGroom(40);
  g.lod.enabled = false;
  g.appearance.useFileColor = true;  // per-strand colours in the words' u, v and AO fields
  for (std::size_t st = 0, at = 0; st < g.pointCounts.size(); at += g.pointCounts[st++])
    for (std::uint32_t k = 0; k < g.pointCounts[st]; ++k)
      g.colors.push_back(glm::vec3(0.05f + 0.002f * (st % 100), 0.3f, 0.6f - 0.001f * (st % 300)));
  Scene s;
  s.width = 128;
  s.height = 96;
  s.grooms.push_back({"synthetic", std::make_shared<const StrandGroom>(g), glm::mat4(1.0f)});
  s.camera = framePreset(s, CameraPreset::Close, 30.0f, 15.0f);
  const gpu::ClhViewGpu v = makeView(s.camera, s.width, s.height);
  g.appearance.strandWidth = 2.0f * glm::length(s.camera.position - s.camera.target) / v.fy;
  s.grooms[0].strands = std::make_shared<const StrandGroom>(g);
  expectSameWords(s, 0.5);
}

// Mean absolute difference of linear colour (r, g, b) over the pixels where `a` or `b`
// differs from `bare` (the scene without hair).
double hairMeanAbsDiff(const Frame& a, const Frame& b, const Frame& bare) {
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.depth.size(); ++i) {
    bool hair = false;
    for (int k = 0; k < 3; ++k)
      hair |= std::fabs(a.color.rgba[4 * i + k] - bare.color.rgba[4 * i + k]) > 1e-4f ||
              std::fabs(b.color.rgba[4 * i + k] - bare.color.rgba[4 * i + k]) > 1e-4f;
    if (!hair) continue;
    ++n;
    for (int k = 0; k < 3; ++k) sum += std::fabs(a.color.rgba[4 * i + k] - b.color.rgba[4 * i + k]);
  }
  return n ? sum / (3.0 * n) : 0.0;
}

// Strands of about 2 px, where both references are exact (the same centre samples, the
// same width, under the raster's cap): over the hair's pixels the images agree to
// kThickTolerance; the traced one at twice the width does not.
TEST(TracedReference, AgreesWithTheRasterReferenceOnThickStrands) {
  Scene s = thickHairMeshScene(1500);
  Renderer r(test::sharedDevice());
  Scene bare = s;
  bare.grooms.clear();
  const Frame none = r.render(bare);
  const Frame traced = r.renderReference(s, 16, ReferenceMethod::Embree);
  const Frame raster = r.renderReference(s, 16, ReferenceMethod::Raster);
  Scene wide = s;
  HairMesh m = *s.grooms[0].mesh;
  m.appearance.strandWidth *= 2.0f;
  wide.grooms[0].mesh = std::make_shared<const HairMesh>(std::move(m));
  const Frame tracedWide = r.renderReference(wide, 16, ReferenceMethod::Embree);
  const double agree = hairMeanAbsDiff(traced, raster, none);
  const double doubled = hairMeanAbsDiff(tracedWide, raster, none);
  RecordProperty("mean_abs_diff", std::to_string(agree));
  RecordProperty("mean_abs_diff_doubled_width", std::to_string(doubled));
  std::printf(
      "traced vs raster reference over the hair: mean |diff| %.5f; traced at twice the "
      "width: %.5f\n",
      agree, doubled);
  EXPECT_LT(agree, kThickTolerance);
  EXPECT_GT(doubled, kThickTolerance);
}

// A strand behind an opaque sphere is absent from the traced reference; one in front of
// it is drawn.
TEST(TracedReference, OpaqueSphereHidesTheStrandBehindIt) {
  Scene s = strandScene(32, 32);
  s.background = glm::vec3(0.8f);
  Sphere ball;
  ball.center = glm::vec3(0.0f, 0.0f, 0.0f);
  ball.radius = 0.01f;  // fills the middle of the frame
  ball.color = glm::vec3(0.8f, 0.1f, 0.1f);
  s.spheres.push_back(ball);
  const gpu::ClhViewGpu v = makeView(s.camera, s.width, s.height);
  const float width = static_cast<float>(2.0 / v.fx);
  Scene behind = s, front = s;
  GroomInstance b = verticalStrand("behind", 0.0f, width), f = verticalStrand("front", 0.0f, width);
  b.transform = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, -0.05f));
  f.transform = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 0.05f));
  behind.grooms.push_back(b);
  front.grooms.push_back(f);
  Renderer r(test::sharedDevice());
  const Frame none = r.renderReference(s, 4, ReferenceMethod::Embree);
  const Frame hidden = r.renderReference(behind, 4, ReferenceMethod::Embree);
  const Frame shown = r.renderReference(front, 4, ReferenceMethod::Embree);
  const int cx = s.width / 2, cy = s.height / 2;
  for (int y = cy - 3; y <= cy + 3; ++y)
    for (int x = cx - 3; x <= cx + 3; ++x)
      for (int k = 0; k < 3; ++k)
        ASSERT_EQ(hidden.color.pixel(x, y)[k], none.color.pixel(x, y)[k]) << x << ", " << y;
  EXPECT_GT(std::fabs(shown.color.pixel(cx, cy)[1] - none.color.pixel(cx, cy)[1]), 0.05f)
      << "the strand in front of the sphere is drawn";
  // and outside the sphere the strand behind it shows
  EXPECT_GT(std::fabs(hidden.color.pixel(cx, 1)[1] - none.color.pixel(cx, 1)[1]), 0.05f);
}

}  // namespace
}  // namespace clhair
