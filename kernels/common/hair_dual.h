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
 *   after any number of forward scatterings is E[a_F^n] = e^{-tau (1 - a_F)} per channel
 *   (Zinke's reading; clhair sums the whole stack, below). The difference is the global
 *   part. Among it, the mean number of fibres crossed is tau a_F, and each adds the TT
 *   lobe's variance v_TT to every lobe's longitudinal variance
 *   (Zinke's sigma_f^2 = n beta_F^2). Its azimuthal spread is taken as complete: each
 *   lobe's energy spread evenly over phi (Ñ_p -> Ā_p / 2 pi), which keeps its energy.
 * - The same map, read past the last layer, gives the depth tau_b of the hair behind the
 *   point along the light. Zinke assume an infinite volume behind.
 * - Zinke sum the paths through the fibres along the light as a stack of layers that each
 *   pass a_F on and send a_B back, truncated at three backward events (A_1 + A_3) and with
 *   no backward event on the way in. That is right for dark hair and short for light hair:
 *   where a fibre absorbs little (a file colour of red 1, blonde in red), light crosses the
 *   groom back and forth many times, and the truncated sums return a third less from behind
 *   and, 10 fibres deep, let through a quarter of what the whole stack does. clhair sums
 *   the same stack in closed form instead (the adding equations of identical layers, as
 *   Kubelka and Munk or Stokes's pile of plates):
 *     R_inf = 2 a_B / (s + sqrt(s^2 - 4 a_B^2)),  s = 1 + a_B^2 - a_F^2  (the infinite stack)
 *     lambda = a_F / (1 - a_B R_inf)                    (the decay per layer of its mode)
 *     T_n = (1 - R^2) lambda^n / (1 - R^2 lambda^2n)        (R = R_inf; n layers)
 *     R_n = R (1 - lambda^2n) / (1 - R^2 lambda^2n)
 *   Expanded in a_B, R_inf - a_B begins with Zinke's A_1 and A_3; for a_F + a_B -> 1 it goes
 *   to a_F where A_1 + A_3 stays near half of it. With the number of fibres Poisson of mean
 *   tau, E[T_n] = (1 - R^2) sum_k R^2k e^{-tau (1 - lambda^(2k+1))}; clhair
 *   takes the terms k = 0, 1 and the rest as a geometric tail with the ratio of terms 3 and
 *   2 (clh_dual_stack_through: within 3 % of the Poisson sum where a_F + a_B <= 0.995,
 *   never below the forward-only e^{-tau (1 - a_F)}; a dark channel, R_inf^2 < 0.01, takes
 *   the first term alone, one exponential per light). The hair behind, m fibres Poisson of
 *   mean tau_b, sends back E[R_{1+m}] - a_B (clh_dual_stack_back, summed the same way,
 *   within 5 %; 0 with nothing behind, the shaded fibre's own back scattering being the
 *   single-fibre lobes).
 *   tests/test_dual.cpp checks both against the Poisson sums of the stack built layer by
 *   layer.
 * - The back lobe is a M of variance 2 v_TT + (v_R + v_TRT) / 2 (two forward crossings and
 *   one backward event; Zinke's sigma_b without the shift Delta_b) about the mirror
 *   direction, constant over the back half of azimuths (|phi| < pi/2, 1 / pi), carrying
 *   d_b (E[R_{1+m}] - a_B) of the light that reached the point (direct and global).
 * - a_F = Ā_TT + Ā_3 / 2 and a_B = Ā_R + Ā_TRT + Ā_3 / 2 from the fibre's own h-averaged
 *   energies at theta_o (hair_bsdf.h), per channel, so melanin and file colours need no
 *   table; this is the split hair_aggregate.h uses too.
 * - d_f = d_b = 0.7: Zinke's density factors (§5), kept as published.
 * Probe light: the AO a is the unoccluded share of the probe; the same Poisson reading with
 * tau = -ln a gives the global part E[T_n] - a of the probe's radiance spread over the fibre's
 * whole albedo, and the back part d_b (1 - a) (R_inf - a_B).
 * Energy: the direct part is the single fibre (<= 1 in the furnace); the global part only
 * returns light the map took away (E[T_n] <= 1: the stack conserves or absorbs); the back
 * part is bounded by d_b (R_inf - a_B) <= d_b a_F; the stack leaves out the light that goes
 * back and forth between the hair in front and the hair behind, so the sum stays under the
 * furnace (tests/test_dual.cpp integrates the whole term in a white furnace in a slab).
 */
#ifndef CLHAIR_HAIR_DUAL_H
#define CLHAIR_HAIR_DUAL_H

#include "hair_bsdf.h"

#define CLH_DUAL_DF 0.7f /* Zinke et al. 2008 §5, forward density factor d_f */
#define CLH_DUAL_DB 0.7f /* Zinke et al. 2008 §5, backward density factor d_b */

/* The stack of fibres of the three channels (see above; each field per channel), with the
 * exponents of its sums ready: the shading evaluates them for every light. */
typedef struct {
  clh_v3 r;        /* R_inf */
  clh_v3 r2;       /* R_inf^2 */
  clh_v3 r_coef;   /* R_inf (1 - R_inf^2) lambda^2 */
  clh_v3 r_back;   /* R_inf - a_B: what infinite hair behind sends back */
  clh_v3 a_b;      /* the fibre's backward energy (held with a_F at 0.995 or less) */
  clh_v3 rl2;      /* R_inf^2 lambda^2 */
  clh_v3 one_m_af; /* 1 - a_F: the forward-only transmission's exponent */
  clh_v3 kt[4];    /* 1 - lambda, 1 - lambda^3, 1 - lambda^5, lambda^5 (1 - lambda^2) */
  clh_v3 kb[4];    /* 1 - lambda^2, 1 - lambda^4, 1 - lambda^6, lambda^6 (1 - lambda^2) */
} clh_dual_stack;

/* The stack of a fibre with energies a_f forward and a_b backward per channel; a_F + a_B is
 * held at 0.995 or less so that R_inf < 1 and the sums stay finite. */
static inline clh_dual_stack clh_dual_stack_make(clh_v3 a_f, clh_v3 a_b) {
  clh_dual_stack st;
  st.one_m_af = clh_v3_fmax(1.0f - a_f, 0.0f);
  const clh_v3 sum = a_f + a_b;
  a_f = clh_v3_if_greater(sum, 0.995f, a_f * (0.995f / sum), a_f);
  a_b = clh_v3_if_greater(sum, 0.995f, a_b * (0.995f / sum), a_b);
  a_b = clh_v3_fmax(a_b, 1e-6f);
  const clh_v3 s = 1.0f + a_b * a_b - a_f * a_f;
  const clh_v3 r = clh_v3_fmin(
      2.0f * a_b / (s + clh_v3_sqrt(clh_v3_fmax(s * s - 4.0f * a_b * a_b, 0.0f))), 0.999f);
  const clh_v3 l = clh_v3_clamp(a_f / (1.0f - a_b * r), 1e-6f, 0.9999f);
  const clh_v3 l2 = l * l, l3 = l2 * l, l4 = l2 * l2, l5 = l4 * l, l6 = l4 * l2;
  st.r = r;
  st.r2 = r * r;
  st.r_coef = r * (1.0f - st.r2) * l2;
  st.r_back = clh_v3_fmax(r - a_b, 0.0f);
  st.a_b = a_b;
  st.rl2 = st.r2 * l2;
  st.kt[0] = 1.0f - l;
  st.kt[1] = 1.0f - l3;
  st.kt[2] = 1.0f - l5;
  st.kt[3] = l5 * (1.0f - l2);
  st.kb[0] = 1.0f - l2;
  st.kb[1] = 1.0f - l4;
  st.kb[2] = 1.0f - l6;
  st.kb[3] = l6 * (1.0f - l2);
  return st;
}

/* E[T_n] for n Poisson of mean tau: light arriving through the stack after any number of
 * forward and backward events (the unscattered e^-tau included), per channel. A dark
 * channel (R_inf^2 below 0.01) takes e^{-tau (1 - lambda)} alone: 1 at tau = 0, at least the
 * forward-only transmission (lambda >= a_F), and within R_inf^2 of the sum; when all three
 * are dark, that is all there is to evaluate. */
static inline clh_v3 clh_dual_stack_through(const clh_dual_stack* st, float tau) {
  const clh_v3 first = clh_v3_exp(-tau * st->kt[0]);
  if (clh_v3_all_less(st->r2, 0.01f)) return first;
  const clh_v3 r2 = st->r2;
  const clh_v3 fwd = clh_v3_exp(-tau * st->one_m_af);
  const clh_v3 tail =
      clh_v3_exp(-tau * st->kt[2]) / clh_v3_fmax(1.0f - r2 * clh_v3_exp(-tau * st->kt[3]), 1e-6f);
  const clh_v3 t = (1.0f - r2) * (first + r2 * (clh_v3_exp(-tau * st->kt[1]) + r2 * tail));
  return clh_v3_if_less(r2, 0.01f, first, clh_v3_fmin(clh_v3_max(t, fwd), 1.0f));
}

/* E[R_{1+m}] - a_B for m Poisson of mean tau_b, per channel: what the hair behind the shaded
 * fibre sends back to it per unit light that reached it (a dark channel, R_inf^2 below 0.01:
 * the first term of the sum). */
static inline clh_v3 clh_dual_stack_back(const clh_dual_stack* st, float tau_b) {
  clh_v3 sum = clh_v3_exp(-tau_b * st->kb[0]);
  if (!clh_v3_all_less(st->r2, 0.01f)) {
    const clh_v3 rl2 = st->rl2;
    const clh_v3 tail = clh_v3_exp(-tau_b * st->kb[2]) /
                        clh_v3_fmax(1.0f - rl2 * clh_v3_exp(-tau_b * st->kb[3]), 1e-6f);
    const clh_v3 more = rl2 * (clh_v3_exp(-tau_b * st->kb[1]) + rl2 * tail);
    sum = clh_v3_if_less(st->r2, 0.01f, sum, sum + more);
  }
  return clh_v3_fmax(st->r - st->r_coef * sum - st->a_b, 0.0f);
}

typedef struct {
  clh_v3 a_f;        /* forward-scattered energy of the fibre (per channel) */
  clh_v3 a_b;        /* backward-scattered energy of the fibre (per channel) */
  clh_v3 albedo;     /* Ā_R + Ā_TT + Ā_TRT + Ā_3 */
  clh_v3 back;       /* d_b (R_inf - a_B): what infinite hair behind sends back */
  clh_dual_stack st; /* the stack of fibres, per channel */
  clh_v3 lobe_e[3];  /* Ā_R, Ā_TT, Ā_TRT over 2 pi: the spread lobes' azimuthal value */
  float af_lum;      /* luminance of a_f: fibres crossed per unit tau among transmitted light */
  float v_f;         /* variance one forward crossing adds (the TT lobe's) */
  float v_b;         /* the back lobe's variance */
} clh_hair_dual;

static inline void clh_hair_dual_prepare_to(clh_hair_dual* out, const clh_hair_view* hv) {
  const clh_v3 half_d = clh_v3_scale(hv->mass[3], 0.5f);
  const clh_v3 a_f = clh_v3_add(hv->mass[1], half_d);
  const clh_v3 a_b = clh_v3_add(clh_v3_add(hv->mass[0], hv->mass[2]), half_d);
  out->a_f = a_f;
  out->albedo =
      clh_v3_add(clh_v3_add(hv->mass[0], hv->mass[1]), clh_v3_add(hv->mass[2], hv->mass[3]));
  out->a_b = a_b;
  out->st = clh_dual_stack_make(a_f, a_b);
  for (int p = 0; p < 3; ++p)
    out->lobe_e[p] = clh_v3_scale(hv->mass[p], 1.0f / (2.0f * CLH_HAIR_PI));
  out->af_lum = 0.2126f * a_f.x + 0.7152f * a_f.y + 0.0722f * a_f.z;
  out->v_f = hv->v[1];
  out->v_b = 2.0f * hv->v[1] + 0.5f * (hv->v[0] + hv->v[2]);
}

static inline clh_v3 clh_dual_through3(const clh_hair_dual* ds, float tau) {
  return clh_dual_stack_through(&ds->st, tau);
}

/* f cos(theta_i) of the whole light reaching the fibre from direction wi, whose angles about
 * the fibre (clh_hair_angles_to) are sin_i, cos_i and cos_phi, for a light whose way to the
 * point crosses tau fibres on average and finds tau_b fibres behind it.
 * `single` is clh_hair_eval_cos(hv, wi) (the caller has it). The map's own transmittance
 * e^-tau is applied here: the caller passes the light's unshadowed radiance. */
static inline clh_v3 clh_hair_dual_eval_cos_at(const clh_hair_view* hv, const clh_hair_dual* ds,
                                               float sin_i, float cos_i, float cos_phi,
                                               clh_v3 single, float tau, float tau_b) {
  tau = fmax(tau, 0.0f);
  const float direct = tau > 0.0f ? clh_hair_exp(-tau) : 1.0f; /* exact where nothing is in front */
  /* light arriving through the fibres in front (direct included), per channel */
  const clh_v3 arrive = clh_dual_through3(ds, tau);
  const clh_v3 through = clh_v3_fmax(clh_v3_sub(arrive, clh_v3_splat(direct)), 0.0f);
  const float n = tau * ds->af_lum; /* mean crossings of the forward-scattered light */

  clh_v3 out = clh_v3_scale(single, direct);
  if (n > 1e-4f) {
    /* global part: the lobes widened by n crossings, spread evenly in phi */
    const clh_v3 v = clh_v3_add(hv->lobe_v, clh_v3_splat(n * ds->v_f));
    const clh_v3 m =
        clh_hair_mp3(sin_i, cos_i, hv->lobe_sin_o, hv->lobe_cos_o, v, clh_hair_mnorm3(v));
    clh_v3 g = clh_v3_scale(clh_hair_diffuse(hv), cos_i);
    g = clh_v3_add(g, clh_v3_scale(ds->lobe_e[0], m.x));
    g = clh_v3_add(g, clh_v3_scale(ds->lobe_e[1], m.y));
    g = clh_v3_add(g, clh_v3_scale(ds->lobe_e[2], m.z));
    out = clh_v3_add(out, clh_v3_scale(clh_v3_mul(through, g), CLH_DUAL_DF));
  }
  if (cos_phi > 0.0f && tau_b > 0.0f) {
    /* local back scattering of the light that reached the point (direct + global) */
    const float v = ds->v_b + n * ds->v_f;
    const float mb = clh_hair_mp(sin_i, cos_i, hv->sin_o, hv->cos_o, v, clh_hair_mnorm(v)) *
                     (CLH_DUAL_DB / CLH_HAIR_PI);
    const clh_v3 back = clh_dual_stack_back(&ds->st, tau_b);
    const clh_v3 reach = clh_v3_add(clh_v3_splat(direct), clh_v3_scale(through, CLH_DUAL_DF));
    out = clh_v3_add(out, clh_v3_scale(clh_v3_mul(reach, back), mb));
  }
  return out;
}

/* The same for direction wi (a light loop that has the angles for the single-fibre lobes
 * already passes them to clh_hair_dual_eval_cos_at). */
static inline clh_v3 clh_hair_dual_eval_cos(const clh_hair_view* hv, const clh_hair_dual* ds,
                                            clh_v3 wi, clh_v3 single, float tau, float tau_b) {
  float sin_i, cos_i, cos_phi;
  clh_hair_angles_to(hv, wi, &sin_i, &cos_i, &cos_phi);
  return clh_hair_dual_eval_cos_at(hv, ds, sin_i, cos_i, cos_phi, single, tau, tau_b);
}

/* The AO the probe's dual-scattering term reads (clh_hair_dual_probe), refined at the point
 * by the lights' deep opacity maps. The vertex AO is baked per layer vertex and interpolated
 * over a bundle's cross-section, so it is the same for a fibre on a lock's lit side and one
 * inside it; the maps resolve the hair at the fibre. map_t is the mean of the mapped lights'
 * transmittances e^-tau at the point, or negative where no light has a map (the AO as baked).
 * The depth the term reads is a blend of the two depths:
 *   -ln a' = (1 - w) (-ln ao) + w (-ln map_t),   w = CLH_DUAL_PROBE_MAP_WEIGHT,
 * so a' lies between ao and map_t (each clamped to [1e-4, 1]). w was measured against the
 * path reference (bench/look-ambient.md, "The ambient light's scale"): 0.35 lowers blonde's FLIP by
 * 12-14 % on groom1 and the darker strand file's by 12-17 %, and moves the rest by at most
 * 2.5 %. Only the given-back term reads it: the single-scattered probe light keeps the AO. */
#define CLH_DUAL_PROBE_MAP_WEIGHT 0.35f
static inline float clh_hair_dual_probe_ao(float ao, float map_t) {
  if (!(map_t >= 0.0f) || (ao >= 1.0f && map_t >= 1.0f)) return ao; /* exact where open */
  const float la = clh_fast_log2(clamp(ao, 1e-4f, 1.0f));
  const float lt = clh_fast_log2(clamp(map_t, 1e-4f, 1.0f));
  const float w = CLH_DUAL_PROBE_MAP_WEIGHT;
  return fmin(clh_hair_exp(0.693147181f * ((1.0f - w) * la + w * lt)), 1.0f);
}

/* The probe light's multiple scattering: radiance per unit probe radiance that the AO took
 * away and the hair gives back (global part spread over the fibre's albedo, and back scattering
 * of the hair around). ao in (0, 1]; 1 (nothing around) gives 0. */
static inline clh_v3 clh_hair_dual_probe(const clh_hair_dual* ds, float ao) {
  ao = clamp(ao, 1e-4f, 1.0f);
  const float tau = -0.693147181f * clh_fast_log2(ao);
  const clh_v3 arrive = clh_dual_through3(ds, tau);
  const clh_v3 through = clh_v3_fmax(clh_v3_sub(arrive, clh_v3_splat(ao)), 0.0f);
  const clh_v3 reach = clh_v3_add(clh_v3_splat(ao), clh_v3_scale(through, CLH_DUAL_DF));
  /* what infinite hair behind sends back: d_b (R_inf - a_B) */
  const clh_v3 back = clh_v3_scale(ds->st.r_back, CLH_DUAL_DB);
  return clh_v3_add(clh_v3_scale(clh_v3_mul(through, ds->albedo), CLH_DUAL_DF),
                    clh_v3_scale(clh_v3_mul(reach, back), 1.0f - ao));
}

#endif /* CLHAIR_HAIR_DUAL_H */
