/* clh_math.h — small vector helpers for the kernels: 3x4 affine matrices loaded from the
 * row-major float[12] arrays of gpu_types.h, safe normalisation, interpolation, and the
 * pinhole projection of ClhViewGpu. Pure functions, no global state.
 */
#ifndef CLHAIR_CLH_MATH_H
#define CLHAIR_CLH_MATH_H

#include "clhair/gpu_types.h"

#define CLH_PI 3.14159265358979323846f

typedef struct {
  float4 r0, r1, r2;
} clh_mat34;

static inline clh_mat34 clh_load_mat34(__global const float* m) {
  clh_mat34 r;
  r.r0 = vload4(0, m);
  r.r1 = vload4(1, m);
  r.r2 = vload4(2, m);
  return r;
}

static inline float3 clh_xform_point(clh_mat34 m, float3 p) {
  return (float3)(dot(m.r0.xyz, p) + m.r0.w, dot(m.r1.xyz, p) + m.r1.w, dot(m.r2.xyz, p) + m.r2.w);
}

static inline float3 clh_xform_dir(clh_mat34 m, float3 d) {
  return (float3)(dot(m.r0.xyz, d), dot(m.r1.xyz, d), dot(m.r2.xyz, d));
}

/* Normalises v, or returns `fallback` when v is (nearly) zero or not finite. */
static inline float3 clh_normalize_or(float3 v, float3 fallback) {
  float l2 = dot(v, v);
  return (l2 > 1e-30f && l2 < 1e30f) ? v * rsqrt(l2) : fallback;
}

/* The pixel of a 2D launch over the box [box.x, box.z) x [box.y, box.w) of a width x height
 * image (a groom's screen box, clipped by the host), counted from the box's origin; false
 * for the launch's rounded-up tail and anything outside the image. */
static inline bool clh_box_pixel(int4 box, int width, int height, int* x, int* y) {
  *x = box.x + (int)get_global_id(0);
  *y = box.y + (int)get_global_id(1);
  return *x >= 0 && *y >= 0 && *x < box.z && *y < box.w && *x < width && *y < height;
}

static inline float clh_saturate(float x) { return clamp(x, 0.0f, 1.0f); }

static inline float clh_smoothstep01(float x) {
  x = clh_saturate(x);
  return x * x * (3.0f - 2.0f * x);
}

/* A 3-vector (a direction, or an RGB triple) for the shading code that the host compiles too
 * (host/groom/hair_bsdf_cpu.h gives the same operations on a struct, the same arithmetic in
 * the same order per component). On the device it is a float3, so a CPU compiler does the
 * three components in one SIMD instruction; the shading kernel is not vectorized across
 * work-items on PoCL either way (DESIGN.md, "Vectorizable kernels"), and on a GPU a float3
 * operation is three scalar ones. Component-wise, the results are the same bits as three
 * scalar operations. */
typedef float3 clh_v3;

static inline clh_v3 clh_v3_make(float x, float y, float z) { return (float3)(x, y, z); }
static inline clh_v3 clh_v3_splat(float a) { return (float3)(a); }
static inline clh_v3 clh_v3_add(clh_v3 a, clh_v3 b) { return a + b; }
static inline clh_v3 clh_v3_sub(clh_v3 a, clh_v3 b) { return a - b; }
static inline clh_v3 clh_v3_mul(clh_v3 a, clh_v3 b) { return a * b; }
static inline clh_v3 clh_v3_scale(clh_v3 a, float s) { return a * s; }
static inline float clh_v3_dot(clh_v3 a, clh_v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline clh_v3 clh_v3_fmax(clh_v3 a, float m) { return fmax(a, m); }
static inline clh_v3 clh_v3_div(clh_v3 a, clh_v3 b) { return a / b; }
static inline clh_v3 clh_v3_sqrt(clh_v3 a) { return sqrt(a); }
static inline clh_v3 clh_v3_fmin(clh_v3 a, float m) { return fmin(a, m); }
static inline clh_v3 clh_v3_max(clh_v3 a, clh_v3 b) { return fmax(a, b); }
static inline clh_v3 clh_v3_clamp(clh_v3 a, float lo, float hi) { return clamp(a, lo, hi); }
/* per component: x < t ? a : b, x > t ? a : b */
static inline clh_v3 clh_v3_if_less(clh_v3 x, float t, clh_v3 a, clh_v3 b) {
  return select(b, a, isless(x, (float3)(t)));
}
static inline clh_v3 clh_v3_if_greater(clh_v3 x, float t, clh_v3 a, clh_v3 b) {
  return select(b, a, isgreater(x, (float3)(t)));
}
static inline bool clh_v3_all_less(clh_v3 x, float t) { return all(isless(x, (float3)(t))) != 0; }
static inline bool clh_v3_any_greater(clh_v3 x, float t) {
  return any(isgreater(x, (float3)(t))) != 0;
}
static inline clh_v3 clh_v3_fabs(clh_v3 a) { return fabs(a); }
static inline clh_v3 clh_v3_from(float3 a) { return a; }
static inline float3 clh_v3_f3(clh_v3 a) { return a; }
/* clh_fast_exp (clhair/fast_math.h) of each lane of a float3 or a float4 (clh_lanes_exp3,
 * clh_lanes_exp4), the same operations lane by lane. */
#define CLH_LANES_EXP(N)                                                       \
  static inline float##N clh_lanes_exp##N(float##N v) {                        \
    float##N x = v * 1.44269504f;                                              \
    x = x < -126.0f ? -126.0f : (x > 126.0f ? 126.0f : x);                     \
    const float##N t = convert_float##N(convert_int##N(x));                    \
    const float##N fl = t - select((float##N)(0.0f), (float##N)(1.0f), t > x); \
    const float##N f = x - fl;                                                 \
    float##N p = (float##N)(1.8724892e-3f);                                    \
    p = p * f + 8.9845192e-3f;                                                 \
    p = p * f + 5.5848695e-2f;                                                 \
    p = p * f + 2.4013717e-1f;                                                 \
    p = p * f + 6.9315684e-1f;                                                 \
    p = p * f + 9.9999970e-1f;                                                 \
    return as_float##N(as_uint##N(convert_int##N(fl) + 127) << 23) * p;        \
  }
CLH_LANES_EXP(3)
CLH_LANES_EXP(4)
static inline clh_v3 clh_v3_exp(clh_v3 v) { return clh_lanes_exp3(v); }
/* clh_fast_log2 of each component, the same operations lane by lane */
static inline clh_v3 clh_v3_log2(clh_v3 x) {
  const uint3 bits = as_uint3(x);
  float3 e = convert_float3(as_int3(bits >> 23) - 127);
  float3 m = as_float3((bits & 0x007FFFFFu) | 0x3F800000u);
  const int3 big = m > 1.41421356f;
  m = select(m, m * 0.5f, big);
  e = select(e, e + 1.0f, big);
  const float3 s = (m - 1.0f) / (m + 1.0f);
  const float3 s2 = s * s;
  float3 p = (float3)(1.0f / 9.0f);
  p = p * s2 + 1.0f / 7.0f;
  p = p * s2 + 1.0f / 5.0f;
  p = p * s2 + 1.0f / 3.0f;
  p = p * s2 + 1.0f;
  return select((float3)(-126.0f), e + (2.0f * 1.44269504f) * s * p, x > 1.17549435e-38f);
}
/* clh_fast_sincos of each component, the same operations lane by lane */
static inline void clh_v3_sincos(clh_v3 x, clh_v3* s_out, clh_v3* c_out) {
  const float3 qf = x * 0.636619772f;
  const float3 q =
      convert_float3(convert_int3(qf + select((float3)(-0.5f), (float3)(0.5f), qf >= 0.0f)));
  const float3 r = (x - q * 1.5703125f) - q * 4.83826794e-4f;
  const float3 r2 = r * r;
  float3 sp = (float3)(-1.9515296e-4f);
  sp = sp * r2 + 8.3321608e-3f;
  sp = sp * r2 - 1.6666654e-1f;
  const float3 sn = r + r * r2 * sp;
  float3 cp = (float3)(2.4433157e-5f);
  cp = cp * r2 - 1.3887316e-3f;
  cp = cp * r2 + 4.1666645e-2f;
  const float3 cs = 1.0f - 0.5f * r2 + r2 * r2 * cp;
  const int3 quadrant = convert_int3(q) & 3;
  const int3 odd = (quadrant & 1) != 0;
  const float3 s1 = select(sn, cs, odd), c1 = select(cs, sn, odd);
  *s_out = select(s1, -s1, (quadrant & 2) != 0);
  *c_out = select(c1, -c1, ((quadrant + 1) & 2) != 0);
}
/* v / |v| (v must not be zero) */
static inline clh_v3 clh_v3_unit(clh_v3 v) {
  return clh_v3_scale(v, 1.0f / sqrt(clh_v3_dot(v, v)));
}
/* the affine 3x4 row-major matrix m (12 floats) applied to point p, without vector loads */
static inline clh_v3 clh_v3_xform_point(__global const float* m, clh_v3 p) {
  return clh_v3_make(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3],
                     m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
                     m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]);
}

#endif /* CLHAIR_CLH_MATH_H */
