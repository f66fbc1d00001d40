// test_link_filter.cpp — the orientation-aware anisotropic filter of Huang et al. 2025
// (kernels/link.cl) on synthetic G-buffers (link_synthetic.h): it keeps a uniform strand's
// colour and does not mix two parallel strands two pixels apart, reaches no farther than
// 3 px and, on a hair only a few pixels large, still 1 px (its 2 px floor), and in dense hair
// takes in a little of the row beside a pixel, nothing of rows farther.
#include <gtest/gtest.h>

#include <vector>

#include "link_synthetic.h"

namespace clhair {
namespace {

TEST(Link, AnisotropicFilterSmoothsAlongAStrandAndDoesNotMixParallelStrands) {
  Synthetic s;
  const cl_float4 dark{{0.2f, 0.2f, 0.2f, 1.0f}}, bright{{0.6f, 0.6f, 0.6f, 1.0f}};
  for (int x = 2; x <= 37; ++x) {
    const float u = float(x - 2) / 35.0f;
    s.drawn(x, 14, 1, u, 1.5f, 1.0f, 0.0f, kRed);
    s.drawn(x, 16, 2, u, 1.5f, 1.0f, 0.0f, kBlue);
    s.drawn(x, 25, 3 + (x & 1), u, 1.5f, 1.0f, 0.0f, dark);  // a noisy strand: two "ids"
  }
  FilterParams f = linkOnly();
  f.aniso = true;
  f.sigmaD = 1.0f;   // a wide kernel, so the normalisation and the ellipse matter
  f.kernelK = 0.2f;  // r = 0.2 sqrt(36 * 12) ~ 4 px, clamped to 3
  const LinkResult r = runLink(
      s, f, [&](clh_u32 k) { return k == 1 ? kRed : (k == 2 ? kBlue : (k == 3 ? bright : dark)); });
  // away from the strands' ends (past the kernel's reach: the ends fade into the empty
  // pixels past them, as the matte's filter does)
  for (int x = 8; x <= 31; ++x) {
    const cl_float4 a = r.out[14 * W + x], b = r.out[16 * W + x];
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(a.s[c], kRed.s[c], 2e-3f) << "red strand at " << x;
      EXPECT_NEAR(b.s[c], kBlue.s[c], 2e-3f) << "blue strand at " << x;
    }
    EXPECT_NEAR(a.s[3], 1.0f, 1e-5f);
  }
  // along the noisy strand: the alternation shrinks, the mean stays
  float lo = 1.0f, hi = 0.0f;
  double mean = 0.0;
  for (int x = 8; x <= 31; ++x) {
    const float v = r.out[25 * W + x].s[0];
    lo = std::min(lo, v);
    hi = std::max(hi, v);
    mean += v / 24.0;
  }
  EXPECT_LT(hi - lo, 0.2f) << "not smoothed along the strand (input spread 0.4)";
  EXPECT_NEAR(mean, 0.4, 0.02);
}

// A horizontal strand at y = 20 from x = 4 to 36, red with one blue pixel (strand 2) at x = 24.
Synthetic strandWithOddPixel() {
  Synthetic s;
  for (int x = 4; x <= 36; ++x)
    s.drawn(x, 20, x == 24 ? 2 : 1, float(x - 4) / 32.0f, 1.5f, 1.0f, 0.0f, x == 24 ? kBlue : kRed);
  return s;
}

TEST(Link, AnisotropicKernelReachesAtMostThreePixels) {
  // a horizontal strand of one colour with one differently coloured pixel at x = 24; the
  // screen box asks for a far longer kernel (k = 1), which is clamped to r = 3 px: the
  // pixel 2 px from the odd one takes some of it, the pixel 4 px away none
  const Synthetic s = strandWithOddPixel();
  FilterParams f = linkOnly();
  f.aniso = true;
  f.kernelK = 1.0f;
  const LinkResult r = runLink(s, f, [](clh_u32 k) { return k == 2 ? kBlue : kRed; });
  for (int c = 0; c < 4; ++c) {
    EXPECT_FLOAT_EQ(r.out[20 * W + 20].s[c], kRed.s[c]) << "reached 4 px, channel " << c;
    EXPECT_FLOAT_EQ(r.out[20 * W + 28].s[c], kRed.s[c]) << "reached 4 px, channel " << c;
  }
  EXPECT_GT(r.out[20 * W + 22].s[2], kRed.s[2] + 0.01f) << "no reach at 2 px";
  EXPECT_GT(r.out[20 * W + 26].s[2], kRed.s[2] + 0.01f) << "no reach at 2 px";
}

TEST(Link, AnisotropicKernelReachesTwoPixelsOnAHairOfAFewPixels) {
  // the same strand with its odd pixel, but a screen box that asks for r far below a pixel
  // (k = 0.001): the kernel keeps its floor of 2 px, so the odd pixel's neighbours along the
  // strand take some of it (below 2 px the ellipse would hold only P) and 3 px away nothing
  const Synthetic s = strandWithOddPixel();
  FilterParams f = linkOnly();
  f.aniso = true;
  f.kernelK = 0.001f;
  const LinkResult r = runLink(s, f, [](clh_u32 k) { return k == 2 ? kBlue : kRed; });
  for (int x : {23, 25}) {
    EXPECT_GT(r.out[20 * W + x].s[2], kRed.s[2] + 0.05f) << "no reach at 1 px, x = " << x;
    EXPECT_NEAR(r.out[20 * W + x].s[3], 1.0f, 1e-5f);
  }
  for (int c = 0; c < 4; ++c) {
    EXPECT_FLOAT_EQ(r.out[20 * W + 21].s[c], kRed.s[c]) << "reached 3 px, channel " << c;
    EXPECT_FLOAT_EQ(r.out[20 * W + 27].s[c], kRed.s[c]) << "reached 3 px, channel " << c;
  }
}

TEST(Link, AnisotropicKernelAveragesTheRowsBesideAStrandInDenseHair) {
  // dense hair, every pixel drawn with a horizontal tangent: red rows with one blue row
  // (21). With the default aspect ratio (minor axis r / 2) and sigma_theta (0.6 rad) the
  // ellipse of a red pixel next to it takes in the blue row's pixels at 27-45 degrees from
  // the tangent, so a little blue comes in; the pixel straight across (90 degrees) adds
  // next to nothing, and two rows away the red stays red
  Synthetic s;
  for (int y = 14; y <= 26; ++y)
    for (int x = 4; x <= 36; ++x)
      s.drawn(x, y, y == 21 ? 2 : 1, float(x - 4) / 32.0f, 1.5f, 1.0f, 0.0f,
              y == 21 ? kBlue : kRed);
  FilterParams f = linkOnly();
  f.aniso = true;
  f.kernelK = 0.2f;  // r = 0.2 sqrt(33 * 13) ~ 4 px, clamped to 3
  const LinkResult r = runLink(s, f, [](clh_u32 k) { return k == 2 ? kBlue : kRed; });
  for (int x = 10; x <= 30; ++x) {
    SCOPED_TRACE(testing::Message() << "x = " << x);
    const cl_float4 beside = r.out[20 * W + x], apart = r.out[19 * W + x];
    EXPECT_GT(beside.s[2], kRed.s[2] + 0.02f) << "the row beside the blue one took none of it";
    EXPECT_LT(beside.s[2], kRed.s[2] + 0.1f) << "more than the diagonal neighbours' share";
    EXPECT_NEAR(beside.s[3], 1.0f, 1e-5f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(apart.s[c], kRed.s[c], 1e-5f) << "two rows away";
  }
}

}  // namespace
}  // namespace clhair
