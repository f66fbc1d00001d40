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

/* A scalar 3-vector (a direction, or an RGB triple) for the kernels CPU compilers vectorize
 * across work-items: vector types (float3, float4) in a kernel stop PoCL's vectorizer
 * (DESIGN.md, "Vectorizable kernels"), a struct of floats does not. */
typedef struct {
  float x, y, z;
} clh_v3;

static inline clh_v3 clh_v3_make(float x, float y, float z) {
  clh_v3 r;
  r.x = x;
  r.y = y;
  r.z = z;
  return r;
}
static inline clh_v3 clh_v3_splat(float a) { return clh_v3_make(a, a, a); }
static inline clh_v3 clh_v3_add(clh_v3 a, clh_v3 b) {
  return clh_v3_make(a.x + b.x, a.y + b.y, a.z + b.z);
}
static inline clh_v3 clh_v3_sub(clh_v3 a, clh_v3 b) {
  return clh_v3_make(a.x - b.x, a.y - b.y, a.z - b.z);
}
static inline clh_v3 clh_v3_mul(clh_v3 a, clh_v3 b) {
  return clh_v3_make(a.x * b.x, a.y * b.y, a.z * b.z);
}
static inline clh_v3 clh_v3_scale(clh_v3 a, float s) {
  return clh_v3_make(a.x * s, a.y * s, a.z * s);
}
static inline float clh_v3_dot(clh_v3 a, clh_v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline clh_v3 clh_v3_fmax(clh_v3 a, float m) {
  return clh_v3_make(fmax(a.x, m), fmax(a.y, m), fmax(a.z, m));
}
static inline clh_v3 clh_v3_from(float3 a) { return clh_v3_make(a.x, a.y, a.z); }
static inline float3 clh_v3_f3(clh_v3 a) { return (float3)(a.x, a.y, a.z); }
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
