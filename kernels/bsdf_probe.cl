/* bsdf_probe.cl — test kernel for the real-time hair BSDF (kernels/common/hair_bsdf.h).
 *
 * Evaluates the device model for an array of records so tests/test_bsdf.cpp can compare it
 * with the double-precision CPU reference (tests/reference/chiang_reference.cpp).
 * Input record i: BSDF_PROBE_IN floats at rec_g[BSDF_PROBE_IN * i]:
 *    0..2 sigma_a   3 beta_m   4 beta_n   5 alpha (radians)   6 eta   7 unused
 *    8..10 t (unit)   12..14 wo (unit, to the eye)   16..18 wi (unit, to the light)
 *    (11, 15, 19 unused)
 * Output: BSDF_PROBE_OUT float4 per record at out_g[BSDF_PROBE_OUT * i]:
 *    0 (f_R, cos theta_i)   1 (f_TT, 0)   2 (f_TRT, 0)   3 (diffuse f, diffuse albedo.g)
 *    4 (clh_hair_bsdf: the full one-call f, clh_hair_eval_cos luminance)
 *    5 (env spec_weight, ggx_alpha)
 * Every f is without the cosine. Work-items past `count` do nothing.
 *
 * bsdf_probe_agg: the aggregated BCSDF (Huang 2024) on the same records, with the cluster's
 * fibre count k in slot 7, its widening w in slot 11 and its depth t (fibre widths along the
 * view) in slot 15. Output 2 float4 per record:
 *    0 (clh_hair_agg_eval_cos rgb, luminance)   1 (clh_hair_eval_cos rgb, luminance)
 * bsdf_probe_dual: dual scattering (hair_dual.h) on the same records, with the optical depth
 * tau toward the light in slot 7, the depth behind tau_b in slot 11, the AO in slot 15 and
 * the maps' mean transmittance in slot 19 (negative: none). Output 2 float4 per record:
 *    0 (clh_hair_dual_eval_cos rgb, luminance)
 *    1 (clh_hair_dual_probe rgb, clh_hair_dual_probe_ao of slots 15 and 19)
 * bsdf_probe_lanes: the lane-wise elementary functions of clh_math.h (clh_v3_exp, clh_v3_log2,
 * clh_v3_sincos) against clhair/fast_math.h's scalar ones on the same device: input i sits
 * in the middle lane, inputs i + 1 and i + 2 in the others; output 8 floats per input: the
 * lane's exp, log2, sin, cos, then the scalar exp, log2, sin, cos.
 * bsdf_probe_visibility: the baked-visibility lookup (kernels/common/visibility.h); record i
 * is 8 floats: SH c0..c3, light direction xyz (world), unused; output float4 per record:
 *    (transmittance, clamped events, unclamped SH value in the object-space direction, 0)
 */
/* gpu_types.h first: its FP_CONTRACT OFF then governs the BSDF code as in shade.cl */
#include "clhair/gpu_types.h"
#include "clhair/fast_math.h"
#include "hair_bsdf.h"
#include "hair_aggregate.h"
#include "hair_env.h"
#include "hair_dual.h"
#include "visibility.h"

#define BSDF_PROBE_IN 20
#define BSDF_PROBE_OUT 6

/* The material and directions of a BSDF_PROBE_IN-float record (layout above). */
static inline void probe_record(__global const float* r, clh_hair_material* m, clh_v3* t,
                                clh_v3* wo, clh_v3* wi) {
  m->sigma_a = clh_v3_make(r[0], r[1], r[2]);
  m->beta_m = r[3];
  m->beta_n = r[4];
  m->alpha = r[5];
  m->eta = r[6];
  *t = clh_v3_make(r[8], r[9], r[10]);
  *wo = clh_v3_make(r[12], r[13], r[14]);
  *wi = clh_v3_make(r[16], r[17], r[18]);
}

__kernel void bsdf_probe_eval(__global const float* rec_g, uint count, __global float4* out_g) {
  uint i = (uint)get_global_id(0);
  if (i >= count) return;
  __global const float* r = rec_g + (size_t)i * BSDF_PROBE_IN;
  clh_hair_material m;
  clh_v3 t, wo, wi;
  probe_record(r, &m, &t, &wo, &wi);

  clh_hair_view hv;
  clh_hair_prepare_to(&hv, &m, t, wo);
  clh_v3 fr, ftt, ftrt;
  clh_hair_eval_lobes(&hv, wi, &fr, &ftt, &ftrt);
  clh_v3 fd = clh_hair_diffuse(&hv);
  clh_hair_env env;
  clh_hair_env_terms_to(&env, &hv);

  __global float4* o = out_g + (size_t)i * BSDF_PROBE_OUT;
  o[0] = (float4)(clh_v3_f3(fr), clh_hair_cos_theta(t, wi));
  o[1] = (float4)(clh_v3_f3(ftt), 0.0f);
  o[2] = (float4)(clh_v3_f3(ftrt), 0.0f);
  o[3] = (float4)(clh_v3_f3(fd), clh_hair_diffuse_albedo(&hv).y);
  o[4] = (float4)(clh_v3_f3(clh_hair_bsdf(&m, t, wo, wi)),
                  clh_v3_dot(clh_hair_eval_cos(&hv, wi), clh_v3_make(0.2126f, 0.7152f, 0.0722f)));
  o[5] = (float4)(clh_v3_f3(env.spec_weight), env.ggx_alpha);
}

/* sigma_a helpers on the device: record i holds (eumelanin, pheomelanin, beta_n, unused,
 * colour rgb, unused); out 2 float4: sigma_a from melanin, sigma_a from colour. */
__kernel void bsdf_probe_sigma(__global const float* rec_g, uint count, __global float4* out_g) {
  uint i = (uint)get_global_id(0);
  if (i >= count) return;
  __global const float* r = rec_g + (size_t)i * 8;
  out_g[2 * (size_t)i] = (float4)(clh_v3_f3(clh_hair_sigma_a_from_melanin(r[0], r[1])), 0.0f);
  out_g[2 * (size_t)i + 1] =
      (float4)(clh_v3_f3(clh_hair_sigma_a_from_color(clh_v3_make(r[4], r[5], r[6]), r[2])), 0.0f);
}

__kernel void bsdf_probe_agg(__global const float* rec_g, uint count, __global float4* out_g) {
  uint i = (uint)get_global_id(0);
  if (i >= count) return;
  __global const float* r = rec_g + (size_t)i * BSDF_PROBE_IN;
  clh_hair_material m;
  clh_v3 t, wo, wi;
  probe_record(r, &m, &t, &wo, &wi);
  clh_hair_view hv;
  clh_hair_prepare_to(&hv, &m, t, wo);
  clh_hair_agg ag;
  clh_hair_agg_prepare_to(&ag, &hv, r[7], r[11], r[15]);
  const clh_v3 lum = clh_v3_make(0.2126f, 0.7152f, 0.0722f);
  const clh_v3 fa = clh_hair_agg_eval_cos(&hv, &ag, wi, 1);
  const clh_v3 fs = clh_hair_eval_cos(&hv, wi);
  out_g[2 * (size_t)i] = (float4)(clh_v3_f3(fa), clh_v3_dot(fa, lum));
  out_g[2 * (size_t)i + 1] = (float4)(clh_v3_f3(fs), clh_v3_dot(fs, lum));
}

__kernel void bsdf_probe_visibility(__global const ClhVisibilityGpu* vis_g,
                                    __global const float* rec_g, uint count,
                                    __global float4* out_g) {
  uint i = (uint)get_global_id(0);
  if (i >= count) return;
  __global const float* r = rec_g + (size_t)i * 8;
  const float4 sh = (float4)(r[0], r[1], r[2], r[3]);
  const clh_v3 l = clh_v3_make(r[4], r[5], r[6]);
  __global const float* m = vis_g->world_to_obj;
  const float x = m[0] * l.x + m[1] * l.y + m[2] * l.z;
  const float y = m[4] * l.x + m[5] * l.y + m[6] * l.z;
  const float z = m[8] * l.x + m[9] * l.y + m[10] * l.z;
  const float inv = 1.0f / sqrt(fmax(x * x + y * y + z * z, 1e-20f));
  out_g[i] = (float4)(clh_vis_transmittance(vis_g, sh, l),
                      clh_vis_events(sh.x, sh.y, sh.z, sh.w, x * inv, y * inv, z * inv),
                      clh_vis_sh_eval(sh.x, sh.y, sh.z, sh.w, x * inv, y * inv, z * inv), 0.0f);
}

__kernel void bsdf_probe_dual(__global const float* rec_g, uint count, __global float4* out_g) {
  uint i = (uint)get_global_id(0);
  if (i >= count) return;
  __global const float* r = rec_g + (size_t)i * BSDF_PROBE_IN;
  clh_hair_material m;
  clh_v3 t, wo, wi;
  probe_record(r, &m, &t, &wo, &wi);
  clh_hair_view hv;
  clh_hair_prepare_to(&hv, &m, t, wo);
  clh_hair_dual ds;
  clh_hair_dual_prepare_to(&ds, &hv);
  const clh_v3 f = clh_hair_dual_eval_cos(&hv, &ds, wi, clh_hair_eval_cos(&hv, wi), r[7], r[11]);
  const clh_v3 lum = clh_v3_make(0.2126f, 0.7152f, 0.0722f);
  out_g[2 * (size_t)i] = (float4)(clh_v3_f3(f), clh_v3_dot(f, lum));
  out_g[2 * (size_t)i + 1] =
      (float4)(clh_v3_f3(clh_hair_dual_probe(&ds, r[15])), clh_hair_dual_probe_ao(r[15], r[19]));
}

__kernel void bsdf_probe_lanes(__global const float* in_g, uint count, __global float* out_g) {
  const uint i = (uint)get_global_id(0);
  if (i >= count) return;
  const float x = in_g[i];
  const clh_v3 v = clh_v3_make(in_g[(i + 1u) % count], x, in_g[(i + 2u) % count]);
  clh_v3 s, c;
  clh_v3_sincos(v, &s, &c);
  float ss, cc;
  clh_fast_sincos(x, &ss, &cc);
  __global float* o = out_g + (size_t)i * 8u;
  o[0] = clh_v3_exp(v).y;
  o[1] = clh_v3_log2(v).y;
  o[2] = s.y;
  o[3] = c.y;
  o[4] = clh_fast_exp(x);
  o[5] = clh_fast_log2(x);
  o[6] = ss;
  o[7] = cc;
}
