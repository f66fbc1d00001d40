/* filter.cl — the reconstruction filter (Lipp et al. 2026 §3.3): strand reconnection,
 * orientation-aware bilateral and alpha, one work-item per pixel, in one pass.
 *
 * Inputs: the G-buffer (layer 0: center hits, layer 1: conservative hits; MSAA 1 only),
 * the shaded colour of every center hit (hair_g: rgb, alpha 1 where shaded), the filter
 * parameters (ClhFilterGpu). Output: premultiplied RGBA of the groom (out_g).
 *
 * For pixel P the reference strand is its center hit, or, for a conservative-only pixel,
 * the conservative strand; when the conservative layer holds a strand nearer than the
 * center hit by more than depth_mismatch, that nearer strand is the reference and its
 * reconstruction is blended over the center colour (output alpha 1). Over the
 * (2r+1)^2 window, with d = Q - P split along the reference's screen tangent T_P into
 * d_par = d.T_P and d_perp = |d - d_par T_P| (Eq. 9):
 *  - colour: the center-hit colours C_Q weighted by exp(-d_par^2/s_par^2 - d_perp^2/s_perp^2)
 *    times exp(-|C_P - C_Q|^2/sigma_c^2) (Eq. 10; the colour term is 1 for promoted pixels,
 *    which have no colour of their own), normalised by the sum of weights;
 *  - alpha: within the strip d_perp <= strip, pixels with a center hit H_c and
 *    conservative-only pixels H_k give alpha = H_c / (H_c + H_k) (§3.3.3). A hit counts
 *    when it lies at the reference depth or behind it (hair behind covers the pixel as
 *    well), so alpha is about 1 inside dense hair and about the strand's sub-pixel
 *    coverage along an isolated strand; for a strand blended over a center hit only hits
 *    at its own depth count, which gives its own coverage.
 * With promote = 0 conservative-only pixels stay empty (the conservative layer still guides
 * alpha and the overlay of nearer strands).
 * Neighbours whose spatial weight is below exp(-24) are skipped (the window is mostly
 * such pixels when sigma_perp is small): negligible next to any nearer neighbour; a
 * promoted pixel with only such neighbours stays empty.
 * Neighbours whose depth differs from the reference by more than depth_reject (relative)
 * give it no colour, so colour never crosses a depth edge. Colour distances use c / (1 + c) so
 * HDR radiance compares like display values.
 */
#include "clhair/gpu_types.h"
#include "clh_math.h"
#include "clhair/fast_math.h"

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable

#define FILTER_MAX_RADIUS 8

static inline float filter_depth(ulong word, float near_z, float far_z) {
  return clh_depth_decode(clh_gbuf_depth(word), near_z, far_z);
}

/* Unit screen-space direction of the world tangent t at view-space point pv. */
static inline float2 filter_screen_tangent(clh_mat34 w2v, float fx, float fy, float3 pv, float3 t) {
  float3 tv = clh_xform_dir(w2v, t);
  float iz = 1.0f / pv.z;
  float2 d = (float2)(fx * (tv.x - pv.x * tv.z * iz) * iz, -fy * (tv.y - pv.y * tv.z * iz) * iz);
  float l2 = dot(d, d);
  return l2 > 1e-20f ? d * rsqrt(l2) : (float2)(1.0f, 0.0f);
}

static inline float3 filter_display(float3 c) { return c / (1.0f + c); }

__kernel void filter_reconstruct(__global const ClhGroomGpu* groom_g,
                                 __global const ClhViewGpu* view_g,
                                 __global const ClhFilterGpu* filter_g,
                                 __global const ulong* gbuf_g, __global const float4* hair_g,
                                 __global float4* out_g) {
  const int x = (int)get_global_id(0), y = (int)get_global_id(1);
  const int width = (int)view_g->width, height = (int)view_g->height;
  if (x >= width || y >= height) return;
  const size_t plane = (size_t)width * (size_t)height;
  const size_t idx = (size_t)y * (size_t)width + (size_t)x;
  const ulong gp = gbuf_g[idx], ap = gbuf_g[plane + idx];
  const bool is_center = gp != CLH_GBUF_EMPTY, is_cons = ap != CLH_GBUF_EMPTY;
  if (!is_center && (!is_cons || filter_g->promote == 0u)) {
    out_g[idx] = (float4)(0.0f);
    return;
  }
  const float near_z = groom_g->depth_near, far_z = groom_g->depth_far;
  const float z_center = is_center ? filter_depth(gp, near_z, far_z) : 0.0f;
  const float z_cons = is_cons ? filter_depth(ap, near_z, far_z) : 0.0f;
  /* a strand in front of the center hit: reconstruct it and blend it over */
  const bool overlay =
      is_center && is_cons && z_cons < z_center * (1.0f - filter_g->depth_mismatch);
  const ulong ref = (is_center && !overlay) ? gp : ap;
  const float z_ref = (is_center && !overlay) ? z_center : z_cons;
  const bool own_colour = is_center && !overlay;
  const float3 c_p = own_colour ? hair_g[idx].xyz : (float3)(0.0f);
  const float3 c_p_disp = filter_display(c_p);

  float tv[3];
  clh_oct_decode(clh_gbuf_oct(ref), tv);
  const float3 pv = (float3)(((float)x + 0.5f - view_g->cx) / view_g->fx * z_ref,
                             -((float)y + 0.5f - view_g->cy) / view_g->fy * z_ref, z_ref);
  const float2 tp = filter_screen_tangent(clh_load_mat34(view_g->world_to_view), view_g->fx,
                                          view_g->fy, pv, (float3)(tv[0], tv[1], tv[2]));

  const int r = (int)min(filter_g->radius, (uint)FILTER_MAX_RADIUS);
  const float s_par = fmax((float)r * filter_g->s_par, 1e-3f);
  const float s_perp = fmax((float)r * filter_g->s_perp, 1e-3f);
  const float inv_par2 = 1.0f / (s_par * s_par), inv_perp2 = 1.0f / (s_perp * s_perp);
  const float inv_c2 = 1.0f / (filter_g->sigma_c * filter_g->sigma_c);
  const float reject = filter_g->depth_reject * z_ref;

  float3 sum = (float3)(0.0f);
  float wsum = 0.0f, h_center = 0.0f, h_cons = 0.0f;
  float3 any_sum = (float3)(0.0f);
  float any_wsum = 0.0f;
  for (int dy = -r; dy <= r; ++dy) {
    const int qy = y + dy;
    if (qy < 0 || qy >= height) continue;
    for (int dx = -r; dx <= r; ++dx) {
      const int qx = x + dx;
      if (qx < 0 || qx >= width) continue;
      const size_t q = (size_t)qy * (size_t)width + (size_t)qx;
      const ulong gq = gbuf_g[q];
      const bool q_hit = gq != CLH_GBUF_EMPTY;
      const float zq = q_hit ? filter_depth(gq, near_z, far_z) : 0.0f;
      const float2 d = (float2)((float)dx, (float)dy);
      const float d_par = dot(d, tp);
      const float2 perp = d - d_par * tp;
      const float d_perp2 = dot(perp, perp);
      if (d_perp2 <= filter_g->strip * filter_g->strip) {
        if (q_hit && (overlay ? fabs(zq - z_ref) <= reject : zq >= z_ref - reject)) {
          h_center += 1.0f;
        } else {
          const ulong aq = gbuf_g[plane + q];
          const float za = aq != CLH_GBUF_EMPTY ? filter_depth(aq, near_z, far_z) : 0.0f;
          if (aq != CLH_GBUF_EMPTY && (overlay ? fabs(za - z_ref) <= reject : za >= z_ref - reject))
            h_cons += 1.0f;
        }
      }
      const float e_spatial = d_par * d_par * inv_par2 + d_perp2 * inv_perp2;
      /* exp(-24) < 4e-11: negligible beside any nearer neighbour */
      if (!q_hit || e_spatial > 24.0f) continue;
      const float3 c_q = hair_g[q].xyz;
      float w = clh_fast_exp(-e_spatial); /* fast_math.h: no library call in the window loop */
      if (!(fabs(zq - z_ref) <= reject)) {
        any_sum += w * c_q;
        any_wsum += w;
        continue;
      }
      if (own_colour) {
        const float3 dc = c_p_disp - filter_display(c_q);
        w *= clh_fast_exp(-dot(dc, dc) * inv_c2);
      }
      sum += w * c_q;
      wsum += w;
    }
  }
  /* a promoted pixel whose strand has no shaded neighbour at its depth borrows from the
   * strands around it at any depth rather than turning into a hole */
  if (!(wsum > 0.0f) && !own_colour) {
    sum = any_sum;
    wsum = any_wsum;
  }
  const float3 colour = wsum > 0.0f ? sum / wsum : c_p;
  const float counted = h_center + h_cons;
  float alpha = counted > 0.0f ? h_center / counted : (own_colour ? 1.0f : 0.0f);
  if (wsum <= 0.0f) alpha = own_colour ? alpha : 0.0f;
  if (overlay) {
    /* the nearer strand's reconstruction over the center hit, which stays opaque */
    const float3 under = hair_g[idx].xyz;
    out_g[idx] = (float4)(alpha * colour + (1.0f - alpha) * under, 1.0f);
    return;
  }
  out_g[idx] = (float4)(colour * alpha, alpha);
}
