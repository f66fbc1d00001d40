/* hair_env.h — the hair BSDF's terms for probe (environment and ambient) lighting, from a
 * prepared clh_hair_view of hair_bsdf.h: the lobes' energies, the mirror direction and the
 * GGX roughness that stands for R + TRT (Lipp §3.4; docs/hair-shading.md §2).
 */
#ifndef CLHAIR_HAIR_ENV_H
#define CLHAIR_HAIR_ENV_H

#include "hair_bsdf.h"

/* ---- environment (probe) lighting, Lipp §3.4 -------------------------------------------
 * R and TRT as one GGX lobe around the mirror direction of wo about the view-facing fibre
 * normal n; TT and diffuse for an irradiance (SH) lookup. Radiance from a probe is then
 *   spec_weight * prefiltered(refl_dir, ggx_alpha)      (split-sum style, no extra cosine)
 * + diffuse_albedo * E(n) / pi  (+ tt_weight * E(-n) / pi, a crude forward-scatter term),
 * with E(n) the cosine-weighted irradiance about n.
 * ggx_alpha matches the mean cosine E[dot(wi, refl_dir)] of the h-averaged R+TRT lobes to
 * that of a GGX lobe at normal incidence (docs/hair-shading.md). */
typedef struct {
  clh_v3 spec_weight;    /* Ā_R + Ā_TRT (h-averaged energies at this theta_o) */
  clh_v3 tt_weight;      /* Ā_TT */
  clh_v3 diffuse_albedo; /* Ā_3 */
  clh_v3 n;              /* view-facing fibre normal */
  clh_v3 refl_dir;       /* mirror of wo about n (theta_i = -theta_o, phi = 0) */
  float ggx_alpha;
} clh_hair_env;

/* Mean cosine of a GGX reflection lobe is 2 (1/c + a² ln(a²)/c²) - 1, c = 1 - a²; its
 * inverse is fitted as a = sqrt(x) (0.31679 + 0.74467 x - 0.44206 x² + 0.38109 x³),
 * x = 1 - mean cosine (max error 0.004 in a). */
static inline float clh_hair_ggx_alpha_from_mean_cos(float mu) {
  float x = clamp(1.0f - mu, 1e-6f, 1.0f);
  return clamp(sqrt(x) * (0.31679f + x * (0.74467f + x * (-0.44206f + x * 0.38109f))), 0.002f,
               1.0f);
}

static inline void clh_hair_env_terms_to(clh_hair_env* out, const clh_hair_view* hv) {
  out->spec_weight = clh_v3_add(hv->mass[0], hv->mass[2]);
  out->tt_weight = hv->mass[1];
  out->diffuse_albedo = hv->mass[3];
  out->n = hv->n;
  /* wo = sin_o t + cos_o n */
  out->refl_dir = clh_v3_sub(clh_v3_scale(hv->n, hv->cos_o), clh_v3_scale(hv->t, hv->sin_o));
  /* E[cos phi] of each azimuthal lobe: panel-wise box averages of cos, times the logistic's
   * characteristic function at 1, pi s / sinh(pi s). R's phase is -2 gamma_o, and
   * cos(2 gamma_o) = 1 - 2 h² averages to 1 - 2 (h0² + h0 h1 + h1²) / 3 over a panel. */
  const float ps = CLH_HAIR_PI * hv->s;
  float lam = 2.0f * ps / (clh_hair_exp(ps) - clh_hair_exp(-ps)); /* pi s / sinh(pi s) */
  float c_r = 0.0f, w_r = 0.0f;
  clh_v3 c_trt = clh_v3_splat(0.0f), w_trt = clh_v3_splat(0.0f);
  for (int k = 0; k < 4; ++k) {
    float h0 = CLH_HAIR_PANEL_H(k), h1 = CLH_HAIR_PANEL_H(k + 1);
    float dh = h1 - h0;
    float f = clh_hair_fresnel(hv->cos_o * CLH_HAIR_PANEL_CM(k), hv->eta);
    float cr = 1.0f - (2.0f / 3.0f) * (h0 * h0 + h0 * h1 + h1 * h1);
    float p0 = hv->trt_phi[k], p1 = hv->trt_phi[k + 1];
    float s0, c0, s1, c1;
    clh_fast_sincos(p0, &s0, &c0);
    clh_fast_sincos(p1, &s1, &c1);
    float ct = fabs(p1 - p0) > 1e-4f ? (s1 - s0) / (p1 - p0) : c0;
    c_r += dh * f * cr;
    w_r += dh * f;
    c_trt = clh_v3_add(c_trt, clh_v3_scale(hv->trt_w[k], ct));
    w_trt = clh_v3_add(w_trt, hv->trt_w[k]);
  }
  const clh_v3 lum = clh_v3_make(0.2126f, 0.7152f, 0.0722f);
  float cos_phi_r = lam * c_r / fmax(w_r, 1e-8f);
  float lum_trt = clh_v3_dot(w_trt, lum);
  float cos_phi_trt = lam * clh_v3_dot(c_trt, lum) / fmax(lum_trt, 1e-12f);
  /* mean cosine to refl_dir of a lobe at theta_i = -theta_o + delta:
   * E[cos delta] (sin² theta_o + cos² theta_o E[cos phi]). delta is treated as a von Mises
   * angle of concentration k = 1/v about the tilt shift, E[cos delta] = I1(k)/I0(k) cos(shift),
   * with I1/I0 ~ k / (0.5 + sqrt(k² + 2.25)) (exact slopes at 0 and infinity, <2% error). */
  float s2 = hv->sin_o * hv->sin_o, c2 = hv->cos_o * hv->cos_o;
  float k0 = 1.0f / hv->v[0], k2 = 1.0f / hv->v[2];
  float a_r = k0 / (0.5f + sqrt(k0 * k0 + 2.25f)), a_trt = k2 / (0.5f + sqrt(k2 * k2 + 2.25f));
  float mu_r = a_r * hv->cos_shift[0] * (s2 + c2 * cos_phi_r);
  float mu_trt = a_trt * hv->cos_shift[2] * (s2 + c2 * cos_phi_trt);
  float wr = w_r, wt = 2.0f * lum_trt;
  float mu = (wr * mu_r + wt * mu_trt) / fmax(wr + wt, 1e-8f);
  out->ggx_alpha = clh_hair_ggx_alpha_from_mean_cos(mu);
}

#endif /* CLHAIR_HAIR_ENV_H */
