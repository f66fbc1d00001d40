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

#define CLHAIR_CLH_MATH_H
#include "../../kernels/common/hair_bsdf.h"
#include "../../kernels/common/hair_dual.h"

}  // namespace cpu_bsdf
}  // namespace clhair
