// hair_bsdf_cpu.h — the shading kernel's hair BSDF (kernels/common/hair_bsdf.h) compiled
// as C++ for the path-traced reference, so the reference scatters light with exactly the
// model and parameters the shading pass evaluates (one source, as pbrt-v4 shares its
// BSDFs between CPU and GPU).
//
// hair_bsdf.h needs from the kernels' clh_math.h only its scalar 3-vector (clh_v3) and a
// few operations on it; clh_math.h itself also holds OpenCL vector types, so its include
// guard is set here and those operations are given again below, the same arithmetic in
// the same order. The elementary functions are clhair/fast_math.h's, shared with the
// kernels already. Everything lands in namespace clhair::cpu_bsdf.
#pragma once

#include <cmath>

#include "clhair/fast_math.h"
#include "clhair/gpu_types.h"

namespace clhair {
namespace cpu_bsdf {

using gpu::clh_fast_acos;
using gpu::clh_fast_asin;
using gpu::clh_fast_exp;
using gpu::clh_fast_log2;
using gpu::clh_fast_sincos;
using std::fabs;
using std::fmax;
using std::fmin;
using std::sqrt;

inline float clamp(float x, float lo, float hi) { return fmin(fmax(x, lo), hi); }

struct clh_v3 {
  float x, y, z;
};
inline clh_v3 clh_v3_make(float x, float y, float z) { return clh_v3{x, y, z}; }
inline clh_v3 clh_v3_splat(float a) { return clh_v3_make(a, a, a); }
inline clh_v3 clh_v3_add(clh_v3 a, clh_v3 b) {
  return clh_v3_make(a.x + b.x, a.y + b.y, a.z + b.z);
}
inline clh_v3 clh_v3_sub(clh_v3 a, clh_v3 b) {
  return clh_v3_make(a.x - b.x, a.y - b.y, a.z - b.z);
}
inline clh_v3 clh_v3_mul(clh_v3 a, clh_v3 b) {
  return clh_v3_make(a.x * b.x, a.y * b.y, a.z * b.z);
}
inline clh_v3 clh_v3_scale(clh_v3 a, float s) { return clh_v3_make(a.x * s, a.y * s, a.z * s); }
inline float clh_v3_dot(clh_v3 a, clh_v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline clh_v3 clh_v3_fmax(clh_v3 a, float m) {
  return clh_v3_make(fmax(a.x, m), fmax(a.y, m), fmax(a.z, m));
}
inline clh_v3 clh_v3_unit(clh_v3 v) { return clh_v3_scale(v, 1.0f / sqrt(clh_v3_dot(v, v))); }
// the operators OpenCL C has on float3, for the code written with them (hair_bsdf.h)
inline clh_v3 operator+(clh_v3 a, clh_v3 b) { return clh_v3_add(a, b); }
inline clh_v3 operator-(clh_v3 a, clh_v3 b) { return clh_v3_sub(a, b); }
inline clh_v3 operator*(clh_v3 a, clh_v3 b) { return clh_v3_mul(a, b); }
inline clh_v3 clh_v3_div(clh_v3 a, clh_v3 b) {
  return clh_v3_make(a.x / b.x, a.y / b.y, a.z / b.z);
}
inline clh_v3 operator/(clh_v3 a, clh_v3 b) { return clh_v3_div(a, b); }
inline clh_v3 operator-(clh_v3 a) { return clh_v3_make(-a.x, -a.y, -a.z); }
inline clh_v3 operator+(clh_v3 a, float s) { return a + clh_v3_splat(s); }
inline clh_v3 operator+(float s, clh_v3 a) { return clh_v3_splat(s) + a; }
inline clh_v3 operator-(clh_v3 a, float s) { return a - clh_v3_splat(s); }
inline clh_v3 operator-(float s, clh_v3 a) { return clh_v3_splat(s) - a; }
inline clh_v3 operator*(clh_v3 a, float s) { return a * clh_v3_splat(s); }
inline clh_v3 operator*(float s, clh_v3 a) { return clh_v3_splat(s) * a; }
inline clh_v3 operator/(clh_v3 a, float s) { return a / clh_v3_splat(s); }
inline clh_v3 operator/(float s, clh_v3 a) { return clh_v3_splat(s) / a; }
inline clh_v3 clh_v3_sqrt(clh_v3 a) { return clh_v3_make(sqrt(a.x), sqrt(a.y), sqrt(a.z)); }
inline clh_v3 clh_v3_fmin(clh_v3 a, float m) {
  return clh_v3_make(fmin(a.x, m), fmin(a.y, m), fmin(a.z, m));
}
inline clh_v3 clh_v3_max(clh_v3 a, clh_v3 b) {
  return clh_v3_make(fmax(a.x, b.x), fmax(a.y, b.y), fmax(a.z, b.z));
}
inline clh_v3 clh_v3_clamp(clh_v3 a, float lo, float hi) {
  return clh_v3_make(clamp(a.x, lo, hi), clamp(a.y, lo, hi), clamp(a.z, lo, hi));
}
inline clh_v3 clh_v3_if_less(clh_v3 x, float t, clh_v3 a, clh_v3 b) {
  return clh_v3_make(x.x < t ? a.x : b.x, x.y < t ? a.y : b.y, x.z < t ? a.z : b.z);
}
inline clh_v3 clh_v3_if_greater(clh_v3 x, float t, clh_v3 a, clh_v3 b) {
  return clh_v3_make(x.x > t ? a.x : b.x, x.y > t ? a.y : b.y, x.z > t ? a.z : b.z);
}
inline bool clh_v3_all_less(clh_v3 x, float t) { return x.x < t && x.y < t && x.z < t; }
inline bool clh_v3_any_greater(clh_v3 x, float t) { return x.x > t || x.y > t || x.z > t; }
inline clh_v3 clh_v3_fabs(clh_v3 a) { return clh_v3_make(fabs(a.x), fabs(a.y), fabs(a.z)); }
inline clh_v3 clh_v3_log2(clh_v3 v) {
  return clh_v3_make(clh_fast_log2(v.x), clh_fast_log2(v.y), clh_fast_log2(v.z));
}
inline void clh_v3_sincos(clh_v3 v, clh_v3* s, clh_v3* c) {
  clh_fast_sincos(v.x, &s->x, &c->x);
  clh_fast_sincos(v.y, &s->y, &c->y);
  clh_fast_sincos(v.z, &s->z, &c->z);
}
inline clh_v3 clh_v3_exp(clh_v3 v) {
  return clh_v3_make(clh_fast_exp(v.x), clh_fast_exp(v.y), clh_fast_exp(v.z));
}

#define CLHAIR_CLH_MATH_H
#include "../../kernels/common/hair_bsdf.h"
#include "../../kernels/common/hair_dual.h"

}  // namespace cpu_bsdf
}  // namespace clhair
