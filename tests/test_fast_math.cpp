// test_fast_math.cpp — the approximations of kernels/include/clhair/fast_math.h against the exact
// functions (double precision) over their whole input ranges, with the bounds their
// comments state. The kernels compile the same code.
#include <gtest/gtest.h>

#include <cmath>

#include "clhair/fast_math.h"

namespace clhair {
namespace {

using namespace gpu;

TEST(FastMath, Exp2RelativeErrorOverItsRange) {
  double worst = 0.0;
  for (int i = 0; i <= 2000000; ++i) {
    const float x = -126.0f + 252.0f * static_cast<float>(i) / 2000000.0f;
    const double exact = std::exp2(static_cast<double>(x));
    worst = std::max(worst, std::abs(clh_fast_exp2(x) / exact - 1.0));
  }
  EXPECT_LT(worst, 5e-7);
  EXPECT_EQ(clh_fast_exp2(0.0f), clh_fast_exp2(-0.0f));
  EXPECT_NEAR(clh_fast_exp2(1000.0f), std::exp2(126.0), std::exp2(126.0) * 5e-7);  // clamped
}

TEST(FastMath, ExpRelativeErrorOverItsRange) {
  double worst = 0.0;
  for (int i = 0; i <= 2000000; ++i) {
    const float x = -87.0f + 174.0f * static_cast<float>(i) / 2000000.0f;
    const double exact = std::exp(static_cast<double>(x));
    // the stated bound: 1e-6 plus the rounding of x log2(e) (6e-8 |x| relative)
    const double bound = 1e-6 + 6e-8 * std::abs(static_cast<double>(x));
    worst = std::max(worst, std::abs(clh_fast_exp(x) / exact - 1.0) / bound);
  }
  EXPECT_LT(worst, 1.0) << "worst error as a multiple of the stated bound";
}

TEST(FastMath, ExpNegRelativeErrorOverItsRangeAndCloseToExp) {
  double worst = 0.0, worst_vs_exp = 0.0;
  for (int i = 0; i <= 2000000; ++i) {
    const float x = -87.0f * static_cast<float>(i) / 2000000.0f;
    const double exact = std::exp(static_cast<double>(x));
    // the stated bound: 1e-6 plus the rounding of x log2(e) (6e-8 |x| relative)
    const double bound = 1e-6 + 6e-8 * std::abs(static_cast<double>(x));
    worst = std::max(worst, std::abs(clh_fast_exp_neg(x) / exact - 1.0) / bound);
    // the same polynomial as clh_fast_exp in another order: a few float roundings apart
    worst_vs_exp = std::max(
        worst_vs_exp, std::abs(static_cast<double>(clh_fast_exp_neg(x)) / clh_fast_exp(x) - 1.0));
  }
  EXPECT_LT(worst, 1.0) << "worst error as a multiple of the stated bound";
  EXPECT_LT(worst_vs_exp, 5e-7);
  EXPECT_EQ(clh_fast_exp_neg(0.0f), clh_fast_exp_neg(-0.0f));
  EXPECT_EQ(clh_fast_exp_neg(1.0f), clh_fast_exp_neg(0.0f));  // x > 0 is taken as 0
  EXPECT_NEAR(clh_fast_exp_neg(-1000.0f), std::exp2(-126.0), std::exp2(-126.0) * 1e-6);
}

TEST(FastMath, Log2AbsoluteErrorOverEveryBinade) {
  double worst = 0.0;
  for (int e = -126; e < 128; ++e)
    for (int k = 0; k < 4096; ++k) {
      const float x = std::ldexp(1.0f + static_cast<float>(k) / 4096.0f, e);
      const double exact = std::log2(static_cast<double>(x));
      // the stated bound plus the float result's own rounding (half an ulp, 2^-24 relative)
      const double bound = 3e-7 + 6e-8 * std::abs(exact);
      worst = std::max(worst, std::abs(clh_fast_log2(x) - exact) / bound);
    }
  EXPECT_LT(worst, 1.0) << "worst error as a multiple of the stated bound";
  EXPECT_EQ(clh_fast_log2(0.0f), -126.0f);
  EXPECT_EQ(clh_fast_log2(-1.0f), -126.0f);
}

TEST(FastMath, PowOnTheUnitIntervalAsStylingUsesIt) {
  double worst = 0.0;
  for (float y : {0.25f, 0.5f, 1.0f, 1.7f, 2.0f, 3.3f, 8.0f})
    for (int i = 1; i <= 100000; ++i) {
      const float x = static_cast<float>(i) / 100000.0f;
      const double exact = std::pow(static_cast<double>(x), static_cast<double>(y));
      if (exact < 1e-30) continue;
      const double bound = 1e-6 * std::max(1.0, std::abs(y * std::log2(static_cast<double>(x))));
      worst = std::max(worst, std::abs(clh_fast_pow(x, y) / exact - 1.0) / bound);
    }
  EXPECT_LT(worst, 1.0) << "worst error as a multiple of the stated bound";
  EXPECT_EQ(clh_fast_pow(0.0f, 2.0f), 0.0f);
}

TEST(FastMath, SinCosAbsoluteErrorUpTo1e4) {
  double worst = 0.0;
  for (int i = -2000000; i <= 2000000; ++i) {
    const float x = 1e4f * static_cast<float>(i) / 2000000.0f;
    float s, c;
    clh_fast_sincos(x, &s, &c);
    worst = std::max({worst, std::abs(s - std::sin(static_cast<double>(x))),
                      std::abs(c - std::cos(static_cast<double>(x)))});
  }
  EXPECT_LT(worst, 1e-6);
  float s, c;
  clh_fast_sincos(0.0f, &s, &c);
  EXPECT_EQ(s, 0.0f);
  EXPECT_EQ(c, 1.0f);
}

TEST(FastMath, AcosAndAsinAbsoluteErrorOverTheirDomain) {
  double worst_acos = 0.0, worst_asin = 0.0;
  for (int i = -2000000; i <= 2000000; ++i) {
    const float x = static_cast<float>(i) / 2000000.0f;
    worst_acos = std::max(worst_acos, std::abs(clh_fast_acos(x) - std::acos(double(x))));
    worst_asin = std::max(worst_asin, std::abs(clh_fast_asin(x) - std::asin(double(x))));
  }
  EXPECT_LT(worst_acos, 1e-6);
  EXPECT_LT(worst_asin, 1e-6);
  // outside the domain: clamped to the ends
  EXPECT_NEAR(clh_fast_acos(1.5f), 0.0, 1e-6);
  EXPECT_NEAR(clh_fast_acos(-1.5f), M_PI, 1e-6);
  EXPECT_NEAR(clh_fast_asin(1.0f), M_PI / 2, 1e-6);
}

}  // namespace
}  // namespace clhair
