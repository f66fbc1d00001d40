/* hair_dual.h — light scattered between fibres: dual scattering (Zinke et al. 2008) on top
 * of the single-fibre model of hair_bsdf.h, for lights with a deep opacity map and for the
 * probe (ambient / environment) light darkened by the baked AO.
 *
 * Zinke et al. split the light that reaches a fibre after scattering in other fibres into
 * - global forward scattering: light that crossed the fibres between the light and the
 *   shaded point, each passing on the fraction a_F of it that it scatters forward, and
 *   spreading it longitudinally (Zinke §4.1, T_f = d_f prod a_F, sigma_f^2 = sum beta_F^2);
 * - local back scattering: light sent back toward the shaded fibre by the hair behind it
 *   (seen from the light), after one or three backward events among forward ones
 *   (Zinke §4.2, A_b = A_1 + A_3, A_1 = a_B a_F^2 / (1 - a_F^2),
 *   A_3 = a_B^3 a_F^2 / (1 - a_F^2)^3), in a lobe over the back hemisphere.
 * How clhair reads them:
 * - The deep opacity map gives the optical depth tau = density * coverage between the light
 *   and the point (the map's transmittance is e^-tau): the expected number of fibres a ray
 *   from the light crosses. Taking that number as Poisson, the light arriving unscattered is
 *   e^-tau (the map's value: the single-fibre shading as before), and the light arriving
 *   after any number of forward scatterings is E[a_F^n] = e^{-tau (1 - a_F)} per channel.
 *   The difference is the global part. Among it, the mean number of fibres crossed is
 *   tau a_F, and each adds the TT lobe's variance v_TT to every lobe's longitudinal variance
 *   (Zinke's sigma_f^2 = n beta_F^2). Its azimuthal spread is taken as complete: each
 *   lobe's energy spread evenly over phi (Ñ_p -> Ā_p / 2 pi), which keeps its energy.
 * - The same map, read past the last layer, gives the depth tau_b of the hair behind the
 *   point along the light. Zinke assume an infinite volume behind; clhair weighs the back
 *   lobe by 1 - e^-tau_b, the chance that the light meets hair behind at all, so a fibre at
 *   the far side of the groom (or alone) gets none.
 * - The back lobe is a M of variance 2 v_TT + (v_R + v_TRT) / 2 (two forward crossings and
 *   one backward event; Zinke's sigma_b without the shift Delta_b) about the mirror
 *   direction, constant over the back half of azimuths (|phi| < pi/2, 1 / pi), carrying
 *   d_b A_b of the light that reached the point (direct and global).
 * - a_F = Ā_TT + Ā_3 / 2 and a_B = Ā_R + Ā_TRT + Ā_3 / 2 from the fibre's own h-averaged
 *   energies at theta_o (hair_bsdf.h), per channel, so melanin and file colours need no
 *   table; this is the split hair_aggregate.h uses too.
 * - d_f = d_b = 0.7: Zinke's density factors (§5), kept as published.
 * Probe light: the AO a is the unoccluded share of the probe; the same Poisson reading with
 * tau = -ln a gives the global part e^{-tau (1 - a_F)} - a of the probe's radiance spread over
 * the fibre's whole albedo, and the back part d_b (1 - a) A_b.
 * Energy: the direct part is the single fibre (<= 1 in the furnace); the global part only
 * returns light the map took away, at most a_F of it per fibre crossed; the back part is
 * bounded by d_b A_b (1 - e^-tau_b), A_b < 1 for a_F + a_B <= 1 (tests/test_dual.cpp
 * integrates the whole term in a white furnace around a cluster).
 */
#ifndef CLHAIR_HAIR_DUAL_H
#define CLHAIR_HAIR_DUAL_H

#include "hair_bsdf.h"

#define CLH_DUAL_DF 0.7f /* Zinke et al. 2008 §5, forward density factor d_f */
#define CLH_DUAL_DB 0.7f /* Zinke et al. 2008 §5, backward density factor d_b */

typedef struct {
  clh_v3 a_f;       /* forward-scattered energy of the fibre (per channel) */
  clh_v3 one_m_af;  /* 1 - a_f */
  clh_v3 albedo;    /* Ā_R + Ā_TT + Ā_TRT + Ā_3 */
  clh_v3 back;      /* d_b A_b: what the hair behind sends back, per unit light */
  clh_v3 lobe_e[3]; /* Ā_R, Ā_TT, Ā_TRT over 2 pi: the spread lobes' azimuthal value */
  float af_lum;     /* luminance of a_f: fibres crossed per unit tau among transmitted light */
  float v_f;        /* variance one forward crossing adds (the TT lobe's) */
  float v_b;        /* the back lobe's variance */
} clh_hair_dual;

static inline float clh_dual_a1a3(float a_f, float a_b) {
  const float af2 = fmin(a_f * a_f, 0.999f);
  const float d = 1.0f - af2;
  return a_b * af2 / d + a_b * a_b * a_b * af2 / (d * d * d);
}

static inline void clh_hair_dual_prepare_to(clh_hair_dual* out, const clh_hair_view* hv) {
  const clh_v3 half_d = clh_v3_scale(hv->mass[3], 0.5f);
  const clh_v3 a_f = clh_v3_add(hv->mass[1], half_d);
  const clh_v3 a_b = clh_v3_add(clh_v3_add(hv->mass[0], hv->mass[2]), half_d);
  out->a_f = a_f;
  out->one_m_af =
      clh_v3_make(fmax(1.0f - a_f.x, 0.0f), fmax(1.0f - a_f.y, 0.0f), fmax(1.0f - a_f.z, 0.0f));
  out->albedo =
      clh_v3_add(clh_v3_add(hv->mass[0], hv->mass[1]), clh_v3_add(hv->mass[2], hv->mass[3]));
  /* the back lobe's energy, capped so that it and the fibre's own never pass 1 */
  const clh_v3 ab = clh_v3_make(clh_dual_a1a3(a_f.x, a_b.x), clh_dual_a1a3(a_f.y, a_b.y),
                                clh_dual_a1a3(a_f.z, a_b.z));
  out->back = clh_v3_make(fmin(CLH_DUAL_DB * ab.x, 1.0f), fmin(CLH_DUAL_DB * ab.y, 1.0f),
                          fmin(CLH_DUAL_DB * ab.z, 1.0f));
  for (int p = 0; p < 3; ++p)
    out->lobe_e[p] = clh_v3_scale(hv->mass[p], 1.0f / (2.0f * CLH_HAIR_PI));
  out->af_lum = 0.2126f * a_f.x + 0.7152f * a_f.y + 0.0722f * a_f.z;
  out->v_f = hv->v[1];
  out->v_b = 2.0f * hv->v[1] + 0.5f * (hv->v[0] + hv->v[2]);
}

/* f cos(theta_i) of the whole light reaching the fibre from direction wi, for a light whose
 * way to the point crosses tau fibres on average and finds tau_b fibres behind it.
 * `single` is clh_hair_eval_cos(hv, wi) (the caller has it). The map's own transmittance
 * e^-tau is applied here: the caller passes the light's unshadowed radiance. */
static inline clh_v3 clh_hair_dual_eval_cos(const clh_hair_view* hv, const clh_hair_dual* ds,
                                            clh_v3 wi, clh_v3 single, float tau, float tau_b) {
  tau = fmax(tau, 0.0f);
  const float direct = tau > 0.0f ? clh_hair_exp(-tau) : 1.0f; /* exact where nothing is in front */
  /* light arriving after any number of forward scatterings (direct included), per channel */
  const clh_v3 arrive = clh_hair_exp3(clh_v3_scale(ds->one_m_af, -tau));
  const clh_v3 through = clh_v3_fmax(clh_v3_sub(arrive, clh_v3_splat(direct)), 0.0f);
  const float n = tau * ds->af_lum; /* mean crossings of the forward-scattered light */

  float sin_i, cos_i, cos_phi;
  clh_hair_angles_to(hv, wi, &sin_i, &cos_i, &cos_phi);

  clh_v3 out = clh_v3_scale(single, direct);
  if (n > 1e-4f) {
    /* global part: the lobes widened by n crossings, spread evenly in phi */
    clh_v3 g = clh_v3_scale(clh_hair_diffuse(hv), cos_i);
    for (int p = 0; p < 3; ++p) {
      const float v = hv->v[p] + n * ds->v_f;
      const float m =
          clh_hair_mp(sin_i, cos_i, hv->sin_o_tilt[p], hv->cos_o_tilt[p], v, clh_hair_mnorm(v));
      g = clh_v3_add(g, clh_v3_scale(ds->lobe_e[p], m));
    }
    out = clh_v3_add(out, clh_v3_scale(clh_v3_mul(through, g), CLH_DUAL_DF));
  }
  const float behind = tau_b > 0.0f ? 1.0f - clh_hair_exp(-tau_b) : 0.0f;
  if (cos_phi > 0.0f && behind > 0.0f) {
    /* local back scattering of the light that reached the point (direct + global) */
    const float v = ds->v_b + n * ds->v_f;
    const float mb = clh_hair_mp(sin_i, cos_i, hv->sin_o, hv->cos_o, v, clh_hair_mnorm(v)) *
                     (behind / CLH_HAIR_PI);
    const clh_v3 reach = clh_v3_add(clh_v3_splat(direct), clh_v3_scale(through, CLH_DUAL_DF));
    out = clh_v3_add(out, clh_v3_scale(clh_v3_mul(reach, ds->back), mb));
  }
  return out;
}

/* The probe light's multiple scattering: radiance per unit probe radiance that the AO took
 * away and the hair gives back (global part spread over the fibre's albedo, and back scattering
 * of the hair around). ao in (0, 1]; 1 (nothing around) gives 0. */
static inline clh_v3 clh_hair_dual_probe(const clh_hair_dual* ds, float ao) {
  ao = clamp(ao, 1e-4f, 1.0f);
  const float tau = -0.693147181f * clh_fast_log2(ao);
  const clh_v3 arrive = clh_hair_exp3(clh_v3_scale(ds->one_m_af, -tau));
  const clh_v3 through = clh_v3_fmax(clh_v3_sub(arrive, clh_v3_splat(ao)), 0.0f);
  const clh_v3 reach = clh_v3_add(clh_v3_splat(ao), clh_v3_scale(through, CLH_DUAL_DF));
  return clh_v3_add(clh_v3_scale(clh_v3_mul(through, ds->albedo), CLH_DUAL_DF),
                    clh_v3_scale(clh_v3_mul(reach, ds->back), 1.0f - ao));
}

#endif /* CLHAIR_HAIR_DUAL_H */
