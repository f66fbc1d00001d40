// test_labels.cpp — the labels hair models learn from (clhair/labels.h, kernels/labels.cl),
// computed on the device from a frame's tangent and hair alpha layers:
//   Labels.DeviceMatchesTheCpuFormulas   every pixel's angle, confidence, mask and strand map
//                                        against the same formulas on the host (doubles)
//   Labels.RadialStrandsGiveTheirOwnAngles   strands radiating in the image plane: each
//                                        pixel's angle is its strand's, modulo pi
//   Labels.AFrameWithoutAovsIsRefused    one clear error
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <glm/geometric.hpp>

#include "clhair/error.h"
#include "clhair/labels.h"
#include "clhair/renderer.h"
#include "stages/view_math.h"
#include "test_util.h"

namespace clhair::test {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kStrands = 24;

// 24 strands radiating from the image centre in the plane z = 0 (strand k at angle
// k pi / 12 from +x, y up), three of them bent toward the camera at their tips; the camera
// at z = 0.3 looks along -z.
Scene radialStrands() {
  StrandGroom g;
  g.name = "radial";
  g.appearance.strandWidth = 0.002f;
  for (int s = 0; s < kStrands; ++s) {
    const double a = s * kPi / 12.0;
    g.pointCounts.push_back(9);
    for (int k = 0; k < 9; ++k) {
      const float r = 0.006f + 0.005f * k;
      const float z = (s % 8 == 3) ? 0.004f * k : 0.0f;
      g.points.emplace_back(r * std::cos(a), r * std::sin(a), z);
    }
  }
  Scene sc;
  sc.width = 96;
  sc.height = 80;
  sc.camera.position = glm::vec3(0.0f, 0.0f, 0.3f);
  sc.camera.target = glm::vec3(0.0f);
  sc.camera.fovYDegrees = 25.0f;
  Light l;
  l.direction = glm::normalize(glm::vec3(0.3f, 1.0f, 0.6f));
  sc.lights.push_back(l);
  sc.grooms.push_back(GroomInstance("radial", std::make_shared<const StrandGroom>(std::move(g))));
  return sc;
}

Frame renderWithAovs(Renderer& r, const Scene& s) {
  RenderOptions o;
  o.aovs = true;
  return r.render(s, o);
}

TEST(Labels, DeviceMatchesTheCpuFormulas) {
  Renderer r(sharedDevice());
  const Scene s = radialStrands();
  const Frame f = renderWithAovs(r, s);
  const HairLabels l = r.labels(f, s.camera);
  const int w = s.width, h = s.height;
  const std::size_t n = std::size_t(w) * h;
  ASSERT_EQ(l.angle.size(), n);
  ASSERT_EQ(l.strandMap.size(), 3 * n);
  const gpu::ClhViewGpu v = makeView(s.camera, w, h);
  std::size_t strands = 0, masked = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double tx = f.aovs.tangent[3 * i], ty = f.aovs.tangent[3 * i + 1],
                 tz = f.aovs.tangent[3 * i + 2];
    const float* m = v.world_to_view;
    const double vx = m[0] * tx + m[1] * ty + m[2] * tz, vy = m[4] * tx + m[5] * ty + m[6] * tz,
                 vz = m[8] * tx + m[9] * ty + m[10] * tz;
    const double a = (double(i % w) + 0.5 - v.cx) / v.fx;
    const double b = -(double(i / w) + 0.5 - v.cy) / v.fy;
    const double dx = vx - a * vz, dy = vy - b * vz, len = std::hypot(dx, dy);
    EXPECT_EQ(l.mask[i], f.aovs.hairAlpha[i] >= kLabelMaskAlpha ? 1 : 0) << "pixel " << i;
    if (!(tx != 0.0 || ty != 0.0 || tz != 0.0) || !(len > 1e-12)) {
      EXPECT_EQ(l.angle[i] + l.confidence[i] + l.strandMap[3 * i], 0.0f) << "pixel " << i;
      continue;
    }
    ++strands;
    const double ux = dx / len, uy = dy / len;
    double angle = std::atan2(uy, ux);
    if (angle < 0.0) angle += kPi;
    // the angle modulo pi: compare the doubled angles' directions (0 and pi are one angle)
    EXPECT_NEAR(std::sin(2.0 * (l.angle[i] - angle)), 0.0, 2e-5) << "pixel " << i;
    EXPECT_NEAR(std::cos(2.0 * (l.angle[i] - angle)), 1.0, 2e-5) << "pixel " << i;
    EXPECT_GE(l.angle[i], 0.0f);
    EXPECT_LT(l.angle[i], static_cast<float>(kPi));
    const double rl = std::sqrt(a * a + b * b + 1.0);
    const double rx = a / rl, ry = b / rl, rz = 1.0 / rl;
    const double cx = vy * rz - vz * ry, cy = vz * rx - vx * rz, cz = vx * ry - vy * rx;
    const double sine = std::min(
        1.0, std::sqrt(cx * cx + cy * cy + cz * cz) / std::sqrt(vx * vx + vy * vy + vz * vz));
    const double alpha = std::clamp(double(f.aovs.hairAlpha[i]), 0.0, 1.0);
    EXPECT_NEAR(l.confidence[i], alpha * sine, 2e-5) << "pixel " << i;
    const bool hair = f.aovs.hairAlpha[i] >= kLabelMaskAlpha;
    masked += hair;
    if (hair) {
      EXPECT_EQ(l.strandMap[3 * i], 1.0f);
      EXPECT_NEAR(l.strandMap[3 * i + 1], 0.5 * (ux + 1.0), 2e-5) << "pixel " << i;
      EXPECT_NEAR(l.strandMap[3 * i + 2], 0.5 * (uy + 1.0), 2e-5) << "pixel " << i;
    } else {
      EXPECT_EQ(l.strandMap[3 * i] + l.strandMap[3 * i + 1] + l.strandMap[3 * i + 2], 0.0f);
    }
  }
  EXPECT_GT(strands, 300u) << "the groom should cover a fair part of the frame";
  EXPECT_GT(masked, 100u);
}

TEST(Labels, RadialStrandsGiveTheirOwnAngles) {
  Renderer r(sharedDevice());
  const Scene s = radialStrands();
  const Frame f = renderWithAovs(r, s);
  const HairLabels l = r.labels(f, s.camera);
  const int w = s.width, h = s.height;
  // a pixel at image angle phi from the centre lies on the strand at that angle (the strands
  // are 15 degrees apart): its label is phi modulo pi, up to the tangent's octahedral code
  std::vector<double> errors;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = std::size_t(y) * w + x;
      if (!l.mask[i]) continue;
      const double px = x + 0.5 - 0.5 * w, py = -(y + 0.5 - 0.5 * h);
      if (std::hypot(px, py) < 8.0) continue;  // the crowded centre
      const double phi = std::atan2(py, px);
      const int k = static_cast<int>(std::lround(phi / (kPi / 12.0)));
      const double strand = k * kPi / 12.0;
      if (std::fabs(phi - strand) > 0.05) continue;        // between strands (their widths)
      if (((k % kStrands) + kStrands) % 8 == 3) continue;  // the bent ones
      errors.push_back(std::fabs(std::sin(l.angle[i] - strand)));
    }
  ASSERT_GT(errors.size(), 50u);
  std::sort(errors.begin(), errors.end());
  EXPECT_LT(errors[errors.size() / 2], 0.02) << "median |sin| of the angle error";
  EXPECT_LT(errors[errors.size() * 9 / 10], 0.06) << "90th percentile";
}

TEST(Labels, AFrameWithoutAovsIsRefused) {
  Renderer r(sharedDevice());
  const Scene s = radialStrands();
  const Frame f = r.render(s);
  try {
    r.labels(f, s.camera);
    FAIL() << "labels of a frame without AOVs";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("RenderOptions::aovs"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace clhair::test
