/* fast_math.h — elementary functions as straight-line arithmetic, for the hot loops of the
 * strand, shading and filter kernels (DESIGN.md, "Vectorizable kernels").
 *
 * CPU OpenCL compilers vectorize across work-items only code without calls into their
 * built-in library, and the built-ins' argument reduction (sin, cos, pow, exp) dominates
 * the per-point styling on a CPU. These are branch-free approximations with the error
 * bounds stated per function, written in the common subset of C++17 and OpenCL C so
 * tests/test_fast_math.cpp checks each against the exact function over its whole input
 * range on the host, and the kernels compile the very same code.
 */
#ifndef CLHAIR_FAST_MATH_H
#define CLHAIR_FAST_MATH_H

#include "clhair/gpu_types.h"

#ifdef CLH_DEVICE_CODE
#define CLH_AS_FLOAT(u) as_float(u)
#define CLH_AS_UINT(f) as_uint(f)
#else
#include <cstring>
namespace clhair {
namespace gpu {
inline float clh_bits_to_float(clh_u32 u) {
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}
inline clh_u32 clh_float_to_bits(float f) {
  clh_u32 u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}
#define CLH_AS_FLOAT(u) clh_bits_to_float(u)
#define CLH_AS_UINT(f) clh_float_to_bits(f)
#endif

#define CLH_FAST_PI 3.14159265358979f

/* 2^x. Relative error below 5e-7 for x in [-126, 126]; x is clamped to that range (so
 * 2^-126 is the smallest result, the caller treats exact zeros itself). */
CLH_FN float clh_fast_exp2(float x) {
  x = x < -126.0f ? -126.0f : (x > 126.0f ? 126.0f : x);
  const float fl = (float)(clh_i32)x - ((float)(clh_i32)x > x ? 1.0f : 0.0f); /* floor */
  const float f = x - fl;                                                     /* [0, 1) */
  /* degree-5 polynomial of 2^f on [0, 1), fitted for equal relative error (3e-7) */
  float p = 1.8724892e-3f;
  p = p * f + 8.9845192e-3f;
  p = p * f + 5.5848695e-2f;
  p = p * f + 2.4013717e-1f;
  p = p * f + 6.9315684e-1f;
  p = p * f + 9.9999970e-1f;
  return CLH_AS_FLOAT((clh_u32)((clh_i32)fl + 127) << 23) * p;
}

/* log2(x) for finite x > 0 (normal numbers). Absolute error below 3e-7 plus the rounding
 * of the result (6e-8 |log2 x|); x <= 0 returns -126. */
CLH_FN float clh_fast_log2(float x) {
  if (!(x > 1.17549435e-38f)) return -126.0f;
  const clh_u32 bits = CLH_AS_UINT(x);
  float e = (float)((clh_i32)(bits >> 23) - 127);
  float m = CLH_AS_FLOAT((bits & 0x007FFFFFu) | 0x3F800000u); /* [1, 2) */
  if (m > 1.41421356f) { /* centre the mantissa on 1: [sqrt(1/2), sqrt(2)) */
    m *= 0.5f;
    e += 1.0f;
  }
  /* log(m) = 2 atanh(s), s = (m - 1) / (m + 1), |s| <= 0.1716: odd series to s^9 */
  const float s = (m - 1.0f) / (m + 1.0f);
  const float s2 = s * s;
  float p = 1.0f / 9.0f;
  p = p * s2 + 1.0f / 7.0f;
  p = p * s2 + 1.0f / 5.0f;
  p = p * s2 + 1.0f / 3.0f;
  p = p * s2 + 1.0f;
  return e + (2.0f * 1.44269504f) * s * p;
}

/* x^y for x >= 0, y > 0 (0^y = 0). Relative error below 1e-6 * max(1, |y log2 x|)
 * for results above 2^-126. */
CLH_FN float clh_fast_pow(float x, float y) {
  return x > 0.0f ? clh_fast_exp2(y * clh_fast_log2(x)) : 0.0f;
}

/* e^x. Relative error below 1e-6 + 6e-8 |x| for |x| < 87 (the second term is the rounding
 * of x log2(e)). */
CLH_FN float clh_fast_exp(float x) { return clh_fast_exp2(x * 1.44269504f); }

/* e^x for x <= 0 (x > 0 is taken as 0): clh_fast_exp's polynomial evaluated in Estrin's
 * order, three levels of dependent operations instead of Horner's five, for loops that wait
 * on each result (the filter's window). Relative error below 1e-6 + 6e-8 |x| (the second
 * term is the rounding of x log2(e)) for x in [-87, 0]; the two orders differ by float
 * rounding. */
CLH_FN float clh_fast_exp_neg(float x) {
  float t = x * 1.44269504f;
  t = t < -126.0f ? -126.0f : (t > 0.0f ? 0.0f : t);
  const float fl = (float)(clh_i32)t - ((float)(clh_i32)t > t ? 1.0f : 0.0f); /* floor */
  const float f = t - fl;                                                     /* [0, 1) */
  const float f2 = f * f;
  const float p01 = 9.9999970e-1f + 6.9315684e-1f * f;
  const float p23 = 2.4013717e-1f + 5.5848695e-2f * f;
  const float p45 = 8.9845192e-3f + 1.8724892e-3f * f;
  return CLH_AS_FLOAT((clh_u32)((clh_i32)fl + 127) << 23) * (p01 + f2 * (p23 + f2 * p45));
}

/* sin and cos of x together. Absolute error below 1e-6 for |x| < 1e4 (the argument is
 * reduced by multiples of pi/2 in two parts, Cody-Waite). */
CLH_FN void clh_fast_sincos(float x, float* s_out, float* c_out) {
  const float qf = x * 0.636619772f; /* x / (pi / 2) */
  const float q = (float)(clh_i32)(qf + (qf >= 0.0f ? 0.5f : -0.5f));
  const float r = (x - q * 1.5703125f) - q * 4.83826794e-4f; /* x - q pi / 2 */
  const float r2 = r * r;
  /* Taylor polynomials on [-pi/4, pi/4] (errors below 3e-8 there) */
  float sp = -1.9515296e-4f;
  sp = sp * r2 + 8.3321608e-3f;
  sp = sp * r2 - 1.6666654e-1f;
  const float sn = r + r * r2 * sp;
  float cp = 2.4433157e-5f;
  cp = cp * r2 - 1.3887316e-3f;
  cp = cp * r2 + 4.1666645e-2f;
  const float cs = 1.0f - 0.5f * r2 + r2 * r2 * cp;
  const clh_i32 quadrant = ((clh_i32)q) & 3;
  const float s1 = (quadrant & 1) ? cs : sn;
  const float c1 = (quadrant & 1) ? sn : cs;
  *s_out = (quadrant & 2) ? -s1 : s1;
  *c_out = ((quadrant + 1) & 2) ? -c1 : c1;
}

/* acos(x) for x in [-1, 1] (clamped), in [0, pi]. Absolute error below 1e-6: a degree-7
 * polynomial times sqrt(1 - |x|) (Abramowitz & Stegun 4.4.46, 2e-8 in exact arithmetic)
 * and pi - acos(|x|) for x < 0. */
CLH_FN float clh_fast_acos(float x) {
  const float ax = fabs(x) < 1.0f ? fabs(x) : 1.0f;
  float p = -1.2624911e-3f;
  p = p * ax + 6.6700901e-3f;
  p = p * ax - 1.70881256e-2f;
  p = p * ax + 3.08918810e-2f;
  p = p * ax - 5.01743046e-2f;
  p = p * ax + 8.89789874e-2f;
  p = p * ax - 2.145988016e-1f;
  p = p * ax + 1.5707963050f;
  const float r = sqrt(1.0f - ax) * p;
  return x < 0.0f ? CLH_FAST_PI - r : r;
}

/* asin(x) for x in [-1, 1] (clamped): pi/2 - acos(x). Absolute error below 1e-6. */
CLH_FN float clh_fast_asin(float x) { return 0.5f * CLH_FAST_PI - clh_fast_acos(x); }

#ifndef CLH_DEVICE_CODE
}  // namespace gpu
}  // namespace clhair
#endif

#endif /* CLHAIR_FAST_MATH_H */
