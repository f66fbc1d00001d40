/* env_lookup.h — environment ("probe") lighting queries for the shading kernels.
 *
 * Lipp et al. 2026 §3.4: the specular hair lobes (R and TRT, each approximated by one GGX
 * lobe) query a pre-filtered environment map; the diffuse part uses 9-coefficient SH
 * irradiance evaluated at a fibre normal turned toward the viewer. The data come from
 * host/lighting/environment.cpp (built by kernels/env.cl at load):
 *   texels_g : float4 texels of every prefiltered level, one buffer (rgb used, w ignored)
 *   levels_g : ClhEnvLevel[level_count], increasing GGX alpha (gpu_env.h)
 *   sh_g     : 27 floats, the radiance SH coefficients L_lm, RGB interleaved
 * Directions are world space (+y up); the (u, v) convention is documented in gpu_env.h.
 *
 * Bounds: the level table is validated on the host (offset + width * height within the
 * texel buffer, width, height >= 1), so the texel indices computed here — clamped to each
 * level's own rectangle — stay inside the buffer; level_count is clamped to
 * CLH_ENV_MAX_LEVELS. NaN or zero directions fall back to +y, NaN roughness to level 0.
 */
#ifndef CLHAIR_ENV_LOOKUP_H
#define CLHAIR_ENV_LOOKUP_H

#include "clhair/gpu_env.h"

/* Bilinear lookup at (u, v) in one level: wraps in u (the seam at u = 0 / 1), clamps in v
 * (the poles). Texel centres sit at ((i + 0.5) / W, (j + 0.5) / H). */
static inline float3 clh_env_bilinear(__global const float4* texels_g, ClhEnvLevel lv, float u,
                                      float v) {
  uint w = max(lv.width, 1u), h = max(lv.height, 1u);
  float x = clamp(u, 0.0f, 1.0f) * (float)w - 0.5f; /* in [-0.5, w - 0.5] */
  float y = clamp(clamp(v, 0.0f, 1.0f) * (float)h - 0.5f, 0.0f, (float)(h - 1u));
  float fx = floor(x), fy = floor(y);
  float tx = x - fx, ty = y - fy;
  int ix = (int)fx; /* in [-1, w - 1] */
  uint x0 = ix < 0 ? w - 1u : min((uint)ix, w - 1u);
  uint x1 = x0 + 1u >= w ? 0u : x0 + 1u;
  uint y0 = min((uint)fy, h - 1u);
  uint y1 = min(y0 + 1u, h - 1u);
  __global const float4* row0 = texels_g + lv.offset + (size_t)y0 * w;
  __global const float4* row1 = texels_g + lv.offset + (size_t)y1 * w;
  float3 a = mix(row0[x0].xyz, row0[x1].xyz, tx);
  float3 b = mix(row1[x0].xyz, row1[x1].xyz, tx);
  return mix(a, b, ty);
}

/* Prefiltered radiance around `dir` for GGX alpha `roughness`: bilinear in (u, v), linear
 * in alpha between the two levels that bracket it, clamped to the first / last level. */
static inline float3 clh_env_radiance(__global const float4* texels_g,
                                      __global const ClhEnvLevel* levels_g, uint level_count,
                                      float3 dir, float roughness) {
  uint n = min(level_count, (uint)CLH_ENV_MAX_LEVELS);
  if (n == 0u) return (float3)(0.0f);
  float l2 = dot(dir, dir);
  float3 d = (l2 > 1e-30f && l2 < 1e30f) ? dir * rsqrt(l2) : (float3)(0.0f, 1.0f, 0.0f);
  float uv[2];
  clh_env_dir_to_uv(d.x, d.y, d.z, uv);
  float r = fmax(roughness, 0.0f); /* fmax drops a NaN */
  ClhEnvLevel lo = levels_g[0];
  if (!(r > lo.roughness) || n == 1u) return clh_env_bilinear(texels_g, lo, uv[0], uv[1]);
  for (uint i = 1u; i < n; ++i) {
    ClhEnvLevel hi = levels_g[i];
    if (r < hi.roughness) {
      float t = (r - lo.roughness) / (hi.roughness - lo.roughness);
      return mix(clh_env_bilinear(texels_g, lo, uv[0], uv[1]),
                 clh_env_bilinear(texels_g, hi, uv[0], uv[1]), t);
    }
    lo = hi;
  }
  return clh_env_bilinear(texels_g, lo, uv[0], uv[1]);
}

/* Irradiance E(n) = integral of L(w) max(0, n.w) dw from the 9 SH coefficients
 * (Ramamoorthi & Hanrahan 2001 Eq. 13). It does NOT include 1/pi: a Lambertian surface of
 * albedo rho reflects rho / pi * E; a constant environment L gives E = pi * L. */
static inline float3 clh_env_irradiance(__global const float* sh_g, float3 n) {
  float c[CLH_ENV_SH_FLOATS];
  for (int i = 0; i < CLH_ENV_SH_FLOATS; ++i) c[i] = sh_g[i];
  float l2 = dot(n, n);
  float3 d = (l2 > 1e-30f && l2 < 1e30f) ? n * rsqrt(l2) : (float3)(0.0f, 1.0f, 0.0f);
  float3 e =
      (float3)(clh_sh9_irradiance(c, d.x, d.y, d.z), clh_sh9_irradiance(c + 1, d.x, d.y, d.z),
               clh_sh9_irradiance(c + 2, d.x, d.y, d.z));
  /* nine bands cannot hold negative radiance exactly; ringing must not make light negative */
  return fmax(e, (float3)(0.0f));
}

#endif /* CLHAIR_ENV_LOOKUP_H */
