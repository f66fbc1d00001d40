/* env.cl — load-time kernels for environment ("probe") lighting (Lipp et al. 2026 §3.4).
 *
 * Run once when an environment is loaded (host/lighting/environment.cpp), in this order:
 *   env_sky         procedural sky (sun disc + sky gradient + ground) into the source map
 *   env_downsample  source pyramid: each level is a solid-angle-weighted box average of the
 *                   previous one (integer partition of the source texels, any size)
 *   env_prefilter   one prefiltered level per dispatch: per output texel, the GGX lobe
 *                   around its direction under the N = V = R assumption, importance
 *                   sampled with a fixed Hammersley set; each sample reads the source
 *                   pyramid at the level its PDF asks for (filtered importance sampling,
 *                   Krivanek & Colbert 2008), which removes fireflies from small bright
 *                   sources with few samples. Weighted by n.l (the split-sum estimator).
 *   env_sh_rows     SH projection, one work-item per source row (solid-angle weighted)
 *   env_sh_reduce   sums the per-row partial sums in row order, one work-item per float
 * env_query evaluates the lookup functions of env_lookup.h for a list of directions (tests
 * and debugging); env_layout reports the struct sizes of gpu_env.h. Every result is deterministic:
 * fixed sample sets, fixed summation order, no atomics, so an environment is bit-identical from run
 * to run.
 *
 * Maps are equirectangular float4 (gpu_env.h for the (u, v) convention). The rotation
 * (rot_cos, rot_sin) = (cos b, sin b) places the source rotated by b about +y: the source
 * direction s appears at world direction R_y(b) s. `intensity` scales all outputs.
 */
#include "clhair/gpu_env.h"
#include "clhair/gpu_types.h"
#include "env_lookup.h"

#ifndef ENV_WG
#define ENV_WG 64 /* work-group size of every 1D kernel here */
#endif
#ifndef ENV_SAMPLES
#define ENV_SAMPLES 512 /* most GGX samples per prefiltered texel (local-memory table) */
#endif
#ifndef ENV_LOD_BIAS
/* added to the filtered-IS source level; +1 (as Karis 2013) trades a little blur for a
 * result free of the fixed sample pattern around small bright sources */
#define ENV_LOD_BIAS 1.0f
#endif
#ifndef ENV_SKY_SS
#define ENV_SKY_SS 4 /* env_sky supersamples per texel and axis (antialiases the sun disc) */
#endif

/* R_y(b) d for (c, s) = (cos b, sin b); pass -s for the inverse. */
static inline float3 env_rotate_y(float3 d, float c, float s) {
  return (float3)(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
}

static inline float3 env_uv_dir(float u, float v) {
  float d[3];
  clh_env_uv_to_dir(u, v, d);
  return (float3)(d[0], d[1], d[2]);
}

/* True when the level lies inside a buffer of `count` texels. */
static inline bool env_level_ok(ClhEnvLevel lv, uint count) {
  return lv.width > 0u && lv.height > 0u && lv.offset <= count &&
         (ulong)lv.width * lv.height <= (ulong)(count - lv.offset);
}

/* Van der Corput radical inverse in base 2 (the second Hammersley coordinate), exact for
 * k < 2^24. A loop rather than the bit-swap idiom: LLVM turns that into llvm.bitreverse,
 * which Oclgrind cannot run. */
static inline float env_radical_inverse(uint k) {
  float r = 0.0f, f = 0.5f;
  for (uint x = k; x != 0u; x >>= 1) {
    if (x & 1u) r += f;
    f *= 0.5f;
  }
  return r;
}

/* ---- procedural sky ------------------------------------------------------------------ */

/* float4 arithmetic, w unused (the ClhEnvSkyGpu colours are float[4]). */
static inline float4 env_sky_radiance(__global const ClhEnvSkyGpu* sky_g, float3 d) {
  float4 shape = vload4(0, sky_g->shape);
  float4 horizon = vload4(0, sky_g->horizon);
  float4 c;
  if (d.y >= 0.0f) {
    c = mix(horizon, vload4(0, sky_g->zenith), pow(d.y, fmax(shape.x, 1e-3f)));
  } else {
    c = mix(horizon, vload4(0, sky_g->ground), clh_clamp01(-d.y / fmax(shape.y, 1e-6f)));
  }
  float4 sun = vload4(0, sky_g->sun_dir);
  if (d.x * sun.x + d.y * sun.y + d.z * sun.z >= sun.w) c += vload4(0, sky_g->sun_radiance);
  return c;
}

__kernel __attribute__((reqd_work_group_size(ENV_WG, 1, 1))) void env_sky(
    __global const ClhEnvSkyGpu* sky_g, __global float4* out_g, uint out_count, uint width,
    uint height) {
  uint gid = (uint)get_global_id(0);
  if (width == 0u || height == 0u || (ulong)width * height > out_count) return;
  if (gid >= width * height) return;
  uint i = gid % width, j = gid / width;
  float4 acc = (float4)(0.0f);
  for (uint sy = 0u; sy < ENV_SKY_SS; ++sy) {
    for (uint sx = 0u; sx < ENV_SKY_SS; ++sx) {
      float u = ((float)i + ((float)sx + 0.5f) / (float)ENV_SKY_SS) / (float)width;
      float v = ((float)j + ((float)sy + 0.5f) / (float)ENV_SKY_SS) / (float)height;
      acc += env_sky_radiance(sky_g, env_uv_dir(u, v));
    }
  }
  float k = 1.0f / (float)(ENV_SKY_SS * ENV_SKY_SS);
  out_g[gid] = (float4)(acc.x * k, acc.y * k, acc.z * k, 1.0f);
}

/* ---- source pyramid ------------------------------------------------------------------ */

/* dst texel (x, y) averages the source block [x*sw/dw, (x+1)*sw/dw) x [y*sh/dh, ...),
 * each source row weighted by its texel solid angle, so the map keeps its power. */
__kernel __attribute__((reqd_work_group_size(ENV_WG, 1, 1))) void env_downsample(
    __global float4* pyr_g, uint pyr_count, uint src_offset, uint src_w, uint src_h,
    uint dst_offset, uint dst_w, uint dst_h) {
  uint gid = (uint)get_global_id(0);
  ClhEnvLevel src = {src_offset, src_w, src_h, 0.0f};
  ClhEnvLevel dst = {dst_offset, dst_w, dst_h, 0.0f};
  if (!env_level_ok(src, pyr_count) || !env_level_ok(dst, pyr_count)) return;
  if (dst_w > src_w || dst_h > src_h) return;
  if (gid >= dst_w * dst_h) return;
  uint x = gid % dst_w, y = gid / dst_w;
  uint c0 = x * src_w / dst_w, c1 = max((x + 1u) * src_w / dst_w, c0 + 1u);
  uint r0 = y * src_h / dst_h, r1 = max((y + 1u) * src_h / dst_h, r0 + 1u);
  c1 = min(c1, src_w);
  r1 = min(r1, src_h);
  float4 acc = (float4)(0.0f);
  float wsum = 0.0f;
  for (uint r = r0; r < r1; ++r) {
    float wr = clh_env_texel_solid_angle(r, src_w, src_h);
    __global const float4* row = pyr_g + src_offset + (size_t)r * src_w;
    float4 racc = (float4)(0.0f);
    for (uint c = c0; c < c1; ++c) racc += row[c];
    acc += wr * racc;
    wsum += wr * (float)(c1 - c0);
  }
  float inv = wsum > 0.0f ? 1.0f / wsum : 0.0f;
  pyr_g[dst_offset + gid] = (float4)(acc.x * inv, acc.y * inv, acc.z * inv, 1.0f);
}

/* ---- GGX prefiltering ---------------------------------------------------------------- */

/* Trilinear read of the source pyramid at (u, v) and fractional level `lod`. */
static inline float3 env_sample_pyramid(__global const float4* pyr_g,
                                        __global const ClhEnvLevel* pyr_levels_g, uint n, float u,
                                        float v, float lod) {
  float l = clamp(lod, 0.0f, (float)(n - 1u));
  float fl = floor(l);
  uint l0 = min((uint)fl, n - 1u);
  uint l1 = min(l0 + 1u, n - 1u);
  float t = l - fl;
  float3 a = clh_env_bilinear(pyr_g, pyr_levels_g[l0], u, v);
  if (!(t > 0.0f) || l1 == l0) return a;
  return mix(a, clh_env_bilinear(pyr_g, pyr_levels_g[l1], u, v), t);
}

/* One work-item per texel of the output level (out_offset, out_w, out_h) for GGX alpha,
 * with N = sample_count (<= ENV_SAMPLES) samples. Sample k: cos^2(theta_h) from xi = (k + 0.5) / N
 * by inverting the GGX CDF, phi from the radical inverse of k; l = 2 (n.h) h - n. Its PDF over l is
 * D(h) / 4 (n = v), so it covers Omega_s = 4 / (N D(h)) steradians and reads the pyramid level
 * where one texel spans that much: lod = 0.5 log2(Omega_s / Omega_p) + ENV_LOD_BIAS with Omega_p =
 * (pi / H0)^2 the size of a level-0 texel (its height squared). The estimate is
 * sum L(l) (n.l) / sum (n.l), i.e. the lobe average of L weighted by D(h) (n.l)+. */
__kernel __attribute__((reqd_work_group_size(ENV_WG, 1, 1))) void env_prefilter(
    __global const float4* pyr_g, uint pyr_count, __global const ClhEnvLevel* pyr_levels_g,
    uint pyr_level_count, __global float4* out_g, uint out_count, uint out_offset, uint out_w,
    uint out_h, float alpha, uint sample_count, float rot_cos, float rot_sin, float intensity) {
  __local float4 samples_l[ENV_SAMPLES];
  uint lid = (uint)get_local_id(0);
  uint ns = clamp(sample_count, 1u, (uint)ENV_SAMPLES);
  uint npyr = min(pyr_level_count, (uint)CLH_ENV_MAX_LEVELS);
  float a = clamp(alpha, 1e-4f, 1.0f);
  float h0 = npyr > 0u ? (float)max(pyr_levels_g[0].height, 1u) : 1.0f;
  float omega_p = (CLH_ENV_PI / h0) * (CLH_ENV_PI / h0);
  for (uint k = lid; k < ns; k += ENV_WG) {
    float xi = ((float)k + 0.5f) / (float)ns;
    float cos2 = (1.0f - xi) / (1.0f + (a * a - 1.0f) * xi);
    float ch = sqrt(clamp(cos2, 0.0f, 1.0f));
    float sh = sqrt(clamp(1.0f - cos2, 0.0f, 1.0f));
    float phi = 2.0f * CLH_ENV_PI * env_radical_inverse(k);
    float omega_s = 4.0f / ((float)ns * clh_env_ggx_d(ch, a));
    float lod = fmax(0.5f * log2(omega_s / omega_p) + ENV_LOD_BIAS, 0.0f);
    samples_l[k] = (float4)(sh * cos(phi), sh * sin(phi), ch, lod);
  }
  barrier(CLK_LOCAL_MEM_FENCE);

  uint gid = (uint)get_global_id(0);
  ClhEnvLevel out = {out_offset, out_w, out_h, a};
  if (npyr == 0u || !env_level_ok(out, out_count) || gid >= out_w * out_h) return;
  for (uint l = 0u; l < npyr; ++l)
    if (!env_level_ok(pyr_levels_g[l], pyr_count)) return;

  uint i = gid % out_w, j = gid / out_w;
  float3 n = env_uv_dir(((float)i + 0.5f) / (float)out_w, ((float)j + 0.5f) / (float)out_h);
  /* tangent frame around n: t along the latitude circle (cross(+y, n)), b = n x t. It is
   * continuous over the whole map except at the poles, so the fixed sample pattern turns
   * smoothly from texel to texel and leaves no seam. */
  float tl2 = n.x * n.x + n.z * n.z;
  float3 t = tl2 > 1e-12f ? (float3)(n.z, 0.0f, -n.x) * rsqrt(tl2) : (float3)(1.0f, 0.0f, 0.0f);
  float3 bt = cross(n, t);

  float3 acc = (float3)(0.0f);
  float wsum = 0.0f;
  for (uint k = 0u; k < ns; ++k) {
    float4 s = samples_l[k];
    float3 h = s.x * t + s.y * bt + s.z * n;
    float3 l = 2.0f * s.z * h - n;
    float nl = dot(n, l);
    if (!(nl > 0.0f)) continue;
    float3 src = env_rotate_y(l, rot_cos, -rot_sin);
    float uv[2];
    clh_env_dir_to_uv(src.x, src.y, src.z, uv);
    acc += nl * env_sample_pyramid(pyr_g, pyr_levels_g, npyr, uv[0], uv[1], s.w);
    wsum += nl;
  }
  float scale = wsum > 0.0f ? intensity / wsum : 0.0f;
  out_g[out_offset + gid] = (float4)(acc * scale, 1.0f);
}

/* ---- SH projection ------------------------------------------------------------------- */

/* Row j of the source (offset 0 of pyr_g, width x height): rows_g[27 j + 3 k + c] =
 * intensity * sum_i L_c(w_ij) Y_k(w_ij) dOmega_j, with w_ij the texel centre's world
 * direction. */
__kernel __attribute__((reqd_work_group_size(ENV_WG, 1, 1))) void env_sh_rows(
    __global const float4* pyr_g, uint pyr_count, uint width, uint height, float rot_cos,
    float rot_sin, float intensity, __global float* rows_g, uint rows_count) {
  uint j = (uint)get_global_id(0);
  if (width == 0u || (ulong)width * height > pyr_count) return;
  if (j >= height || (ulong)(j + 1u) * CLH_ENV_SH_FLOATS > rows_count) return;
  float acc[CLH_ENV_SH_FLOATS];
  for (int m = 0; m < CLH_ENV_SH_FLOATS; ++m) acc[m] = 0.0f;
  float v = ((float)j + 0.5f) / (float)height;
  __global const float4* row = pyr_g + (size_t)j * width;
  for (uint i = 0u; i < width; ++i) {
    float3 d = env_rotate_y(env_uv_dir(((float)i + 0.5f) / (float)width, v), rot_cos, rot_sin);
    float y[9];
    clh_sh9_basis(d.x, d.y, d.z, y);
    float3 L = row[i].xyz;
    for (int k = 0; k < 9; ++k) {
      acc[3 * k + 0] += y[k] * L.x;
      acc[3 * k + 1] += y[k] * L.y;
      acc[3 * k + 2] += y[k] * L.z;
    }
  }
  float scale = intensity * clh_env_texel_solid_angle(j, width, height);
  for (int m = 0; m < CLH_ENV_SH_FLOATS; ++m)
    rows_g[(size_t)j * CLH_ENV_SH_FLOATS + m] = acc[m] * scale;
}

/* sh_g[m] = sum over rows j = 0, 1, ... of rows_g[27 j + m], in that order. */
__kernel __attribute__((reqd_work_group_size(ENV_WG, 1, 1))) void env_sh_reduce(
    __global const float* rows_g, uint rows, uint rows_count, __global float* sh_g) {
  uint m = (uint)get_global_id(0);
  if (m >= CLH_ENV_SH_FLOATS || (ulong)rows * CLH_ENV_SH_FLOATS > rows_count) return;
  float sum = 0.0f;
  for (uint j = 0u; j < rows; ++j) sum += rows_g[(size_t)j * CLH_ENV_SH_FLOATS + m];
  sh_g[m] = sum;
}

/* ---- queries (tests, debugging) -------------------------------------------------------- */

/* queries_g[q] = (direction xyz, GGX alpha);  out_g[2q] = (clh_env_radiance, 0),
 * out_g[2q + 1] = (clh_env_irradiance, 0). */
__kernel __attribute__((reqd_work_group_size(ENV_WG, 1, 1))) void env_query(
    __global const float4* texels_g, __global const ClhEnvLevel* levels_g, uint level_count,
    __global const float* sh_g, __global const float4* queries_g, uint query_count,
    __global float4* out_g) {
  uint q = (uint)get_global_id(0);
  if (q >= query_count) return;
  float4 in = queries_g[q];
  out_g[2u * q] = (float4)(clh_env_radiance(texels_g, levels_g, level_count, in.xyz, in.w), 0.0f);
  out_g[2u * q + 1u] = (float4)(clh_env_irradiance(sh_g, in.xyz), 0.0f);
}

/* Struct sizes as the device sees them (host static_asserts pin the same numbers). */
__kernel void env_layout(__global uint* out_g, uint count) {
  if (get_global_id(0) != 0 || count < 2u) return;
  out_g[0] = (uint)sizeof(ClhEnvLevel);
  out_g[1] = (uint)sizeof(ClhEnvSkyGpu);
}
