/* hair_aggregate.h — the aggregated BCSDF of a LOD strand that stands for a cluster of
 * fibres (Huang et al. 2024, §4), on top of the single-fibre model of hair_bsdf.h.
 *
 * Input: a prepared clh_hair_view and the cluster's shape (fibres k, drawn width w, depth t);
 * output: f_agg cos(theta_i) for a light direction. With k = 1 it is the single fibre's
 * value bit for bit. docs/hair-shading.md §6 derives the choices and measures them.
 */
#ifndef CLHAIR_HAIR_AGGREGATE_H
#define CLHAIR_HAIR_AGGREGATE_H

#include "hair_bsdf.h"

/* ---- aggregated BCSDF of a LOD strand (Huang et al. 2024, §4) ---------------------------
 * When LOD draws one strand, widened w times, in place of a cluster of k fibres, the light
 * scatters between the cluster's fibres before it leaves. Huang Eq. 7:
 *   f_agg = S(phi) [ sum_p M^_p N^_p + M_B^ N_B^ ]
 * - inherited lobes (Eq. 8-9): the fibre's R, TT, TRT and diffuse after the light crossed
 *   n - 1 other fibres of the cluster, each passing on the fraction a_F: N^_p = a_F^(n-1) N_p,
 *   and each widening the longitudinal lobe by the forward spread: v^_p = v_p + (n-1) v_TT.
 * - B^ lobe (Eq. 10-11): light sent back to the viewer's side by the fibres behind, with the
 *   dual-scattering paths A_1 = a_B a_F^2 / (1 - a_F^2), A_3 = a_B^3 a_F^2 / (1 - a_F^2)^3
 *   and Huang's A_1+ = d_1+ a_B sum_{i=1..n} a_F^(2i-1) (closed form), a constant azimuthal
 *   lobe over the back hemisphere (|phi| < pi/2, I_B / pi) and a Gaussian-like M with the
 *   variance of the R and TRT lobes summed (two back-scattering events at least).
 * - shadowing-masking (Eq. 12-15), for |phi| < pi/2 only (Huang §4: the back half's
 *   attenuation is the inherited lobes' a_F^(n-1)): P_s = (1 - rho)(1 - cos phi),
 *   P_m = (1 - rho) c_m, S = P_s a_F + max(0, 1 - P_s - P_m); S = 1 for |phi| >= pi/2.
 * The cluster's cross-section is Huang's ellipse, semi-axes w r across the view (the drawn
 * width, r the fibre radius) and t r along it, 1 <= w, t <= k (the caller's: see shade.cl,
 * where the LOD widening fixes t):
 * - density rho = k r^2 / (w r t r) = k / (w t) (at most 1), and a chord of length l meets
 *   n = rho l sqrt(k / (pi w t r^2)) fibres (Huang §4);
 * - light from the back half (cos phi < 0) reaches the view-facing fibre along the chord
 *   from that fibre to the far side, l = 2 r |cos phi| / (t (sin^2 phi / w^2 + cos^2 phi /
 *   t^2)) (2 t r straight from behind, 0 at |phi| = pi/2), and crosses the other
 *   n - 1 fibres on it, clamped to 0..k-1 (so k = 1 gives back the single fibre exactly);
 *   light from the front half reaches it directly (n = 1), where S acts;
 * - A_1+ sums over the fibres behind the shaded one along the view (the chord at phi = pi);
 * - a_F = A_TT + A_3 / 2 and a_B = A_R + A_TRT + A_3 / 2 from the fibre's h-averaged
 *   energies at theta_o (the hemispherical averages of dual scattering);
 * - A_1, A_3 and A_1+ are weighted by 1 - 1/k, the share of the cluster that is other
 *   fibres, and the B^ energy is capped at 1 - (the fibre's own energy), which keeps the
 *   aggregate within the white furnace. */
#define CLH_AGG_CM 0.2f  /* Huang Eq. 13 */
#define CLH_AGG_D1P 0.6f /* Huang Eq. 10 */

typedef struct {
  float rho;            /* strand density of the cluster's cross-section */
  float other;          /* 1 - 1/k: share of the cluster's fibres besides the shaded one */
  float per_r;          /* fibres met per fibre radius of chord */
  float inv_t2, inv_w2; /* 1 / t^2, 1 / w^2 */
  float t, n_max;       /* t, and the other fibres there are: k - 1 */
  clh_v3 ln_af;         /* ln a_F per channel */
  clh_v3 a_f;           /* forward attenuation of one fibre */
  clh_v3 b_weight;      /* A_B^ energy */
  float v_b, norm_b;
} clh_hair_agg;

static inline float clh_hair_agg_a1p(float a_f, float a_b, float n) {
  /* sum_{i=1..n} a_F^(2i-1) = a_F (1 - a_F^(2n)) / (1 - a_F^2), continued to real n */
  const float af2 = a_f * a_f;
  const float num =
      a_f * (1.0f - clh_hair_exp(2.0f * n * 0.693147181f * clh_fast_log2(fmax(a_f, 1e-8f))));
  return CLH_AGG_D1P * a_b * (af2 < 0.999f ? num / (1.0f - af2) : a_f * n);
}

static inline float clh_hair_agg_b(float a_f, float a_b, float n, float other, float own) {
  const float af2 = fmin(a_f * a_f, 0.999f);
  const float d = 1.0f - af2;
  const float a1 = a_b * af2 / d;
  const float a3 = a_b * a_b * a_b * af2 / (d * d * d);
  const float e = other * (a1 + a3 + clh_hair_agg_a1p(a_f, a_b, n));
  return fmin(e, fmax(1.0f - own, 0.0f));
}

/* Per pixel: the cluster of k >= 1 fibres the strand stands for, drawn w >= 1 times as wide
 * as one fibre, t >= 1 fibre widths deep along the view. */
static inline void clh_hair_agg_prepare_to(clh_hair_agg* out, const clh_hair_view* hv, float k,
                                           float w, float t) {
  k = fmax(k, 1.0f);
  w = clamp(w, 1.0f, k); /* k fibres fill at most k widths: the LOD widening never exceeds k */
  t = clamp(t, 1.0f, k); /* nor more than k depths */
  out->rho = fmin(k / (w * t), 1.0f);
  out->other = 1.0f - 1.0f / k;
  out->per_r = out->rho * sqrt(k / (CLH_HAIR_PI * w * t));
  out->inv_t2 = 1.0f / (t * t);
  out->inv_w2 = 1.0f / (w * w);
  out->t = t;
  out->n_max = k - 1.0f;
  /* the fibres behind the shaded one straight along the view: chord 2 t r */
  const float behind = clamp(2.0f * t * out->per_r - 1.0f, 0.0f, out->n_max);
  const clh_v3 half_d = clh_v3_scale(hv->mass[3], 0.5f);
  const clh_v3 a_f = clh_v3_add(hv->mass[1], half_d);
  const clh_v3 a_b = clh_v3_add(clh_v3_add(hv->mass[0], hv->mass[2]), half_d);
  const clh_v3 own =
      clh_v3_add(clh_v3_add(hv->mass[0], hv->mass[1]), clh_v3_add(hv->mass[2], hv->mass[3]));
  out->a_f = a_f;
  out->ln_af = clh_v3_make(0.693147181f * clh_fast_log2(fmax(a_f.x, 1e-8f)),
                           0.693147181f * clh_fast_log2(fmax(a_f.y, 1e-8f)),
                           0.693147181f * clh_fast_log2(fmax(a_f.z, 1e-8f)));
  out->b_weight = clh_v3_make(clh_hair_agg_b(a_f.x, a_b.x, behind, out->other, own.x),
                              clh_hair_agg_b(a_f.y, a_b.y, behind, out->other, own.y),
                              clh_hair_agg_b(a_f.z, a_b.z, behind, out->other, own.z));
  out->v_b = hv->v[0] + hv->v[2];
  out->norm_b = clh_hair_mnorm(out->v_b);
}

/* f_agg cos(theta_i) for a light: the aggregated counterpart of clh_hair_eval_cos (equal to
 * it when k = 1: then no other fibre is crossed, S = 1 and the B^ lobe is zero).
 * attenuate = 0 leaves out the a_F^(n-1) of the fibres crossed (their spread stays): for a
 * light whose transmittance through the hair already counts them (shade.cl: a deep opacity
 * map drawn with the LOD's coverage compensation, or a visibility bake of every fibre). */
static inline clh_v3 clh_hair_agg_eval_cos(const clh_hair_view* hv, const clh_hair_agg* ag,
                                           clh_v3 wi, int attenuate) {
  float sin_i, cos_i, cos_phi;
  clh_hair_angles_to(hv, wi, &sin_i, &cos_i, &cos_phi);
  float phi = clh_fast_acos(cos_phi);
  /* inherited lobes (Eq. 8-9): the other fibres on the chord toward a light behind */
  float nm1 = 0.0f;
  if (cos_phi < 0.0f) {
    const float c2 = cos_phi * cos_phi;
    const float l_r = -2.0f * cos_phi / (ag->t * (c2 * ag->inv_t2 + (1.0f - c2) * ag->inv_w2));
    nm1 = clamp(l_r * ag->per_r - 1.0f, 0.0f, ag->n_max);
  }
  float m[3];
  for (int p = 0; p < 3; ++p) {
    const float v = hv->v[p] + nm1 * hv->v[1];
    const float norm = nm1 > 0.0f ? clh_hair_mnorm(v) : hv->m_norm[p];
    m[p] = clh_hair_mp(sin_i, cos_i, hv->sin_o_tilt[p], hv->cos_o_tilt[p], v, norm);
  }
  clh_v3 f = clh_v3_add(clh_v3_add(clh_v3_add(clh_v3_splat(m[0] * clh_hair_n_r(hv, phi)),
                                              clh_v3_scale(clh_hair_n_tt(hv, phi), m[1])),
                                   clh_v3_scale(clh_hair_n_trt(hv, phi), m[2])),
                        clh_v3_scale(clh_hair_diffuse(hv), cos_i));
  if (attenuate && nm1 > 0.0f) f = clh_v3_mul(f, clh_hair_exp3(clh_v3_scale(ag->ln_af, nm1)));
  if (cos_phi <= 0.0f) return f;
  /* front half: B^ lobe (Eq. 10-11) and shadowing-masking (Eq. 12-15) */
  const float mb =
      clh_hair_mp(sin_i, cos_i, hv->sin_o, hv->cos_o, ag->v_b, ag->norm_b) * (1.0f / CLH_HAIR_PI);
  f = clh_v3_add(f, clh_v3_scale(ag->b_weight, mb));
  const float ps = (1.0f - ag->rho) * (1.0f - cos_phi);
  const float pn = fmax(1.0f - ps - (1.0f - ag->rho) * CLH_AGG_CM, 0.0f);
  const clh_v3 S = clh_v3_add(clh_v3_scale(ag->a_f, ps), clh_v3_splat(pn));
  return clh_v3_mul(S, f);
}

#endif /* CLHAIR_HAIR_AGGREGATE_H */
