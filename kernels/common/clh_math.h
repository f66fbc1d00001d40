/* clh_math.h — small vector helpers for the kernels: 3x4 affine matrices loaded from the
 * row-major float[12] arrays of gpu_types.h, safe normalisation, interpolation, and the
 * pinhole projection of ClhViewGpu. Pure functions, no global state.
 */
#ifndef CLHAIR_CLH_MATH_H
#define CLHAIR_CLH_MATH_H

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

static inline float clh_saturate(float x) { return clamp(x, 0.0f, 1.0f); }

static inline float clh_smoothstep01(float x) {
  x = clh_saturate(x);
  return x * x * (3.0f - 2.0f * x);
}

#endif /* CLHAIR_CLH_MATH_H */
