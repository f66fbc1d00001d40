/* shadow.h — deep-opacity-map lookups (Yuksel & Keyser 2008) for the shading kernels.
 *
 * A world point is projected into the light's view; at each of the four nearest texels
 * the transmittance is 0 behind the opaque scene (shadow map with a bias in texels),
 * else exp(-density * O(d)) with O the hair coverage accumulated from the first hair
 * depth z0 to the point's depth past it, d: whole opacity layers before d's layer plus
 * the linear share of that layer. d is reduced by `shift` layer-1 units: the LOD depth
 * correction of Lipp §3.2.3, Delta = -log(beta) when LOD drew a fraction beta of the
 * groom's strands, so strands exposed by stochastic removal are not darkened by the
 * hair that was removed in front of them. The four texels are blended bilinearly.
 * Opaque surfaces (clh_shadow_transmittance_opaque) filter wider when the map asks for it
 * (ClhShadowGpu.pcf): percentage-closer filtering over the 4x4 texels around the point.
 */
#ifndef CLHAIR_SHADOW_H
#define CLHAIR_SHADOW_H

#include "clh_math.h"
#include "clhair/fast_math.h"

/* Transmittance at depth z of texel (tx, ty); with `total` non-null also the transmittance
 * through every layer of the texel (all the hair the map holds there, past the point too). */
static inline float clh_dom_texel_total(__global const ClhShadowGpu* sh,
                                        __global const float* opaque_g,
                                        __global const float* hair_g,
                                        __global const uint* opacity_g, int tx, int ty, float z,
                                        float shift, float* total) {
  const int w = (int)sh->width, h = (int)sh->height;
  tx = clamp(tx, 0, w - 1);
  ty = clamp(ty, 0, h - 1);
  const size_t plane = (size_t)w * (size_t)h;
  const size_t t = (size_t)sh->offset + (size_t)ty * (size_t)w + (size_t)tx;
  const float zo = opaque_g[t];
  if (z > zo + sh->bias * zo / sh->fx) {
    if (total) *total = 0.0f;
    return 0.0f;
  }
  const float z0 = hair_g[t];
  if (!(z0 < INFINITY)) {
    if (total) *total = 1.0f;
    return 1.0f;
  }
  const float d = z - z0 - shift * sh->bound[0];
  const size_t layers = (size_t)sh->offset * CLH_DOM_LAYERS + (size_t)ty * (size_t)w + (size_t)tx;
  if (!total && !(d > 0.0f)) return 1.0f;
  float acc = 0.0f, all = 0.0f, lo = 0.0f;
  bool inside = d > 0.0f;
  for (int k = 0; k < CLH_DOM_LAYERS; ++k) {
    const float v = (float)opacity_g[layers + (size_t)k * plane] * (1.0f / CLH_DOM_FIXED);
    const float hi = sh->bound[k];
    all += v;
    if (inside) {
      if (d < hi) {
        acc += v * (d - lo) / fmax(hi - lo, 1e-12f);
        inside = false;
        if (!total) break;
      } else {
        acc += v;
      }
    }
    lo = hi;
  }
  if (total) *total = clh_fast_exp(-sh->density * all);
  return clh_fast_exp(-sh->density * acc);
}

static inline float clh_dom_texel(__global const ClhShadowGpu* sh, __global const float* opaque_g,
                                  __global const float* hair_g, __global const uint* opacity_g,
                                  int tx, int ty, float z, float shift) {
  return clh_dom_texel_total(sh, opaque_g, hair_g, opacity_g, tx, ty, z, shift, 0);
}

/* Fraction of the light reaching world point p (1 = unshadowed). Scalar arithmetic only
 * (clh_v3), for the shading kernel CPU compilers vectorize. */
static inline float clh_shadow_transmittance_v3(__global const ClhShadowGpu* sh,
                                                __global const float* opaque_g,
                                                __global const float* hair_g,
                                                __global const uint* opacity_g, clh_v3 p,
                                                float shift) {
  if (sh->width == 0u || sh->height == 0u) return 1.0f;
  const clh_v3 pv = clh_v3_xform_point(sh->world_to_view, p);
  if (!(pv.z > 1e-6f)) return 1.0f;
  const float u = sh->cx + sh->fx * pv.x / pv.z - 0.5f;
  const float v = sh->cy - sh->fy * pv.y / pv.z - 0.5f;
  if (u < -1.0f || v < -1.0f || u > (float)sh->width || v > (float)sh->height) return 1.0f;
  const float fu = floor(u), fv = floor(v);
  const int x0 = (int)fu, y0 = (int)fv;
  const float ax = u - fu, ay = v - fv;
  const float t00 = clh_dom_texel(sh, opaque_g, hair_g, opacity_g, x0, y0, pv.z, shift);
  const float t10 = clh_dom_texel(sh, opaque_g, hair_g, opacity_g, x0 + 1, y0, pv.z, shift);
  const float t01 = clh_dom_texel(sh, opaque_g, hair_g, opacity_g, x0, y0 + 1, pv.z, shift);
  const float t11 = clh_dom_texel(sh, opaque_g, hair_g, opacity_g, x0 + 1, y0 + 1, pv.z, shift);
  const float top = t00 + (t10 - t00) * ax, bottom = t01 + (t11 - t01) * ax;
  return top + (bottom - top) * ay;
}

/* The hair between the light and world point p, and behind p along the light, as optical
 * depths (expected fibres crossed; the map's transmittance is e^-depth), for the dual
 * scattering of hair_dual.h: the bilinear blend of the four nearest texels' transmittances
 * at p (the value clh_shadow_transmittance_v3 returns) and through the whole texel. Behind
 * the opaque scene both are "blocked" (depth 80, e^-80 = 0). */
static inline void clh_shadow_depths_v3(__global const ClhShadowGpu* sh,
                                        __global const float* opaque_g,
                                        __global const float* hair_g,
                                        __global const uint* opacity_g, clh_v3 p, float shift,
                                        float* tau, float* tau_behind) {
  *tau = 0.0f;
  *tau_behind = 0.0f;
  if (sh->width == 0u || sh->height == 0u) return;
  const clh_v3 pv = clh_v3_xform_point(sh->world_to_view, p);
  if (!(pv.z > 1e-6f)) return;
  const float u = sh->cx + sh->fx * pv.x / pv.z - 0.5f;
  const float v = sh->cy - sh->fy * pv.y / pv.z - 0.5f;
  if (u < -1.0f || v < -1.0f || u > (float)sh->width || v > (float)sh->height) return;
  const float fu = floor(u), fv = floor(v);
  const int x0 = (int)fu, y0 = (int)fv;
  const float ax = u - fu, ay = v - fv;
  float a00, a10, a01, a11;
  const float t00 = clh_dom_texel_total(sh, opaque_g, hair_g, opacity_g, x0, y0, pv.z, shift, &a00);
  const float t10 =
      clh_dom_texel_total(sh, opaque_g, hair_g, opacity_g, x0 + 1, y0, pv.z, shift, &a10);
  const float t01 =
      clh_dom_texel_total(sh, opaque_g, hair_g, opacity_g, x0, y0 + 1, pv.z, shift, &a01);
  const float t11 =
      clh_dom_texel_total(sh, opaque_g, hair_g, opacity_g, x0 + 1, y0 + 1, pv.z, shift, &a11);
  const float top = t00 + (t10 - t00) * ax, bottom = t01 + (t11 - t01) * ax;
  const float t = top + (bottom - top) * ay;
  const float atop = a00 + (a10 - a00) * ax, abottom = a01 + (a11 - a01) * ax;
  const float all = fmin(atop + (abottom - atop) * ay, t);
  const float d = t > 1e-35f ? fmin(-0.693147181f * clh_fast_log2(t), 80.0f) : 80.0f;
  const float d_all = all > 1e-35f ? fmin(-0.693147181f * clh_fast_log2(all), 80.0f) : 80.0f;
  *tau = d;
  *tau_behind = fmax(d_all - d, 0.0f);
}

static inline float clh_shadow_transmittance(__global const ClhShadowGpu* sh,
                                             __global const float* opaque_g,
                                             __global const float* hair_g,
                                             __global const uint* opacity_g, float3 p,
                                             float shift) {
  return clh_shadow_transmittance_v3(sh, opaque_g, hair_g, opacity_g, clh_v3_from(p), shift);
}

/* Fraction of the light reaching a point on an opaque surface. With sh->pcf the bilinear
 * lookup above is averaged over 3 x 3 positions one texel apart around p (percentage-
 * closer filtering): each texel of the 4 x 4 block around p weighs w_x w_y, w = (1 - a,
 * 1, 1, a) / 3 along an axis with a the point's fraction within its texel, so the weights
 * sum to one, a shadow edge ramps over three texels instead of one (smooth where a texel
 * covers several pixels), and blocks that are all lit or all shadowed keep their value.
 * The weights are continuous in p, so the result is too. */
static inline float clh_shadow_transmittance_opaque(__global const ClhShadowGpu* sh,
                                                    __global const float* opaque_g,
                                                    __global const float* hair_g,
                                                    __global const uint* opacity_g, float3 p) {
  if (sh->pcf == 0u) return clh_shadow_transmittance(sh, opaque_g, hair_g, opacity_g, p, 0.0f);
  if (sh->width == 0u || sh->height == 0u) return 1.0f;
  const clh_mat34 w2v = clh_load_mat34(sh->world_to_view);
  const float3 pv = clh_xform_point(w2v, p);
  if (!(pv.z > 1e-6f)) return 1.0f;
  const float u = sh->cx + sh->fx * pv.x / pv.z - 0.5f;
  const float v = sh->cy - sh->fy * pv.y / pv.z - 0.5f;
  if (u < -1.0f || v < -1.0f || u > (float)sh->width || v > (float)sh->height) return 1.0f;
  const float fu = floor(u), fv = floor(v);
  const int x0 = (int)fu - 1, y0 = (int)fv - 1;
  const float ax = u - fu, ay = v - fv;
  const float wx[4] = {(1.0f - ax) / 3.0f, 1.0f / 3.0f, 1.0f / 3.0f, ax / 3.0f};
  const float wy[4] = {(1.0f - ay) / 3.0f, 1.0f / 3.0f, 1.0f / 3.0f, ay / 3.0f};
  float sum = 0.0f;
  for (int j = 0; j < 4; ++j) {
    float row = 0.0f;
    for (int i = 0; i < 4; ++i)
      row += wx[i] * clh_dom_texel(sh, opaque_g, hair_g, opacity_g, x0 + i, y0 + j, pv.z, 0.0f);
    sum += wy[j] * row;
  }
  return sum;
}

/* The light's shadow slot, or -1 (stored in the light colour's w). */
static inline int clh_light_shadow_slot(__global const ClhLightGpu* light) {
  return (int)floor(light->color[3] + 0.5f);
}

#endif /* CLHAIR_SHADOW_H */
