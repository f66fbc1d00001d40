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
 * Four texels are looked up together (clh_dom_texels4: a 2x2 block, or a row of the 4x4),
 * one per lane of a float4, each lane with the operations of a lookup of its own.
 */
#ifndef CLHAIR_SHADOW_H
#define CLHAIR_SHADOW_H

#include "clh_math.h"
#include "clhair/fast_math.h"

/* Four texels' transmittances (one per lane: texel (tx.sK, ty.sK)) for a point at
 * light-view depth z; the opaque test compares z_opaque (clh_shadow_transmittance_opaque:
 * the receiver's plane at each texel), the hair layers z. With `total` non-null also each
 * texel's transmittance through all of its layers (all the hair the map holds there, past
 * the point too); without it a texel whose first hair is not in front of the point is 1.
 * Every lane takes the operations a one-texel lookup would, in the same order: the layers'
 * coverage is summed up to d's layer and its linear share, and nothing after. */
static inline float4 clh_dom_texels4(__global const ClhShadowGpu* sh,
                                     __global const float* opaque_g, __global const float* hair_g,
                                     __global const uint* opacity_g, int4 tx, int4 ty,
                                     float4 z_opaque, float z, float shift, float4* total) {
  const int w = (int)sh->width, h = (int)sh->height;
  const size_t plane = (size_t)w * (size_t)h;
  const int xs[4] = {tx.s0, tx.s1, tx.s2, tx.s3}, ys[4] = {ty.s0, ty.s1, ty.s2, ty.s3};
  float zo[4], z0[4], v[CLH_DOM_LAYERS][4];
  for (int i = 0; i < 4; ++i) {
    /* clamped lane by lane: under Oclgrind (tests/test_oclgrind.cpp) clamp() of an int4 with
     * scalar bounds let reads past the map through, on PoCL it did not */
    const size_t at = (size_t)clamp(ys[i], 0, h - 1) * (size_t)w + (size_t)clamp(xs[i], 0, w - 1);
    zo[i] = opaque_g[(size_t)sh->offset + at];
    z0[i] = hair_g[(size_t)sh->offset + at];
    const size_t layers = (size_t)sh->offset * CLH_DOM_LAYERS + at;
    for (int k = 0; k < CLH_DOM_LAYERS; ++k)
      v[k][i] = (float)opacity_g[layers + (size_t)k * plane] * (1.0f / CLH_DOM_FIXED);
  }
  const float4 opaque = (float4)(zo[0], zo[1], zo[2], zo[3]);
  const float4 first = (float4)(z0[0], z0[1], z0[2], z0[3]);
  const int4 blocked = z_opaque > opaque + sh->bias * opaque / sh->fx;
  const int4 no_hair = !(first < INFINITY);
  const float4 d = z - first - shift * sh->bound[0];
  /* coverage up to d: whole layers before d's layer, the linear share of that layer */
  float4 acc = (float4)(0.0f), all = (float4)(0.0f);
  float lo = 0.0f;
  int4 inside = d > 0.0f;
  for (int k = 0; k < CLH_DOM_LAYERS; ++k) {
    const float4 vk = (float4)(v[k][0], v[k][1], v[k][2], v[k][3]);
    const float hi = sh->bound[k];
    all += vk;
    const int4 ends = d < hi;
    acc = select(acc, acc + vk * (d - lo) / fmax(hi - lo, 1e-12f), inside & ends);
    acc = select(acc, acc + vk, inside & ~ends);
    inside &= ~ends;
    lo = hi;
  }
  const float4 zero = (float4)(0.0f), one = (float4)(1.0f);
  const float4 t = clh_lanes_exp4(-sh->density * acc);
  if (total)
    *total = select(select(clh_lanes_exp4(-sh->density * all), one, no_hair), zero, blocked);
  const float4 lit = total ? t : select(one, t, d > 0.0f);
  return select(select(lit, one, no_hair), zero, blocked);
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
  const float4 tr = clh_dom_texels4(sh, opaque_g, hair_g, opacity_g, (int4)(x0, x0 + 1, x0, x0 + 1),
                                    (int4)(y0, y0, y0 + 1, y0 + 1), (float4)(pv.z), pv.z, shift, 0);
  const float t00 = tr.s0, t10 = tr.s1, t01 = tr.s2, t11 = tr.s3;
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
  float4 alls;
  const float4 tr =
      clh_dom_texels4(sh, opaque_g, hair_g, opacity_g, (int4)(x0, x0 + 1, x0, x0 + 1),
                      (int4)(y0, y0, y0 + 1, y0 + 1), (float4)(pv.z), pv.z, shift, &alls);
  const float t00 = tr.s0, t10 = tr.s1, t01 = tr.s2, t11 = tr.s3;
  const float a00 = alls.s0, a10 = alls.s1, a01 = alls.s2, a11 = alls.s3;
  const float top = t00 + (t10 - t00) * ax, bottom = t01 + (t11 - t01) * ax;
  const float t = top + (bottom - top) * ay;
  const float atop = a00 + (a10 - a00) * ax, abottom = a01 + (a11 - a01) * ax;
  const float all = fmin(atop + (abottom - atop) * ay, t);
  const float d = t > 1e-35f ? fmin(-0.693147181f * clh_fast_log2(t), 80.0f) : 80.0f;
  *tau = d;
  /* nothing behind p (all == t, the common case) leaves tau_behind 0 without a logarithm */
  if (all == t) return;
  const float d_all = all > 1e-35f ? fmin(-0.693147181f * clh_fast_log2(all), 80.0f) : 80.0f;
  *tau_behind = fmax(d_all - d, 0.0f);
}

static inline float clh_shadow_transmittance(__global const ClhShadowGpu* sh,
                                             __global const float* opaque_g,
                                             __global const float* hair_g,
                                             __global const uint* opacity_g, float3 p,
                                             float shift) {
  return clh_shadow_transmittance_v3(sh, opaque_g, hair_g, opacity_g, clh_v3_from(p), shift);
}

/* Fraction of the light reaching a point p with unit normal n on an opaque surface. Each
 * texel's opaque depth is compared with the depth of p's tangent plane along that texel's
 * ray (receiver plane depth bias, Isidoro 2006), not with p's own depth: a texel a distance
 * delta from p samples the surface delta * tan(theta) deeper or shallower (theta between n
 * and the light's ray), which exceeds the constant bias once theta passes ~45 degrees over
 * the filter's reach of up to 2 texels, and a curved surface then shadows itself in bands
 * that follow the texel grid (rings on a sphere). A convex or flat receiver lies at or behind
 * its tangent plane, so it never shadows itself; the constant bias stays for depth rounding.
 * The plane's slope is capped where the light grazes the surface (|cos theta| < 0.02 along
 * the ray's z = 1 length), where Lambert leaves under 2 % of the light.
 * Filtering: with sh->pcf the lookup is averaged over 3 x 3 positions one texel apart around
 * p (percentage-closer filtering): each texel of the 4 x 4 block around p weighs w_x w_y,
 * w = (1 - a, 1, 1, a) / 3 along an axis with a the point's fraction within its texel, so the
 * weights sum to one, a shadow edge ramps over three texels instead of one (smooth where a
 * texel covers several pixels), and blocks that are all lit or all shadowed keep their
 * value; without it, the bilinear blend of the four nearest texels, w = (0, 1 - a, a, 0).
 * The weights are continuous in p, so the result is too. Hair transmittance is looked up at
 * p's own depth, as for the hair. */
static inline float clh_shadow_transmittance_opaque(__global const ClhShadowGpu* sh,
                                                    __global const float* opaque_g,
                                                    __global const float* hair_g,
                                                    __global const uint* opacity_g, float3 p,
                                                    float3 n) {
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
  /* the tangent plane n.(q - pv) = 0 met by the texel rays q = z' (x/z, y/z, 1): dz'/du and
   * dz'/dv at p, with n.(pv / pv.z) (negative when n faces the light) capped away from 0 */
  const float3 nv = clh_xform_dir(w2v, n);
  const float facing = fmin(dot(nv, pv) / pv.z, -0.02f);
  const float dzdu = -pv.z * nv.x / (sh->fx * facing), dzdv = pv.z * nv.y / (sh->fy * facing);
  float wx[4], wy[4];
  if (sh->pcf != 0u) {
    wx[0] = (1.0f - ax) / 3.0f, wx[1] = wx[2] = 1.0f / 3.0f, wx[3] = ax / 3.0f;
    wy[0] = (1.0f - ay) / 3.0f, wy[1] = wy[2] = 1.0f / 3.0f, wy[3] = ay / 3.0f;
  } else {
    wx[0] = wx[3] = wy[0] = wy[3] = 0.0f;
    wx[1] = 1.0f - ax, wx[2] = ax, wy[1] = 1.0f - ay, wy[2] = ay;
  }
  float sum = 0.0f;
  for (int j = 0; j < 4; ++j) {
    if (wy[j] == 0.0f) continue;
    /* texel (x0 + i, y0 + j)'s centre sits i - 1 - ax, j - 1 - ay texels from p */
    float zr[4];
    for (int i = 0; i < 4; ++i)
      zr[i] = pv.z + dzdu * ((float)i - 1.0f - ax) + dzdv * ((float)j - 1.0f - ay);
    const float4 t4 =
        clh_dom_texels4(sh, opaque_g, hair_g, opacity_g, (int4)(x0, x0 + 1, x0 + 2, x0 + 3),
                        (int4)(y0 + j), (float4)(zr[0], zr[1], zr[2], zr[3]), pv.z, 0.0f, 0);
    const float t[4] = {t4.s0, t4.s1, t4.s2, t4.s3};
    float row = 0.0f;
    for (int i = 0; i < 4; ++i)
      if (wx[i] != 0.0f) row += wx[i] * t[i];
    sum += wy[j] * row;
  }
  return sum;
}

/* The light's shadow slot, or -1 (stored in the light colour's w). */
static inline int clh_light_shadow_slot(__global const ClhLightGpu* light) {
  return (int)floor(light->color[3] + 0.5f);
}

#endif /* CLHAIR_SHADOW_H */
