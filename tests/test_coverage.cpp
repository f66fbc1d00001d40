// test_coverage.cpp — the coverage raster mode (clhair/coverage.h; the raster in
// raster_core.h, the shading rule in shade.cl):
//  - a segment's per-pixel coverages (host and device) sum to its trapezoid's area;
//  - each pixel's coverage on the device against a supersampled point-in-trapezoid count;
//  - the raster writes each pixel's coverage x 1024 into the coverage plane and nothing
//    where the scene depth is nearer;
//  - the three layers hold the three smallest words whatever the write order (random
//    orders on the device against a sort);
//  - the alpha curve reproduces from its simulation (tests/coverage_sim.h) and stays
//    within its stated error;
//  - renders: a fronto-parallel strand's coverage and alpha profile, and a dense slab of
//    strands reaching alpha 1;
//  - the CLI: --raster coverage renders, an unknown --raster or scene "raster" value is one
//    error line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <memory>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "cl/device_impl.h"
#include "clhair/coverage.h"
#include "clhair/renderer.h"
#include "clhair/strand_groom.h"
#include "coverage_sim.h"
#include "test_util.h"

namespace clhair::test {
namespace {

using gpu::clh_poly8;
using gpu::clh_u64;

struct Trap {
  float ax, ay, bx, by, wa, wb;
  double area() const {
    return 0.5 * (double(wa) + double(wb)) * std::hypot(double(bx) - ax, double(by) - ay);
  }
};

// Segments of several orientations, lengths and widths (sub-pixel among them) around the
// centre of a 48 x 48 grid, with off-grid ends.
std::vector<Trap> testTrapezoids() {
  std::vector<Trap> out;
  const float c = 24.3f;
  for (float deg : {0.0f, 17.0f, 45.0f, 73.5f, 90.0f, 133.0f, 200.0f})
    for (float len : {0.4f, 3.7f, 12.2f})
      for (float w : {0.05f, 0.3f, 1.0f, 2.6f}) {
        const float r = deg * 3.14159265f / 180.0f;
        const float dx = 0.5f * len * std::cos(r), dy = 0.5f * len * std::sin(r);
        out.push_back({c - dx, c + 0.37f - dy, c + dx, c + 0.37f + dy, w, 0.6f * w + 0.1f});
      }
  return out;
}

constexpr int kGrid = 48;

// The device's per-pixel areas of one trapezoid over the kGrid x kGrid grid.
std::vector<float> deviceAreas(const Trap& t) {
  auto& d = *sharedDevice().impl();
  static cl::Program program = d.program("coverage_probe.cl", "-DCLH_RASTER_COVER=1");
  cl::Kernel k(program, "coverage_probe_area");
  const float in[6] = {t.ax, t.ay, t.bx, t.by, t.wa, t.wb};
  cl::Buffer bin(d.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof(in),
                 const_cast<float*>(in));
  std::vector<float> out(kGrid * kGrid + 4, -7.0f);  // canaries past the end
  cl::Buffer bout(d.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, out.size() * sizeof(float),
                  out.data());
  k.setArg(0, bin);
  k.setArg(1, cl_uint(kGrid));
  k.setArg(2, cl_uint(kGrid));
  k.setArg(3, bout);
  d.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(kGrid, kGrid), cl::NullRange);
  d.queue.enqueueReadBuffer(bout, CL_TRUE, 0, out.size() * sizeof(float), out.data());
  for (int i = 0; i < 4; ++i) EXPECT_EQ(out[kGrid * kGrid + i], -7.0f) << "canary " << i;
  out.resize(kGrid * kGrid);
  return out;
}

TEST(Coverage, SegmentCoverageIntegratesToItsArea) {
  for (const Trap& t : testTrapezoids()) {
    SCOPED_TRACE(testing::Message() << "segment (" << t.ax << ", " << t.ay << ")-(" << t.bx << ", "
                                    << t.by << ") widths " << t.wa << ", " << t.wb);
    clh_poly8 q;
    ASSERT_TRUE(gpu::clh_trapezoid(t.ax, t.ay, t.bx, t.by, t.wa, t.wb, &q));
    double host = 0.0;
    for (int y = 0; y < kGrid; ++y)
      for (int x = 0; x < kGrid; ++x) host += gpu::clh_trapezoid_pixel_area(&q, float(x), float(y));
    const std::vector<float> dev = deviceAreas(t);
    const double device = std::accumulate(dev.begin(), dev.end(), 0.0);
    EXPECT_NEAR(host, t.area(), 0.01 * t.area());
    EXPECT_NEAR(device, t.area(), 0.01 * t.area());
  }
}

// Share of a grid of n x n points of pixel (px, py) inside the trapezoid, by an independent
// test: the point's distance along the segment in [0, len] and across it within the width
// interpolated there.
double supersampled(const Trap& t, int px, int py, int n) {
  const double dx = double(t.bx) - t.ax, dy = double(t.by) - t.ay, len = std::hypot(dx, dy);
  int in = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = px + (i + 0.5) / n - t.ax, y = py + (j + 0.5) / n - t.ay;
      const double along = (x * dx + y * dy) / len, across = (x * dy - y * dx) / len;
      if (along < 0.0 || along > len) continue;
      const double half = 0.5 * (t.wa + (double(t.wb) - t.wa) * along / len);
      if (std::fabs(across) < half) ++in;
    }
  return double(in) / (double(n) * n);
}

// Whether pixel (px, py) lies wholly outside the box of the trapezoid's ends widened by its
// larger half width (no point of the pixel is inside: supersampled() gives 0 there).
bool outsideBox(const Trap& t, int px, int py) {
  const float h = 0.5f * std::max(t.wa, t.wb) + 0.01f;
  return px + 1 < std::min(t.ax, t.bx) - h || px > std::max(t.ax, t.bx) + h ||
         py + 1 < std::min(t.ay, t.by) - h || py > std::max(t.ay, t.by) + h;
}

TEST(Coverage, PixelCoverageMatchesSupersampledTrapezoid) {
  // n x n points per pixel: each straight edge crossing a pixel miscounts at most one point
  // per row of points, 1/n of the pixel; a pixel meets at most the trapezoid's 4 edges
  constexpr int n = 256;
  const double bound = 4.0 / n;
  double worst = 0.0, sum = 0.0;
  int pixels = 0;
  for (const Trap& t : testTrapezoids()) {
    if (t.wa < 0.3f) continue;  // the thinnest are covered by the area test
    const std::vector<float> dev = deviceAreas(t);
    for (int y = 0; y < kGrid; ++y)
      for (int x = 0; x < kGrid; ++x) {
        const double ss = outsideBox(t, x, y) ? 0.0 : supersampled(t, x, y, n);
        const double a = dev[y * kGrid + x];
        if (ss == 0.0 && a == 0.0) continue;
        const double e = std::fabs(a - ss);
        worst = std::max(worst, e);
        sum += e;
        ++pixels;
        EXPECT_LE(e, bound) << "pixel " << x << ", " << y << " of segment (" << t.ax << ", " << t.ay
                            << ")-(" << t.bx << ", " << t.by << ") width " << t.wa;
      }
  }
  std::printf("[ coverage ] %d pixels: max |analytic - supersampled| %.5f, mean %.6f\n", pixels,
              worst, sum / pixels);
  EXPECT_LT(sum / pixels, 0.25 * bound);
}

// Draws segments (ax, ay, iza, bx, by, izb each) with the raster's coverage path into a
// kGrid x kGrid G-buffer; returns its CLH_LAYER_COVERAGE + 1 planes.
std::vector<cl_ulong> drawSegments(const std::vector<float>& segs, float widthPx1,
                                   const std::vector<float>& sceneDepth) {
  auto& d = *sharedDevice().impl();
  static cl::Program program = d.program("coverage_probe.cl", "-DCLH_RASTER_COVER=1");
  cl::Kernel k(program, "coverage_probe_segments");
  const std::size_t plane = kGrid * kGrid, planes = CLH_LAYER_COVERAGE + 1;
  std::vector<cl_ulong> gbuf(plane * planes + 2, ~cl_ulong(0));
  gbuf[plane * planes] = gbuf[plane * planes + 1] = 0x5A5A5A5A5A5A5A5Aull;  // canaries
  cl::Buffer bs(d.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, segs.size() * sizeof(float),
                const_cast<float*>(segs.data()));
  cl::Buffer bd(d.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, plane * sizeof(float),
                const_cast<float*>(sceneDepth.data()));
  cl::Buffer bg(d.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, gbuf.size() * sizeof(cl_ulong),
                gbuf.data());
  const cl_uint count = static_cast<cl_uint>(segs.size() / 6);
  k.setArg(0, bs);
  k.setArg(1, count);
  k.setArg(2, cl_uint(kGrid));
  k.setArg(3, cl_uint(kGrid));
  k.setArg(4, widthPx1);
  k.setArg(5, bd);
  k.setArg(6, bg);
  d.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange((count + 7) / 8 * 8), cl::NDRange(8));
  d.queue.enqueueReadBuffer(bg, CL_TRUE, 0, gbuf.size() * sizeof(cl_ulong), gbuf.data());
  EXPECT_EQ(gbuf[plane * planes], 0x5A5A5A5A5A5A5A5Aull);
  EXPECT_EQ(gbuf[plane * planes + 1], 0x5A5A5A5A5A5A5A5Aull);
  gbuf.resize(plane * planes);
  return gbuf;
}

float coverageAt(const std::vector<cl_ulong>& gbuf, std::size_t idx) {
  const auto* plane = reinterpret_cast<const std::uint32_t*>(
      gbuf.data() + std::size_t(CLH_LAYER_COVERAGE) * kGrid * kGrid);
  return gpu::clh_cover_sum(plane[idx]);
}

TEST(Coverage, RasterAddsEachPixelsCoverageInFrontOfTheScene) {
  // one segment at depth 2 (its width 1.4 / 2 = 0.7 px); the scene depth is 1 (in front of
  // it) on the right half of the grid
  const std::vector<float> seg = {10.2f, 11.7f, 0.5f, 37.9f, 30.1f, 0.5f};
  std::vector<float> depth(kGrid * kGrid, 1e30f);
  for (int y = 0; y < kGrid; ++y)
    for (int x = kGrid / 2; x < kGrid; ++x) depth[y * kGrid + x] = 1.0f;
  const std::vector<cl_ulong> g = drawSegments(seg, 1.4f, depth);
  clh_poly8 q;
  ASSERT_TRUE(gpu::clh_trapezoid(seg[0], seg[1], seg[3], seg[4], 0.7f, 0.7f, &q));
  int covered = 0;
  for (int y = 0; y < kGrid; ++y)
    for (int x = 0; x < kGrid; ++x) {
      const std::size_t i = std::size_t(y) * kGrid + x;
      const float area = gpu::clh_trapezoid_pixel_area(&q, float(x), float(y));
      const bool hidden = x >= kGrid / 2;
      const float expect = hidden ? 0.0f : std::round(area * 1024.0f) / 1024.0f;
      EXPECT_NEAR(coverageAt(g, i), expect, 1e-6f) << "pixel " << x << ", " << y;
      EXPECT_EQ(g[i] != CLH_GBUF_EMPTY, !hidden && expect > 0.0f) << "pixel " << x << ", " << y;
      EXPECT_EQ(g[kGrid * kGrid + i], CLH_GBUF_EMPTY) << "one segment fills one layer";
      if (!hidden && expect > 0.0f) {
        ++covered;
        const float z = gpu::clh_depth_decode(gpu::clh_gbuf_depth(g[i]), 0.0f, 100.0f);
        EXPECT_NEAR(z, 2.0f, 1e-3f);
      }
    }
  EXPECT_GT(covered, 20);
}

TEST(Coverage, LayersStayDepthOrderedUnderAnyWriteOrder) {
  auto& d = *sharedDevice().impl();
  cl::Program program = d.program("coverage_probe.cl", "-DCLH_RASTER_COVER=1");
  cl::Kernel k(program, "coverage_probe_insert");
  std::mt19937_64 rng(2024);
  for (int round = 0; round < 24; ++round) {
    SCOPED_TRACE(round);
    // many fragments, some equal, in a random order (depth code in the high bits)
    const std::uint32_t n = 37 + static_cast<std::uint32_t>(rng() % 3000);
    std::vector<cl_ulong> words(n);
    const std::uint64_t range = round % 3 == 0 ? 40 : (1ull << 24);
    for (cl_ulong& w : words) w = ((rng() % range) << 40) | (rng() & 0xFFFFFFFFFFull);
    std::shuffle(words.begin(), words.end(), rng);
    std::vector<cl_ulong> gbuf(4 + 2, ~cl_ulong(0));
    gbuf[4] = gbuf[5] = 0x0123456789ABCDEFull;
    cl::Buffer bw(d.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(cl_ulong),
                  words.data());
    cl::Buffer bg(d.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                  gbuf.size() * sizeof(cl_ulong), gbuf.data());
    k.setArg(0, bw);
    k.setArg(1, n);
    k.setArg(2, bg);
    const std::size_t local = round % 2 == 0 ? 1 : 64;
    d.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange((n + local - 1) / local * local),
                                 cl::NDRange(local));
    d.queue.enqueueReadBuffer(bg, CL_TRUE, 0, gbuf.size() * sizeof(cl_ulong), gbuf.data());
    std::vector<cl_ulong> sorted = words;
    std::sort(sorted.begin(), sorted.end());
    for (int layer = 0; layer < 3; ++layer)
      EXPECT_EQ(gbuf[layer], sorted[layer]) << "layer " << layer << " of " << n << " fragments";
    std::uint64_t add = 0;
    for (std::uint32_t i = 0; i < n; ++i) add += std::uint64_t((i % 7u) / 8.0f * 1024.0f + 0.5f);
    const auto* cov = reinterpret_cast<const std::uint32_t*>(&gbuf[3]);
    EXPECT_EQ(std::uint64_t(std::uint32_t(cov[0] + 1u)), add) << "every fragment adds";
    EXPECT_EQ(gbuf[4], 0x0123456789ABCDEFull);
    EXPECT_EQ(gbuf[5], 0x0123456789ABCDEFull);
  }
}

TEST(Coverage, AlphaCurveReproducesFromItsSimulationWithinItsError) {
  const CoverageSimulation sim = simulateCoverage();
  double b1 = 0.0, b2 = 0.0;
  fitCoverageCurve(sim, CLH_COVER_X1, &b1, &b2);
  std::printf("[ coverage ] fit on x in [0, %.1f]: b1 = %.5f, b2 = %.5f\n", CLH_COVER_X1, b1, b2);
  EXPECT_NEAR(b1, CLH_COVER_B1, 5e-5) << "coverage.h's b1 is not the simulation's fit";
  EXPECT_NEAR(b2, CLH_COVER_B2, 5e-5) << "coverage.h's b2 is not the simulation's fit";
  double worst = 0.0, sum = 0.0, talkWorst = 0.0, talkSum = 0.0;
  int bins = 0;
  for (int b = 0; b < sim.bins(); ++b) {
    if (sim.count[b] == 0.0) continue;
    const double x = sim.centre(b), truth = sim.mean(b);
    const double e = std::fabs(gpu::clh_cover_alpha(float(x)) - truth);
    const double s = std::min(std::max(0.5 * x, 0.0), 1.0);
    const double talk = std::min(std::max(x - 0.5 * x * s, 0.0), 1.0);  // Kulikov's quadratic
    worst = std::max(worst, e);
    sum += e;
    talkWorst = std::max(talkWorst, std::fabs(talk - truth));
    talkSum += std::fabs(talk - truth);
    ++bins;
  }
  std::printf(
      "[ coverage ] %d bins of x in [0, %.0f]: fit max error %.4f, mean %.4f; the talk's "
      "quadratic %.4f / %.4f\n",
      bins, CoverageSimulation::kMaxX, worst, sum / bins, talkWorst, talkSum / bins);
  EXPECT_LE(worst, CLH_COVER_MAX_ERROR + 1e-4);
  EXPECT_LE(sum / bins, CLH_COVER_MEAN_ERROR + 1e-4);
  // the curve's shape: 0 at 0, increasing, 1 from x1 on
  EXPECT_EQ(gpu::clh_cover_alpha(0.0f), 0.0f);
  EXPECT_EQ(gpu::clh_cover_alpha(CLH_COVER_X1), 1.0f);
  EXPECT_EQ(gpu::clh_cover_alpha(100.0f), 1.0f);
  float prev = 0.0f;
  for (int i = 1; i <= 6000; ++i) {
    const float a = gpu::clh_cover_alpha(i * 0.001f);
    EXPECT_GE(a, prev) << "x = " << i * 0.001f;
    prev = a;
  }
}

// A scene of horizontal straight strands in the plane z = 0 (world y values `ys`, each from
// x = -0.06 to 0.06 in 13 points), seen from z = 0.3 at 64 x 48, no lights but ambient.
Scene horizontalStrands(const std::vector<float>& ys, float strandWidth) {
  StrandGroom g;
  g.name = "horizontal";
  g.appearance.strandWidth = strandWidth;
  for (float y : ys) {
    g.pointCounts.push_back(13);
    for (int k = 0; k < 13; ++k) g.points.emplace_back(-0.06f + 0.01f * k, y, 0.0f);
  }
  Scene sc;
  sc.width = 64;
  sc.height = 48;
  sc.camera.position = glm::vec3(0.0f, 0.0f, 0.3f);
  sc.camera.target = glm::vec3(0.0f);
  sc.camera.fovYDegrees = 35.0f;
  sc.grooms.push_back(
      GroomInstance("horizontal", std::make_shared<const StrandGroom>(std::move(g))));
  return sc;
}

const double kFy = 0.5 * 48.0 / std::tan(35.0 * 3.14159265358979 / 360.0);

TEST(Coverage, FrontoParallelStrandHasTheStripsCoverageAndAlphaProfile) {
  // one strand 0.6 px wide at a sub-pixel offset
  const float y0 = 0.0123f, width = 0.6f * 0.3f / float(kFy);
  Renderer r(sharedDevice());
  RenderOptions ro;
  ro.raster = RasterMode::Coverage;
  ro.aovs = true;
  ro.captureGBuffer = true;
  ro.ambientOcclusion = false;
  const Frame f = r.render(horizontalStrands({y0}, width), ro);
  ASSERT_EQ(f.gbufferLayers, int(CLH_LAYER_COVERAGE) + 1);
  EXPECT_EQ(f.stats.linkSelecting, 0u) << "the default filter (Huang's) ran in coverage mode";
  const std::size_t W = 64, H = 48;
  const auto* cov =
      reinterpret_cast<const std::uint32_t*>(f.gbuffer.data() + CLH_LAYER_COVERAGE * W * H);
  const double yc = 0.5 * H - kFy * y0 / 0.3, half = 0.3;  // the strip [yc - half, yc + half]
  int checked = 0;
  for (std::size_t x = 20; x < 44; ++x) {  // columns well inside the strand
    double column = 0.0;
    for (std::size_t y = 0; y < H; ++y) {
      const double strip =
          std::max(0.0, std::min(double(y) + 1.0, yc + half) - std::max(double(y), yc - half));
      const float c = gpu::clh_cover_sum(cov[y * W + x]);
      column += c;
      // a column may hold two segments' parts, each rounded to 1/1024
      EXPECT_NEAR(c, strip, 2.0 / 1024.0 + 2e-3) << "pixel " << x << ", " << y;
      EXPECT_NEAR(f.aovs.hairAlpha[y * W + x], gpu::clh_cover_alpha(c), 1e-5)
          << "alpha from the coverage plane, pixel " << x << ", " << y;
      if (strip > 0.0) ++checked;
    }
    EXPECT_NEAR(column, 0.6, 0.01 * 0.6) << "column " << x << ": the strand's width";
    // one layer per pixel, scaled to the pixel's alpha: the hair's colour over alpha (its
    // premultiplied colour is the frame minus the background's share) is the same in every
    // pixel of the column, whatever its coverage
    const glm::vec3 bg = Scene().background;
    std::vector<glm::vec3> unpremultiplied;
    for (std::size_t y = 0; y < H; ++y) {
      const float a = f.aovs.hairAlpha[y * W + x];
      if (a < 0.05f) continue;
      const float* c = &f.color.rgba[4 * (y * W + x)];
      unpremultiplied.push_back((glm::vec3(c[0], c[1], c[2]) - (1.0f - a) * bg) / a);
    }
    ASSERT_GE(unpremultiplied.size(), 2u) << "column " << x;
    for (const glm::vec3& u : unpremultiplied)
      for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(u[ch], unpremultiplied[0][ch], 0.02f * unpremultiplied[0][ch] + 2e-3f)
            << "column " << x << " channel " << ch;
  }
  EXPECT_GE(checked, 24);
}

TEST(Coverage, DenseSlabOfStrandsReachesOpaqueAlpha) {
  // 300 strands 0.5 px wide spread over a band 8 px high: ~19 coverages per pixel
  std::vector<float> ys;
  std::mt19937 rng(7);
  const float pxToWorld = 0.3f / float(kFy);
  for (int i = 0; i < 300; ++i)
    ys.push_back((std::uniform_real_distribution<float>(-4.0f, 4.0f)(rng)) * pxToWorld);
  Renderer r(sharedDevice());
  RenderOptions ro;
  ro.raster = RasterMode::Coverage;
  ro.aovs = true;
  const Frame f = r.render(horizontalStrands(ys, 0.5f * pxToWorld), ro);
  const std::size_t W = 64;
  for (std::size_t x = 20; x < 44; ++x) {
    for (std::size_t y = 21; y < 27; ++y)  // rows 20..27 hold the band [20, 28)
      EXPECT_GE(f.aovs.hairAlpha[y * W + x], 0.999f) << "pixel " << x << ", " << y;
    for (std::size_t y : {std::size_t(10), std::size_t(17), std::size_t(31), std::size_t(40)})
      EXPECT_EQ(f.aovs.hairAlpha[y * W + x], 0.0f) << "pixel " << x << ", " << y;
  }
  // the lines raster of the same slab: more than three strands per pixel, still opaque
  ro.raster = RasterMode::Lines;
  const Frame lines = r.render(horizontalStrands(ys, 0.5f * pxToWorld), ro);
  EXPECT_GT(lines.aovs.hairAlpha[24 * W + 32], 0.5f);
}

TEST(Coverage, CliRendersCoverageAndRefusesUnknownRasterInOneLine) {
  const std::string dir = scratchDir();
  const std::string scene = sourceDir() + "/tests/data/oclgrind_tiny.json";
  const CommandResult ok =
      runCli("render " + quote(scene) + " -q --raster coverage -o " + quote(dir + "/c.png"));
  EXPECT_EQ(ok.exitCode, 0) << ok.output;
  EXPECT_TRUE(std::filesystem::exists(dir + "/c.png"));

  // layers for compositing of a still scene (the CLI hands the renderer the previous frame)
  const CommandResult aov =
      runCli("render " + quote(scene) + " -q --raster coverage --aov rgba,alpha -o " +
             quote(dir + "/c.exr"));
  EXPECT_EQ(aov.exitCode, 0) << aov.output;

  const CommandResult bad =
      runCli("render " + quote(scene) + " -q --raster trapezoid -o " + quote(dir + "/b.png"));
  EXPECT_NE(bad.exitCode, 0);
  EXPECT_EQ(std::count(bad.output.begin(), bad.output.end(), '\n'), 1) << bad.output;
  EXPECT_NE(bad.output.find("--raster must be lines or coverage, not \"trapezoid\""),
            std::string::npos)
      << bad.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/b.png"));

  const CommandResult msaa = runCli("render " + quote(scene) +
                                    " -q --raster coverage --msaa 4 -o " + quote(dir + "/m.png"));
  EXPECT_NE(msaa.exitCode, 0);
  EXPECT_EQ(std::count(msaa.output.begin(), msaa.output.end(), '\n'), 1) << msaa.output;

  // the scene key (the groom's path made absolute for the scratch folder)
  std::ifstream in(scene);
  std::string keyed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string rel = "../../assets/grooms/tiny.hairmesh.json";
  const std::size_t at = keyed.find(rel), brace = keyed.find('{');
  ASSERT_NE(at, std::string::npos);
  keyed.replace(at, rel.size(), assetPath("grooms/tiny.hairmesh.json"));
  keyed.insert(brace + 1, "\"raster\": \"wide\", ");
  const std::string badScene = dir + "/bad_raster.json";
  std::ofstream(badScene) << keyed;
  const CommandResult key = runCli("render " + quote(badScene) + " -q -o " + quote(dir + "/k.png"));
  EXPECT_NE(key.exitCode, 0);
  EXPECT_EQ(std::count(key.output.begin(), key.output.end(), '\n'), 1) << key.output;
  EXPECT_NE(key.output.find("raster"), std::string::npos) << key.output;
  EXPECT_NE(key.output.find("\"lines\" or \"coverage\""), std::string::npos) << key.output;
}

}  // namespace
}  // namespace clhair::test
