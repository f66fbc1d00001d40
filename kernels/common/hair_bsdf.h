/* hair_bsdf.h — real-time far-field hair BSDF for the deferred shading pass.
 *
 * A float, closed-form evaluation of the h-averaged Chiang et al. 2016 model (the G-buffer
 * stores no offset h across the fibre), in the spirit of Pekelis et al. 2015 and Lipp et al.
 * §3.4: R, TT and TRT lobes plus a Kajiya-Kay-like diffuse term that carries the p >= 3
 * energy. docs/hair-shading.md derives every approximation and lists the measured errors
 * against the double-precision reference in tests/reference/chiang_reference.cpp.
 *
 * Inputs: a clh_hair_material, a unit fibre tangent t (root to tip), unit wo (to the eye)
 * and wi (to the light). Output: f(wo, wi) WITHOUT the cosine: reflected radiance is
 *     L_o = f * cos(theta_i) * E_light,   cos(theta_i) = sqrt(1 - dot(t, wi)^2)
 * (clh_hair_cos_theta). Energy: ∫ f cos(theta_i) dw_i <= 1 for every wo.
 *
 * Model, per lobe p (the longitudinal part does not depend on h, so it factors out exactly):
 *   f = Σ_{p=0..2} M_p(theta_i, theta_o) Ñ_p(phi; theta_o) / cos(theta_i) + Ā_3 / pi²
 *   M_p : d'Eon's Bessel form with Chiang's variances and cuticle tilt on theta_o (pbrt-v4
 *         convention), I0 by Abramowitz & Stegun 9.8.1-2 — same function as the reference.
 *   Ñ_0 : R. Zero-roughness limit  ¼ |cos(phi/2)| F(cos theta_o |cos(phi/2)|)  (exact
 *         change of variables h = -sin(phi/2)), blurred by the logistic with a 3-tap rule.
 *   Ñ_1 : TT. Zero-roughness limit by inverting Phi_1(h) in closed form
 *         (tan gamma_o = sin x / (cos x - 1/eta'), x = (pi - phi)/2), 3-tap logistic blur.
 *   Ñ_2 : TRT. Its phase Phi_2(h) has caustics, so it is approximated as piecewise linear on
 *         4 fixed gamma_o panels; each panel is one analytic lobe (a box convolved with the
 *         logistic = a difference of two logistic CDFs).
 *   Ā_3 : p >= 3 energy from the same 4 panels, spread as a constant f (Kajiya-Kay diffuse).
 * All stay valid for beta_m in [0.1, 1], beta_n in [0.15, 0.6] (fitted and tested at 0.2-0.5),
 * eta in [1.4, 1.7] (panels were placed for eta = 1.55).
 *
 * Typical use in a shading kernel:
 *   clh_hair_view hv; clh_hair_prepare_to(&hv, &mat, t, wo);   // once per pixel
 *   for each light: L += clh_hair_eval_cos(&hv, wi) * E;       // = f cos(theta_i) E
 * (directions and colours as clh_v3, kernels/common/clh_math.h).
 */
#ifndef CLHAIR_HAIR_BSDF_H
#define CLHAIR_HAIR_BSDF_H

#include "clh_math.h"

#define CLH_HAIR_PI 3.14159265358979323846f

/* Everything here is arithmetic on floats and clh_v3 (clh_math.h) with fixed-trip loops and
 * no library calls besides sqrt (DESIGN.md, "Vectorizable kernels"). A clh_v3 holds a
 * direction, an RGB triple, or three values of one kind evaluated together: the three taps
 * of a lobe's blur, the three lobes' M_p. On the device it is a float3, which a CPU
 * evaluates in one SIMD instruction; each component gets the same operations as a scalar
 * evaluation, so the results are the same bits (DESIGN.md, "Shading three values at a
 * time"). The elementary functions are the straight-line ones of clhair/fast_math.h
 * (relative errors below 1e-6, far under the model's own errors in docs/hair-shading.md),
 * lane by lane through clh_math.h's clh_v3_exp, clh_v3_log2 and clh_v3_sincos. A few early
 * returns skip work whose result is known to the bit: a logistic term whose exponential
 * rounds away next to 1, a TT lobe none of whose taps has a root; they return exactly what
 * the full evaluation would (PoCL runs the shading kernel one pixel at a time, where skipped
 * work is time saved; DESIGN.md, "Shading: work skipped to the bit"). */
static inline float clh_hair_exp(float x) { return clh_fast_exp(x); }
static inline clh_v3 clh_hair_exp3(clh_v3 x) { return clh_v3_exp(x); }

typedef struct {
  clh_v3 sigma_a; /* absorption per unit fibre radius, per RGB channel */
  float beta_m;   /* longitudinal roughness, 0..1 */
  float beta_n;   /* azimuthal roughness, 0..1 */
  float alpha;    /* cuticle tilt in radians (about 2 degrees for human hair) */
  float eta;      /* index of refraction of the fibre, 1.55 for keratin */
} clh_hair_material;

/* Everything that depends on the material and wo only: computed once per pixel. */
typedef struct {
  clh_v3 t;           /* unit tangent */
  clh_v3 n;           /* unit fibre normal facing wo (wo projected on the normal plane) */
  clh_v3 sigma_path;  /* sigma_a / cos(theta_t): 2 cos(gamma_t) * this is the optical depth */
  clh_v3 trt_w[4];    /* TRT panel weights ½ Δh A_2 (h_mid) */
  clh_v3 mass[4];     /* h-averaged energies Ā_0..Ā_3 (panel estimates) */
  float trt_phi[5];   /* TRT phase Phi_2 at the panel breakpoints */
  float trt_width[4]; /* max(|Phi_2(h_k+1) - Phi_2(h_k)|, 1e-4) */
  float sin_o, cos_o;
  float sin_o_tilt[3], cos_o_tilt[3]; /* theta_o shifted by -2a, a, 4a for R, TT, TRT */
  float v[3];                         /* longitudinal variances of R, TT, TRT */
  float m_norm[3];                    /* 1 / (v (1 - e^{-2/v})) of each M_p */
  clh_v3 lobe_sin_o, lobe_cos_o;      /* sin_o_tilt, cos_o_tilt as one vector (R, TT, TRT) */
  clh_v3 lobe_v, lobe_norm;           /* v, m_norm as one vector (clh_hair_mp3) */
  float cos_shift[3];                 /* cos of the tilt shifts */
  float eta, inv_eta_p, s, inv_s, blur, trim;
} clh_hair_view;

/* ---- small helpers ------------------------------------------------------------------- */

static inline float clh_hair_sqrt0(float x) { return sqrt(fmax(x, 0.0f)); }

/* Unpolarised dielectric Fresnel reflectance from air at cos(theta) (no TIR from outside). */
static inline float clh_hair_fresnel(float cos_i, float eta) {
  cos_i = clamp(cos_i, 0.0f, 1.0f);
  float sin_t2 = (1.0f - cos_i * cos_i) / (eta * eta);
  float cos_t = clh_hair_sqrt0(1.0f - sin_t2);
  float r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  float r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (r_par * r_par + r_perp * r_perp);
}

/* clh_hair_fresnel of each component of cos_i, the same operations. */
static inline clh_v3 clh_hair_fresnel3(clh_v3 cos_i, float eta) {
  cos_i = clh_v3_clamp(cos_i, 0.0f, 1.0f);
  const clh_v3 sin_t2 = (1.0f - cos_i * cos_i) / (eta * eta);
  const clh_v3 cos_t = clh_v3_sqrt(clh_v3_fmax(1.0f - sin_t2, 0.0f));
  const clh_v3 r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const clh_v3 r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (r_par * r_par + r_perp * r_perp);
}

/* The polynomials of Abramowitz & Stegun 9.8.1 (I0(x) for x < 3.75, in y = (x / 3.75)^2) and
 * 9.8.2 (sqrt(x) e^{-x} I0(x) for x >= 3.75, in yl = 3.75 / x), as the handbook prints
 * them; written for a float or a clh_v3 alike. */
/* clang-format off */
#define CLH_HAIR_I0_SMALL(y) \
  (1.0f + (y) * (3.5156229f + (y) * (3.0899424f + (y) * (1.2067492f + \
   (y) * (0.2659732f + (y) * (0.0360768f + (y) * 0.0045813f))))))
#define CLH_HAIR_I0E_LARGE(yl) \
  (0.39894228f + (yl) * (0.01328592f + (yl) * (0.00225319f + (yl) * (-0.00157565f + \
   (yl) * (0.00916281f + (yl) * (-0.02057706f + (yl) * (0.02635537f + (yl) * (-0.01647633f + \
   (yl) * 0.00392377f))))))))
/* clang-format on */

/* e^{-x} I0(x) for x >= 0 times e^{e} (one exponential for both), Abramowitz & Stegun
 * 9.8.1 / 9.8.2 (relative error < 2e-7). Only the polynomial of x's range is evaluated. */
static inline float clh_hair_i0e_exp(float x, float e) {
  if (x < 3.75f) {
    const float y = (x / 3.75f) * (x / 3.75f);
    return CLH_HAIR_I0_SMALL(y) * clh_hair_exp(e - x);
  }
  const float yl = 3.75f / x;
  return CLH_HAIR_I0E_LARGE(yl) / sqrt(x) * clh_hair_exp(e);
}

/* Longitudinal lobe M_p (d'Eon et al. 2011; Chiang Eq. 3), normalised over cos(theta_i):
 * M = exp(-b) I0(a) / (2 v sinh(1/v)) with a = cos_i cos_o / v, b = sin_i sin_o / v,
 * written as exp((cos(theta_i + theta_o) - 1) / v) I0e(a) / (v (1 - e^{-2/v})) so that
 * nothing overflows for small v; norm = 1 / (v (1 - e^{-2/v})) comes from the view. */
static inline float clh_hair_mp(float sin_i, float cos_i, float sin_o, float cos_o, float v,
                                float norm) {
  float a = cos_i * cos_o / v;
  float e = (cos_i * cos_o - sin_i * sin_o - 1.0f) / v;
  return clh_hair_i0e_exp(a, e) * norm;
}

/* 1 / (v (1 - e^{-2/v})): the normalisation of M_p for variance v. */
static inline float clh_hair_mnorm(float v) {
  const float y = 2.0f / v;
  /* from 2/v = 18 on, e^{-2/v} < 1.6e-8 is less than half the spacing of floats below 1
   * (3e-8): 1 - e^{-2/v} rounds to 1 and the result is 1/v exactly */
  if (!(y < 18.0f)) return 1.0f / v;
  return 1.0f / (v * (1.0f - clh_hair_exp(-y)));
}

/* The three lobes' M_p at once (R, TT, TRT as the components; sin_o, cos_o, v and norm per
 * lobe): clh_hair_mp and clh_hair_mnorm component by component, the same operations (both
 * polynomials are evaluated, each component keeps the one of its range). */
static inline clh_v3 clh_hair_mnorm3(clh_v3 v) {
  const clh_v3 y = 2.0f / v;
  return clh_v3_if_less(y, 18.0f, 1.0f / (v * (1.0f - clh_v3_exp(-y))), 1.0f / v);
}

static inline clh_v3 clh_hair_mp3(float sin_i, float cos_i, clh_v3 sin_o, clh_v3 cos_o, clh_v3 v,
                                  clh_v3 norm) {
  const clh_v3 x = cos_i * cos_o / v;
  const clh_v3 e = (cos_i * cos_o - sin_i * sin_o - 1.0f) / v;
  const clh_v3 y = (x / 3.75f) * (x / 3.75f), xl = clh_v3_fmax(x, 3.75f), yl = 3.75f / xl;
  const clh_v3 i0e =
      clh_v3_if_less(x, 3.75f, CLH_HAIR_I0_SMALL(y), CLH_HAIR_I0E_LARGE(yl) / clh_v3_sqrt(xl));
  return i0e * clh_v3_exp(clh_v3_if_less(x, 3.75f, e - x, e)) * norm;
}

/* Logistic CDF with scale 1 / inv_s. */
static inline float clh_hair_lcdf(float x, float inv_s) {
  const float y = x * inv_s;
  /* from y = 17 on, 1 + e^{-y} rounds to 1 (e^{-y} < 4.2e-8 is less than half the spacing
   * of floats above 1, 6e-8) and the result is 1 exactly */
  if (!(y < 17.0f)) return 1.0f;
  return 1.0f / (1.0f + clh_hair_exp(-y));
}

/* |x| smoothed over a logistic of scale k: E|x + X| = |x| + 2k ln(1 + e^{-|x|/k}), for each
 * component. From |x|/k = 17 on, 1 + e^{-|x|/k} rounds to 1 (as in clh_hair_lcdf), whose
 * log2 is 0: the sum is |x| exactly there, which is what those components take. */
static inline clh_v3 clh_hair_softabs3(clh_v3 x, float k) {
  const clh_v3 ax = clh_v3_fabs(x), y = ax / k;
  const clh_v3 smooth = ax + (2.0f * k * 0.693147181f) * clh_v3_log2(1.0f + clh_v3_exp(-y));
  return clh_v3_if_less(y, 17.0f, smooth, ax);
}

/* Wraps angles to [0, pi] for the even, 2pi-periodic azimuthal functions. */
static inline clh_v3 clh_hair_fold3(clh_v3 phi) {
  phi = clh_v3_fabs(phi);
  phi = clh_v3_if_greater(phi, CLH_HAIR_PI, 2.0f * CLH_HAIR_PI - phi, phi);
  return clh_v3_clamp(phi, 0.0f, CLH_HAIR_PI);
}

/* ---- roughness mappings (Chiang Eq. 7-8) ----------------------------------------------- */

static inline float clh_hair_v0(float bm) {
  float b2 = bm * bm, b4 = b2 * b2, b5 = b4 * bm, b10 = b5 * b5, b20 = b10 * b10;
  float r = 0.726f * bm + 0.812f * b2 + 3.7f * b20;
  return r * r;
}

static inline float clh_hair_logistic_s(float bn) {
  float b2 = bn * bn, b4 = b2 * b2, b5 = b4 * bn, b10 = b5 * b5, b22 = b10 * b10 * b2;
  return 0.626657069f * (0.265f * bn + 1.194f * b2 + 5.372f * b22);
}

/* ---- absorption from melanin or from a colour ------------------------------------------ */

/* sigma_a from eumelanin / pheomelanin concentrations (Chiang Eq. 11, pbrt-v4 RGB values). */
static inline clh_v3 clh_hair_sigma_a_from_melanin(float eumelanin, float pheomelanin) {
  const float eu = fmax(eumelanin, 0.0f), ph = fmax(pheomelanin, 0.0f);
  return clh_v3_make(eu * 0.419f + ph * 0.187f, eu * 0.697f + ph * 0.4f, eu * 1.37f + ph * 1.05f);
}

/* sigma_a that yields roughly colour c after multiple scattering (Chiang Eq. 9). */
static inline clh_v3 clh_hair_sigma_a_from_color(clh_v3 c, float bn) {
  float b2 = bn * bn, b3 = b2 * bn, b4 = b2 * b2, b5 = b4 * bn;
  float d = 5.969f - 0.215f * bn + 2.532f * b2 - 10.73f * b3 + 5.574f * b4 + 0.245f * b5;
  const float k = 0.693147181f / d; /* ln(c) / d from log2 */
  const float lx = clh_fast_log2(clamp(c.x, 1e-4f, 1.0f)) * k;
  const float ly = clh_fast_log2(clamp(c.y, 1e-4f, 1.0f)) * k;
  const float lz = clh_fast_log2(clamp(c.z, 1e-4f, 1.0f)) * k;
  return clh_v3_make(lx * lx, ly * ly, lz * lz);
}

/* ---- the azimuthal lobes -------------------------------------------------------------- */

/* The three taps of the blur below at phi: phi itself and phi +- sqrt(3) sigma folded back
 * into [0, pi], as the components of one vector (each lobe evaluates its taps together). */
static inline clh_v3 clh_hair_taps(const clh_hair_view* hv, float phi) {
  clh_v3 taps = clh_hair_fold3(clh_v3_make(phi, phi + hv->blur, phi - hv->blur));
  taps.x = phi;
  return taps;
}

/* R in the zero-roughness limit at |phi| in [0, pi] (each component a tap); the kink at
 * phi = pi is pre-smoothed over 0.3 s (fitted, docs/hair-shading.md). */
static inline clh_v3 clh_hair_r_delta3(const clh_hair_view* hv, clh_v3 phi) {
  const clh_v3 u = clh_hair_softabs3(CLH_HAIR_PI - phi, 0.3f * hv->s);
  clh_v3 c, unused;
  clh_v3_sincos(0.5f * clh_v3_fmin(u, CLH_HAIR_PI), &c, &unused);
  return 0.25f * c * clh_hair_fresnel3(hv->cos_o * c, hv->eta);
}

/* TT in the zero-roughness limit at |phi| in [0, pi] (each component of phi a tap): ½ A_1(h)
 * / |dPhi_1/dh| at the single root h of Phi_1(h) = phi (h >= 0 branch; the h < 0 branch gives
 * -phi). Zero where cos x <= 1/eta' (no root). Tap k's RGB is (out[0].k, out[1].k, out[2].k);
 * returns false, out untouched, when no tap has a root. */
static inline bool clh_hair_tt_delta3(const clh_hair_view* hv, clh_v3 phi, clh_v3 out[3]) {
  const clh_v3 x = 0.5f * (CLH_HAIR_PI - phi); /* gamma_o - gamma_t */
  clh_v3 sin_x, cos_x;
  clh_v3_sincos(x, &sin_x, &cos_x);
  const clh_v3 den0 = cos_x - hv->inv_eta_p;
  if (!clh_v3_any_greater(den0, 1e-6f)) return false;
  const clh_v3 one = clh_v3_splat(1.0f);
  const clh_v3 den = clh_v3_if_greater(den0, 1e-6f, den0, one); /* taps without a root: any */
  /* gamma_o = atan2(sin x, den): its cosine and sine directly */
  const clh_v3 inv_len = 1.0f / clh_v3_sqrt(sin_x * sin_x + den * den);
  const clh_v3 cos_go = den * inv_len;
  const clh_v3 sin_gt = sin_x * inv_len * hv->inv_eta_p;
  const clh_v3 cos_gt = clh_v3_sqrt(clh_v3_fmax(1.0f - sin_gt * sin_gt, 0.0f));
  const clh_v3 f = clh_hair_fresnel3(hv->cos_o * cos_go, hv->eta);
  /* 1 / |dPhi/dh| = 1 / (2/cos_go - 2/(eta' cos_gt)), written without the 1/cos_go pole */
  const clh_v3 eta_p_cgt = cos_gt / hv->inv_eta_p;
  const clh_v3 jac = cos_go * eta_p_cgt / (2.0f * clh_v3_fmax(eta_p_cgt - cos_go, 1e-6f));
  const clh_v3 w =
      clh_v3_if_greater(den0, 1e-6f, 0.5f * (1.0f - f) * (1.0f - f) * jac, clh_v3_splat(0.0f));
  const clh_v3 depth = -2.0f * cos_gt; /* times sigma_path: the optical depth, per channel */
  out[0] = clh_v3_exp(depth * hv->sigma_path.x) * w;
  out[1] = clh_v3_exp(depth * hv->sigma_path.y) * w;
  out[2] = clh_v3_exp(depth * hv->sigma_path.z) * w;
  return true;
}

/* 3-tap blur with the logistic: nodes 0, ±sqrt(3) sigma, weights 2/3, 1/6 (exact for a
 * Gaussian kernel up to degree 5; the logistic's variance is pi² s² / 3). */
static inline float clh_hair_n_r(const clh_hair_view* hv, float phi) {
  const clh_v3 r = clh_hair_r_delta3(hv, clh_hair_taps(hv, phi));
  return (2.0f / 3.0f) * r.x + (1.0f / 6.0f) * (r.y + r.z);
}

static inline clh_v3 clh_hair_n_tt(const clh_hair_view* hv, float phi) {
  clh_v3 t[3];
  if (!clh_hair_tt_delta3(hv, clh_hair_taps(hv, phi), t)) return clh_v3_splat(0.0f);
  return clh_v3_add(clh_v3_scale(clh_v3_make(t[0].x, t[1].x, t[2].x), 2.0f / 3.0f),
                    clh_v3_scale(clh_v3_add(clh_v3_make(t[0].y, t[1].y, t[2].y),
                                            clh_v3_make(t[0].z, t[1].z, t[2].z)),
                                 1.0f / 6.0f));
}

/* TRT: each panel is the logistic averaged over its phase interval [p_k, p_k+1] (a box
 * convolved with the logistic: a difference of two logistic CDFs over the width), at phi
 * for the panels of h > 0 and at -phi for their mirror images. Neighbouring panels share
 * the CDF at their common breakpoint, so 10 CDFs serve the 8 boxes. A degenerate panel
 * (width below 1e-4) takes the logistic density instead. */
static inline clh_v3 clh_hair_n_trt(const clh_hair_view* hv, float phi) {
  float cp[5], cm[5];
  for (int k = 0; k < 5; ++k) {
    cp[k] = clh_hair_lcdf(phi - hv->trt_phi[k], hv->inv_s);
    cm[k] = clh_hair_lcdf(-phi - hv->trt_phi[k], hv->inv_s);
  }
  clh_v3 r = clh_v3_splat(0.0f);
  for (int k = 0; k < 4; ++k) {
    const float w = hv->trt_width[k];
    const bool thin = fabs(hv->trt_phi[k + 1] - hv->trt_phi[k]) < 1e-4f;
    const float bp = thin ? cp[k] * (1.0f - cp[k]) * hv->inv_s : fabs(cp[k] - cp[k + 1]) / w;
    const float bm = thin ? cm[k] * (1.0f - cm[k]) * hv->inv_s : fabs(cm[k] - cm[k + 1]) / w;
    r = clh_v3_add(r, clh_v3_scale(hv->trt_w[k], bp + bm));
  }
  return clh_v3_scale(r, hv->trim);
}

/* ---- per-pixel preparation ------------------------------------------------------------ */

/* TRT/diffuse panels on gamma_o in [0, pi/2] (breakpoints 0, 0.5942, 1.0038, 1.3361, pi/2,
 * placed by minimising the TRT error over theta_o and sigma_a; docs/hair-shading.md). */
#define CLH_HAIR_PANEL_H(k) \
  ((k) == 0 ? 0.0f : (k) == 1 ? 0.5598461f : (k) == 2 ? 0.8435181f : (k) == 3 ? 0.9725850f : 1.0f)
#define CLH_HAIR_PANEL_HM(k) \
  ((k) == 0 ? 0.2927485f : (k) == 1 ? 0.7166590f : (k) == 2 ? 0.9207311f : 0.9931226f)
#define CLH_HAIR_PANEL_CM(k) \
  ((k) == 0 ? 0.9561895f : (k) == 1 ? 0.6974237f : (k) == 2 ? 0.3901977f : 0.1170790f)

/* sigma_a of a fibre whose own albedo (the energy it scatters, every lobe together) is c
 * at normal incidence: what a strand file's colour means (the colour a strand shows under
 * white light, not the colour of a dense volume of it, which Chiang Eq. 9 maps). Per
 * channel, the fibre's energy F + (1 - F)^2 T / (1 - F T) (all paths p >= 0 summed, one
 * mean Fresnel F and one mean transmittance T = e^{-kappa sigma_a}) is inverted for T, with
 * F the h-average of the Fresnel factor at theta_o = 0 and kappa = 2 E_h[cos gamma_t], both
 * from the 4 panels of clh_hair_prepare_to; so the shading's Ā_0..3 at theta_o = 0 sum to c
 * within a few % (tests/test_dual.cpp). Colours below F (no fibre is that dark) clamp. */
static inline float clh_hair_sigma_a_channel(float c, float f, float kappa) {
  const float e = fmax(c - f, 1e-4f);
  const float t = e / ((1.0f - f) * (1.0f - f) + f * e);
  return fmin(-0.693147181f * clh_fast_log2(fmin(t, 1.0f)) / kappa, 40.0f);
}

static inline clh_v3 clh_hair_sigma_a_from_albedo(clh_v3 c, float eta) {
  float f = 0.0f, kappa = 0.0f;
  const float inv_eta = 1.0f / eta;
  for (int k = 0; k < 4; ++k) {
    const float dh = CLH_HAIR_PANEL_H(k + 1) - CLH_HAIR_PANEL_H(k);
    const float sin_gt = CLH_HAIR_PANEL_HM(k) * inv_eta;
    f += dh * clh_hair_fresnel(CLH_HAIR_PANEL_CM(k), eta);
    kappa += dh * 2.0f * sqrt(fmax(1.0f - sin_gt * sin_gt, 0.0f));
  }
  return clh_v3_make(clh_hair_sigma_a_channel(clamp(c.x, 0.0f, 1.0f), f, kappa),
                     clh_hair_sigma_a_channel(clamp(c.y, 0.0f, 1.0f), f, kappa),
                     clh_hair_sigma_a_channel(clamp(c.z, 0.0f, 1.0f), f, kappa));
}

/* Written through `out` (no struct returned by value: Oclgrind's LLVM lacks the
 * noalias-scope intrinsic clang emits when one is inlined). */
static inline void clh_hair_prepare_to(clh_hair_view* out, const clh_hair_material* m, clh_v3 t,
                                       clh_v3 wo) {
  out->t = t;
  out->eta = m->eta;
  float sin_o = clamp(clh_v3_dot(t, wo), -1.0f, 1.0f);
  clh_v3 wp = clh_v3_sub(wo, clh_v3_scale(t, sin_o));
  float l2 = clh_v3_dot(wp, wp);
  float cos_o = clamp(sqrt(l2), 1e-4f, 1.0f);
  out->sin_o = sin_o;
  out->cos_o = cos_o;
  /* looking along the fibre: any normal */
  const clh_v3 ax =
      fabs(t.x) < 0.9f ? clh_v3_make(1.0f, 0.0f, 0.0f) : clh_v3_make(0.0f, 1.0f, 0.0f);
  const clh_v3 axp = clh_v3_sub(ax, clh_v3_scale(t, clh_v3_dot(ax, t)));
  out->n = l2 > 1e-12f ? clh_v3_scale(wp, 1.0f / sqrt(l2)) : clh_v3_unit(axp);

  /* longitudinal terms; tilt on theta_o: R -2a, TT +a, TRT +4a (pbrt-v4 convention) */
  float v0 = fmax(clh_hair_v0(clamp(m->beta_m, 0.05f, 1.0f)), 1e-4f);
  out->v[0] = v0;
  out->v[1] = 0.25f * v0;
  out->v[2] = 4.0f * v0;
  for (int p = 0; p < 3; ++p) {
    const float shift = (p == 0 ? -2.0f : p == 1 ? 1.0f : 4.0f) * m->alpha;
    float cs, sn;
    clh_fast_sincos(shift, &sn, &cs);
    out->cos_shift[p] = cs;
    out->sin_o_tilt[p] = sin_o * cs + cos_o * sn;
    out->cos_o_tilt[p] = fabs(cos_o * cs - sin_o * sn);
    out->m_norm[p] = clh_hair_mnorm(out->v[p]);
  }
  out->lobe_sin_o = clh_v3_make(out->sin_o_tilt[0], out->sin_o_tilt[1], out->sin_o_tilt[2]);
  out->lobe_cos_o = clh_v3_make(out->cos_o_tilt[0], out->cos_o_tilt[1], out->cos_o_tilt[2]);
  out->lobe_v = clh_v3_make(out->v[0], out->v[1], out->v[2]);
  out->lobe_norm = clh_v3_make(out->m_norm[0], out->m_norm[1], out->m_norm[2]);

  /* azimuthal terms */
  out->s = clh_hair_logistic_s(clamp(m->beta_n, 0.1f, 1.0f));
  out->inv_s = 1.0f / out->s;
  out->blur = CLH_HAIR_PI * out->s; /* sqrt(3) x the logistic's std. dev. pi s / sqrt(3) */
  out->trim =
      1.0f / (clh_hair_lcdf(CLH_HAIR_PI, out->inv_s) - clh_hair_lcdf(-CLH_HAIR_PI, out->inv_s));
  float eta_p = clh_hair_sqrt0(m->eta * m->eta - sin_o * sin_o) / cos_o;
  out->inv_eta_p = 1.0f / eta_p;
  float sin_t = sin_o / m->eta;
  float cos_t = clh_hair_sqrt0(1.0f - sin_t * sin_t);
  out->sigma_path = clh_v3_scale(clh_v3_fmax(m->sigma_a, 0.0f), 1.0f / cos_t);

  /* panels: TRT phase at the breakpoints, attenuations at the panel midpoints */
  for (int k = 0; k < 5; ++k) {
    float h = CLH_HAIR_PANEL_H(k);
    out->trt_phi[k] = 4.0f * clh_fast_asin(h * out->inv_eta_p) - 2.0f * clh_fast_asin(h);
  }
  for (int p = 0; p < 4; ++p) out->mass[p] = clh_v3_splat(0.0f);
  /* the panels' Fresnel factors, three of them as one vector */
  const clh_v3 f012 = clh_hair_fresnel3(
      cos_o * clh_v3_make(CLH_HAIR_PANEL_CM(0), CLH_HAIR_PANEL_CM(1), CLH_HAIR_PANEL_CM(2)),
      m->eta);
  const float fk[4] = {f012.x, f012.y, f012.z,
                       clh_hair_fresnel(cos_o * CLH_HAIR_PANEL_CM(3), m->eta)};
  for (int k = 0; k < 4; ++k) {
    out->trt_width[k] = fmax(fabs(out->trt_phi[k + 1] - out->trt_phi[k]), 1e-4f);
    float hm = CLH_HAIR_PANEL_HM(k);
    float dh = CLH_HAIR_PANEL_H(k + 1) - CLH_HAIR_PANEL_H(k);
    float sin_gt = hm * out->inv_eta_p;
    float cos_gt = clh_hair_sqrt0(1.0f - sin_gt * sin_gt);
    const float f = fk[k];
    clh_v3 T = clh_hair_exp3(clh_v3_scale(out->sigma_path, -2.0f * cos_gt));
    clh_v3 a1 = clh_v3_scale(T, (1.0f - f) * (1.0f - f));
    clh_v3 a2 = clh_v3_scale(clh_v3_mul(a1, T), f);
    clh_v3 a3 = a2 * f * T / (1.0f - f * T);
    out->trt_w[k] = clh_v3_scale(a2, 0.5f * dh);
    out->mass[0] = clh_v3_add(out->mass[0], clh_v3_splat(dh * f));
    out->mass[1] = clh_v3_add(out->mass[1], clh_v3_scale(a1, dh));
    out->mass[2] = clh_v3_add(out->mass[2], clh_v3_scale(a2, dh));
    out->mass[3] = clh_v3_add(out->mass[3], clh_v3_scale(a3, dh));
  }
}

/* ---- evaluation ----------------------------------------------------------------------- */

/* cos(theta_i): the cosine the caller multiplies f by. */
static inline float clh_hair_cos_theta(clh_v3 t, clh_v3 wi) {
  clh_v3 wp = clh_v3_sub(wi, clh_v3_scale(t, clh_v3_dot(t, wi))); /* accurate near the axis */
  return fmin(sqrt(clh_v3_dot(wp, wp)), 1.0f);
}

/* Diffuse (multiple-scattering) term: a constant f = Ā_3 / pi², so that f cos(theta_i)
 * integrates to Ā_3 over the sphere (∫ cos(theta) dw = pi²) — Kajiya-Kay's diffuse lobe
 * carrying exactly the energy the reference puts into p >= 3. */
static inline clh_v3 clh_hair_diffuse_albedo(const clh_hair_view* hv) { return hv->mass[3]; }

static inline clh_v3 clh_hair_diffuse(const clh_hair_view* hv) {
  return clh_v3_scale(hv->mass[3], 1.0f / (CLH_HAIR_PI * CLH_HAIR_PI));
}

/* sin(theta_i), cos(theta_i) and cos(phi) of wi about the prepared fibre. */
static inline void clh_hair_angles_to(const clh_hair_view* hv, clh_v3 wi, float* sin_i,
                                      float* cos_i, float* cos_phi) {
  *sin_i = clamp(clh_v3_dot(hv->t, wi), -1.0f, 1.0f);
  clh_v3 wp = clh_v3_sub(wi, clh_v3_scale(hv->t, *sin_i));
  float l2 = clh_v3_dot(wp, wp);
  *cos_i = fmin(sqrt(l2), 1.0f); /* |wi_perp|: no cancellation near the fibre axis */
  *cos_phi =
      l2 > 1e-12f ? clamp(clh_v3_dot(wp, hv->n) / sqrt(fmax(l2, 1e-12f)), -1.0f, 1.0f) : 1.0f;
}

/* The three specular lobes times cos(theta_i), i.e. M_p Ñ_p (what a light loop needs; no
 * division, so it stays exact as wi approaches the fibre axis), at the angles of
 * clh_hair_angles_to (a light loop that needs them elsewhere too finds them once). */
static inline void clh_hair_lobes_at(const clh_hair_view* hv, float sin_i, float cos_i,
                                     float cos_phi, clh_v3* r, clh_v3* tt, clh_v3* trt) {
  float phi = clh_fast_acos(cos_phi); /* the h-averaged lobes are even in phi */
  const clh_v3 m =
      clh_hair_mp3(sin_i, cos_i, hv->lobe_sin_o, hv->lobe_cos_o, hv->lobe_v, hv->lobe_norm);
  *r = clh_v3_splat(m.x * clh_hair_n_r(hv, phi));
  *tt = clh_v3_scale(clh_hair_n_tt(hv, phi), m.y);
  *trt = clh_v3_scale(clh_hair_n_trt(hv, phi), m.z);
}

/* The same for direction wi. Returns cos(theta_i). */
static inline float clh_hair_lobes_cos(const clh_hair_view* hv, clh_v3 wi, clh_v3* r, clh_v3* tt,
                                       clh_v3* trt) {
  float sin_i, cos_i, cos_phi;
  clh_hair_angles_to(hv, wi, &sin_i, &cos_i, &cos_phi);
  clh_hair_lobes_at(hv, sin_i, cos_i, cos_phi, r, tt, trt);
  return cos_i;
}

/* The three specular lobes separately as f (1/cos(theta_i) included; cos clamped at 1e-7). */
static inline void clh_hair_eval_lobes(const clh_hair_view* hv, clh_v3 wi, clh_v3* r, clh_v3* tt,
                                       clh_v3* trt) {
  float inv_cos = 1.0f / fmax(clh_hair_lobes_cos(hv, wi, r, tt, trt), 1e-7f);
  *r = clh_v3_scale(*r, inv_cos);
  *tt = clh_v3_scale(*tt, inv_cos);
  *trt = clh_v3_scale(*trt, inv_cos);
}

/* R + TT + TRT only (no diffuse), f without the cosine. */
static inline clh_v3 clh_hair_eval_specular(const clh_hair_view* hv, clh_v3 wi) {
  clh_v3 r, tt, trt;
  clh_hair_eval_lobes(hv, wi, &r, &tt, &trt);
  return clh_v3_add(clh_v3_add(r, tt), trt);
}

/* f cos(theta_i) for a light: the preferred call in a shading loop,
 *   L += clh_hair_eval_cos(&hv, wi) * E_light. */
static inline clh_v3 clh_hair_eval_cos_at(const clh_hair_view* hv, float sin_i, float cos_i,
                                          float cos_phi) {
  clh_v3 r, tt, trt;
  clh_hair_lobes_at(hv, sin_i, cos_i, cos_phi, &r, &tt, &trt);
  return clh_v3_add(clh_v3_add(clh_v3_add(r, tt), trt), clh_v3_scale(clh_hair_diffuse(hv), cos_i));
}

static inline clh_v3 clh_hair_eval_cos(const clh_hair_view* hv, clh_v3 wi) {
  float sin_i, cos_i, cos_phi;
  clh_hair_angles_to(hv, wi, &sin_i, &cos_i, &cos_phi);
  return clh_hair_eval_cos_at(hv, sin_i, cos_i, cos_phi);
}

/* Full f: R + TT + TRT + diffuse. */
static inline clh_v3 clh_hair_eval(const clh_hair_view* hv, clh_v3 wi) {
  return clh_v3_add(clh_hair_eval_specular(hv, wi), clh_hair_diffuse(hv));
}

/* One-call form for a single light. */
static inline clh_v3 clh_hair_bsdf(const clh_hair_material* m, clh_v3 t, clh_v3 wo, clh_v3 wi) {
  clh_hair_view hv;
  clh_hair_prepare_to(&hv, m, t, wo);
  return clh_hair_eval(&hv, wi);
}

#endif /* CLHAIR_HAIR_BSDF_H */
