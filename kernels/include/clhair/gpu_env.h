/* gpu_env.h — the host/device contract for environment ("probe") lighting.
 *
 * Lipp et al. 2026 §3.4 light hair with a pre-filtered environment map for the specular
 * lobes and 9-coefficient spherical-harmonics irradiance for the diffuse part. This header
 * holds what host and kernels share for that: the level table of the prefiltered
 * equirectangular map, the procedural-sky parameters, the direction <-> (u, v) mapping and
 * the SH basis. Like gpu_types.h it is written in the common subset of C++17 and OpenCL C
 * 1.2 (no float3 members, explicit padding, sizes multiples of 16 bytes).
 *
 * Equirectangular convention (world space, +y up), texel (i, j) of a W x H level has its
 * centre at u = (i + 0.5) / W, v = (j + 0.5) / H, row j = 0 is the top (+y) row:
 *   u = 0.5 + atan2(x, -z) / (2 pi)        v = acos(y) / pi
 *   x = sin(pi v) sin(phi),  y = cos(pi v),  z = -sin(pi v) cos(phi),  phi = 2 pi (u - 0.5)
 * so the image centre looks along -z, u = 0.75 is +x, u = 0.25 is -x, u = 0 / 1 is +z
 * (the seam). Seen from inside the sphere facing -z the image is not mirrored.
 *
 * SH layout: 9 radiance coefficients L_lm, RGB interleaved, sh[3 * k + c] with
 *   k: 0 (0,0)  1 (1,-1)  2 (1,0)  3 (1,1)  4 (2,-2)  5 (2,-1)  6 (2,0)  7 (2,1)  8 (2,2)
 * and the real basis of Ramamoorthi & Hanrahan 2001 (Eq. 3) written in the world x, y, z
 * of this file (their z axis is our world z; the basis is complete, so the choice of axes
 * does not matter as long as projection and evaluation agree — both use clh_sh9_basis).
 */
#ifndef CLHAIR_GPU_ENV_H
#define CLHAIR_GPU_ENV_H

#include "clhair/gpu_types.h"

#ifndef CLH_DEVICE_CODE
#include <cmath>
namespace clhair {
namespace gpu {
using std::acos;
using std::atan2;
using std::cos;
using std::sin;
#endif

#define CLH_ENV_PI 3.14159265358979323846f
#define CLH_ENV_MAX_LEVELS 16 /* prefiltered levels, and source-pyramid levels */
#define CLH_ENV_SH_FLOATS 27  /* 9 coefficients x RGB */

/* ---- one level of an equirectangular map inside a shared float4 texel buffer, 16 bytes
 * offset    : index of the level's first texel (row-major, top row first)
 * width     : texels per row, always 2 * height
 * height    : rows
 * roughness : GGX alpha the level is prefiltered for (D(h) = a^2 / (pi ((n.h)^2 (a^2 - 1)
 *             + 1)^2)); 0 for the levels of the unfiltered source pyramid.
 * Invariants (checked by the host before upload): levels sorted by increasing roughness,
 * offset + width * height <= texel count of the buffer, width = 2 * height >= 2.          */
typedef struct {
  clh_u32 offset;
  clh_u32 width;
  clh_u32 height;
  float roughness;
} ClhEnvLevel;

/* ---- procedural sky (env_sky in kernels/env.cl), 96 bytes -----------------------------
 * sun_dir      : xyz unit vector toward the sun;  w: cos of the disc's angular radius
 * sun_radiance : rgb radiance inside the disc (host: irradiance / disc solid angle)
 * zenith, horizon, ground : rgb radiance; the sky blends horizon -> zenith with
 *                (dir.y)^shape.x, the ground blends horizon -> ground over
 *                -dir.y in [0, shape.y]
 * shape        : x gradient exponent, y ground blend width, z/w unused                   */
typedef struct {
  float sun_dir[4];
  float sun_radiance[4];
  float zenith[4];
  float horizon[4];
  float ground[4];
  float shape[4];
} ClhEnvSkyGpu;

CLH_FN float clh_env_clamp(float x, float lo, float hi) { return fmin(fmax(x, lo), hi); }

/* Direction (need not be normalised, must be non-zero) -> (u, v) in [0, 1]^2. */
CLH_FN void clh_env_dir_to_uv(float x, float y, float z, float* uv) {
  float len = sqrt(x * x + y * y + z * z);
  float cy = len > 0.0f ? y / len : 1.0f;
  uv[0] = clh_env_clamp(0.5f + atan2(x, -z) * (0.5f / CLH_ENV_PI), 0.0f, 1.0f);
  uv[1] = clh_env_clamp(acos(clh_env_clamp(cy, -1.0f, 1.0f)) * (1.0f / CLH_ENV_PI), 0.0f, 1.0f);
}

/* (u, v) -> unit direction written to d[0..2]. */
CLH_FN void clh_env_uv_to_dir(float u, float v, float* d) {
  float phi = 2.0f * CLH_ENV_PI * (u - 0.5f);
  float theta = CLH_ENV_PI * v;
  float st = sin(theta);
  d[0] = st * sin(phi);
  d[1] = cos(theta);
  d[2] = -st * cos(phi);
}

/* Solid angle of one texel of row j in a W x H equirectangular level (exact for the cell
 * between the row's latitude lines). Sums to 4 pi over the map. */
CLH_FN float clh_env_texel_solid_angle(clh_u32 j, clh_u32 width, clh_u32 height) {
  float t0 = CLH_ENV_PI * (float)j / (float)height;
  float t1 = CLH_ENV_PI * (float)(j + 1u) / (float)height;
  return (2.0f * CLH_ENV_PI / (float)width) * (cos(t0) - cos(t1));
}

/* The 9 real SH basis functions at unit direction (x, y, z), R&H 2001 Eq. 3 constants. */
CLH_FN void clh_sh9_basis(float x, float y, float z, float* b) {
  b[0] = 0.282095f;
  b[1] = 0.488603f * y;
  b[2] = 0.488603f * z;
  b[3] = 0.488603f * x;
  b[4] = 1.092548f * x * y;
  b[5] = 1.092548f * y * z;
  b[6] = 0.315392f * (3.0f * z * z - 1.0f);
  b[7] = 1.092548f * x * z;
  b[8] = 0.546274f * (x * x - y * y);
}

/* Irradiance E(n) = integral of L(w) max(0, n.w) dw from the 9 radiance coefficients of
 * one colour channel (stride 3 in `sh`), R&H 2001 Eq. 13 with c1..c5 of their Eq. 12.
 * No 1/pi: a Lambertian surface of albedo rho reflects rho / pi * E. */
CLH_FN float clh_sh9_irradiance(const float* sh, float x, float y, float z) {
  const float c1 = 0.429043f, c2 = 0.511664f, c3 = 0.743125f, c4 = 0.886227f, c5 = 0.247708f;
  return c1 * sh[3 * 8] * (x * x - y * y) + c3 * sh[3 * 6] * z * z + c4 * sh[3 * 0] -
         c5 * sh[3 * 6] + 2.0f * c1 * (sh[3 * 4] * x * y + sh[3 * 7] * x * z + sh[3 * 5] * y * z) +
         2.0f * c2 * (sh[3 * 3] * x + sh[3 * 1] * y + sh[3 * 2] * z);
}

/* GGX (Trowbridge-Reitz) normal distribution for cos(theta_h) and alpha. */
CLH_FN float clh_env_ggx_d(float cos_h, float alpha) {
  float a2 = alpha * alpha;
  float t = cos_h * cos_h * (a2 - 1.0f) + 1.0f;
  return a2 / (CLH_ENV_PI * t * t);
}

#ifndef CLH_DEVICE_CODE
} /* namespace gpu */
} /* namespace clhair */
#endif

#endif /* CLHAIR_GPU_ENV_H */
