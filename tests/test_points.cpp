// test_points.cpp — shading once per visible strand point (DESIGN.md, "Shading once per
// visible strand point"): a straight strand at MSAA 4 resolves to the per-sample shaded
// colour within 1 % where the shading is smooth along its segments, and within the range
// its segment's colour spans where a sharp highlight lies inside one; the marked points
// are exactly the points of the segments that own a visible sample (against the identity
// layers read back, and against all points of unoccluded strands); every pass binds only
// what it declared.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "cl/device_impl.h"
#include "clhair/gpu_types.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "groom/presets.h"
#include "synthetic_groom.h"
#include "test_util.h"

namespace clhair::test {
namespace {

// The graph's declaration checks on for the shared device while alive.
struct GraphChecks {
  bool before;
  GraphChecks() : before(sharedDevice().impl()->graphChecks) {
    sharedDevice().impl()->graphChecks = true;
  }
  ~GraphChecks() { sharedDevice().impl()->graphChecks = before; }
};

constexpr int kW = 96, kH = 16;

// One straight strand of `points` points from x = -2.5 to 2.5 (about 75 pixels), 3 pixels
// wide, seen through a long lens from z = 20 on a black background, its colour blended from
// `root` to `tip`, lit by `light` only. (The per-sample path rebuilds a sample's
// position at its pixel's centre: through a wide lens the view direction would turn across
// the strand's 3 pixels and shade its rows differently, which the strand's centre line,
// where its points are shaded, does not see. Real fibres are far thinner than a pixel.)
Scene straightStrand(int points, const Light& light, float betaM, glm::vec3 root, glm::vec3 tip) {
  StrandGroom g;
  g.name = "straight";
  g.pointCounts = {static_cast<std::uint32_t>(points)};
  for (int k = 0; k < points; ++k)
    g.points.emplace_back(-2.5f + 5.0f * k / (points - 1), 0.0f, 0.0f);
  g.appearance.useMelanin = false;
  g.appearance.rootColor = root;
  g.appearance.tipColor = tip;
  g.appearance.variation = 0.0f;
  g.appearance.betaM = betaM;
  g.appearance.strandWidth = 0.2f;  // 3 pixels at z = 2
  g.lod.enabled = false;
  Scene s;
  s.width = kW;
  s.height = kH;
  s.background = glm::vec3(0.0f);
  s.ambient = glm::vec3(0.0f);
  s.lights = {light};
  s.camera.position = glm::vec3(0.0f, 0.0f, 20.0f);
  s.camera.target = glm::vec3(0.0f);
  s.camera.fovYDegrees = 3.0f;  // 15 px per unit at z = 20
  s.grooms.emplace_back("straight", std::make_shared<const StrandGroom>(std::move(g)));
  return s;
}

Frame render4(const Scene& s, Toggle points) {
  GraphChecks checks;
  Renderer r(sharedDevice());
  RenderOptions o;
  o.msaa = 4;
  o.pointShading = points;
  return r.render(s, o);
}

float lum(const Frame& f, std::size_t i) {
  return 0.2126f * f.color.rgba[4 * i] + 0.7152f * f.color.rgba[4 * i + 1] +
         0.0722f * f.color.rgba[4 * i + 2];
}

TEST(PointShading, StraightStrandMatchesPerSampleShadingWhereShadingIsSmooth) {
  // a point light beyond the root, in the strand's plane of view: its distance (the
  // falloff changes 2.2x root to tip) and direction change smoothly along the strand, and
  // across it only to second order (the per-sample path shades each sample at its pixel's
  // centre, up to half a pixel off the strand's centre line where the points lie); one
  // colour root to tip (the per-sample words carry w in 6 bits, whose steps a steep colour
  // gradient would show and the interpolated points would not)
  Light l;
  l.type = Light::Type::Point;
  l.position = glm::vec3(-8.0f, 0.0f, 6.0f);
  l.intensity = 60.0f;
  const Scene s = straightStrand(41, l, 0.3f, glm::vec3(0.3f, 0.2f, 0.1f),
                                 glm::vec3(0.3f, 0.2f, 0.1f));  // 40 segments of 2 pixels
  const Frame perSample = render4(s, Toggle::Off), perPoint = render4(s, Toggle::On);
  EXPECT_EQ(perSample.stats.pointsShaded, 0u);
  EXPECT_EQ(perPoint.stats.pointsShaded, 41u) << "every point of the strand owns a sample";
  std::size_t hair = 0;
  double worst = 0.0;
  for (std::size_t i = 0; i < perSample.depth.size(); ++i) {
    const bool a = std::isfinite(perSample.depth[i]), b = std::isfinite(perPoint.depth[i]);
    EXPECT_EQ(a, b) << "pixel " << i << ": the two frames cover different pixels";
    for (int c = 0; c < 3; ++c) {
      const float want = perSample.color.rgba[4 * i + c], got = perPoint.color.rgba[4 * i + c];
      if (want > 1e-4f) hair += c == 0;
      const double rel = std::fabs(got - want) / std::max(want, 1e-3f);
      worst = std::max(worst, rel);
      EXPECT_LE(std::fabs(got - want), 0.01f * want + 1e-5f)
          << "pixel (" << i % kW << ", " << i / kW << ") channel " << c;
    }
  }
  RecordProperty("worst_relative_difference", std::to_string(worst));
  EXPECT_GT(hair, 150u) << "the strand should cover about 75 x 3 pixels";
}

// A highlight that peaks inside a 37-pixel segment: interpolating the segment's two point
// colours misses it, so the resolved colour differs from the per-sample one there, but by
// no more than the interpolation error of the segment can be: the range of the colours the
// per-sample frame shows along that segment.
TEST(PointShading, SharpHighlightInsideASegmentIsBoundedByTheSegmentsRange) {
  Light l;
  l.type = Light::Type::Point;
  l.position = glm::vec3(1.2f, 0.0f, 1.0f);  // the R lobe peaks near x = 1.2, inside segment 1
  l.intensity = 8.0f;
  const Scene s = straightStrand(3, l, 0.1f, glm::vec3(0.05f), glm::vec3(0.6f, 0.3f, 0.1f));
  const Frame perSample = render4(s, Toggle::Off), perPoint = render4(s, Toggle::On);
  EXPECT_EQ(perPoint.stats.pointsShaded, 3u);
  // the columns of each segment: x < 0 (segment 0) and x >= 0 (segment 1), the point x = 0
  // at the image's middle column
  float lo[2] = {1e30f, 1e30f}, hi[2] = {-1e30f, -1e30f};
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * kW + x;
      if (!std::isfinite(perSample.depth[i])) continue;
      const int seg = x < kW / 2 ? 0 : 1;
      lo[seg] = std::min(lo[seg], lum(perSample, i));
      hi[seg] = std::max(hi[seg], lum(perSample, i));
    }
  double worst = 0.0, peak = 0.0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * kW + x;
      if (!std::isfinite(perSample.depth[i])) continue;
      const int seg = x < kW / 2 ? 0 : 1;
      const double err = std::fabs(lum(perPoint, i) - lum(perSample, i));
      worst = std::max(worst, err);
      peak = std::max(peak, static_cast<double>(lum(perSample, i)));
      EXPECT_LE(err, hi[seg] - lo[seg] + 1e-5f) << "pixel (" << x << ", " << y << ")";
    }
  RecordProperty("worst_error", std::to_string(worst));
  RecordProperty("peak", std::to_string(peak));
  // the case is a real one: the highlight is missed by more than 1 % of its peak
  EXPECT_GT(worst, 0.01 * peak);
}

// The points a CPU reference finds from the identity layers the strand pass left (both
// points of every sample's segment) are exactly the points the device marked and shaded.
std::size_t cpuMarkedPoints(const Frame& f, int msaa, std::size_t pixels) {
  using gpu::clh_u32;  // the layout macros of gpu_types.h name its types
  using gpu::clh_u64;
  std::set<std::uint32_t> marked;
  EXPECT_GE(f.gbufferLayers, 2 * msaa + 1);
  for (int s = 0; s < msaa; ++s)
    for (std::size_t i = 0; i < pixels; ++i) {
      const std::uint64_t id =
          f.gbuffer[static_cast<std::size_t>(CLH_LAYER_POINT_ID(msaa) + s) * pixels + i];
      if (id == CLH_GBUF_EMPTY) continue;
      const std::uint32_t p = gpu::clh_pt_point(id);
      marked.insert(p);
      marked.insert(p + 1);
    }
  return marked.size();
}

void expectMarkedPointsMatch(const Scene& s, int msaa) {
  GraphChecks checks;
  Renderer r(sharedDevice());
  RenderOptions o;
  o.msaa = msaa;
  o.pointShading = Toggle::On;
  o.captureGBuffer = true;
  const Frame f = r.render(s, o);
  const std::size_t pixels = static_cast<std::size_t>(s.width) * s.height;
  const std::size_t expected = cpuMarkedPoints(f, msaa, pixels);
  ::testing::Test::RecordProperty("marked_points", std::to_string(expected));
  EXPECT_GT(expected, 20u);
  EXPECT_EQ(f.stats.pointsShaded, expected);
}

// Strands of a file, half of them behind an opaque sphere, at MSAA 4 and 8.
Scene occludedStrands() {
  StrandGroom g = syntheticGroom(60);
  g.lod.enabled = false;
  Scene s;
  s.width = 80;
  s.height = 60;
  s.grooms.push_back({"synthetic", std::make_shared<const StrandGroom>(g), glm::mat4(1.0f)});
  s.camera = framePreset(s, CameraPreset::Close, 30.0f, 15.0f);
  Sphere ball;
  ball.center = glm::vec3(0.05f, 0.15f, 0.0f) + 0.5f * (s.camera.position - s.camera.target);
  ball.radius = 0.04f;
  s.spheres.push_back(ball);
  return s;
}

TEST(PointShading, MarkedPointsAreThePointsOfSegmentsWithAVisibleSample) {
  expectMarkedPointsMatch(occludedStrands(), 4);
  expectMarkedPointsMatch(occludedStrands(), 8);
  // a hair mesh (its point space: CLH_MAX_CONTROL_POINTS per strand)
  HairMesh m = makeGroomPreset("tiny");
  m.strandCount = 300;
  Scene s;
  s.width = 64;
  s.height = 48;
  s.grooms.emplace_back("tiny", std::make_shared<const HairMesh>(m));
  s.camera = framePreset(s, CameraPreset::Close, 30.0f, 15.0f);
  expectMarkedPointsMatch(s, 4);
}

// Unoccluded strands seen whole: every segment owns a sample, so every point is marked.
TEST(PointShading, EveryPointOfUnoccludedStrandsIsMarked) {
  StrandGroom g;
  for (int st = 0; st < 5; ++st) {
    g.pointCounts.push_back(9 + st);
    for (std::uint32_t k = 0; k < g.pointCounts.back(); ++k)
      g.points.emplace_back(-2.0f + 4.0f * k / (g.pointCounts.back() - 1), -1.2f + 0.6f * st,
                            0.1f * st);
  }
  g.appearance.strandWidth = 0.12f;
  g.lod.enabled = false;
  std::uint64_t total = 0;
  for (std::uint32_t n : g.pointCounts) total += n;
  Scene s;
  s.width = 64;
  s.height = 48;
  s.camera.position = glm::vec3(0.0f, 0.0f, 4.0f);
  s.camera.fovYDegrees = 60.0f;
  s.grooms.emplace_back("lines", std::make_shared<const StrandGroom>(std::move(g)));
  GraphChecks checks;
  Renderer r(sharedDevice());
  RenderOptions o;
  o.msaa = 4;
  o.pointShading = Toggle::On;
  EXPECT_EQ(r.render(s, o).stats.pointsShaded, total);
}

}  // namespace
}  // namespace clhair::test
