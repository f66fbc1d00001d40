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
 * Cost (DESIGN.md, "Vectorizable kernels"): on a CPU the window loop waits on each weight's
 * chain of dependent operations (branches on the neighbours' hits and depths leave little
 * to overlap), so the chain is kept short: depths compared as 24-bit codes, the spatial
 * exponent as a quadratic along the row, the spatial and colour weights as one exponential
 * whose polynomial is evaluated in Estrin's order, one division for the display colour.
 */
#include "clhair/gpu_types.h"
#include "clh_math.h"
#include "faint_alpha.h"
#include "clhair/fast_math.h"

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable

#define FILTER_MAX_RADIUS 8

/* clh_depth_decode with its division by the code range as a product (per tap, one
 * rounding apart): near_z + scale * code, scale = (far_z - near_z) / CLH_DEPTH_MAX_CODE. */
static inline float filter_depth(ulong word, float near_z, float scale) {
  return near_z + scale * (float)clh_gbuf_depth(word);
}

/* The display value c / (1 + c) of each channel with one division for the three. */
static inline float3 filter_display(float3 c) {
  const float3 d = 1.0f + c;
  const float inv = 1.0f / (d.x * d.y * d.z);
  return (float3)(c.x * (d.y * d.z), c.y * (d.x * d.z), c.z * (d.x * d.y)) * inv;
}

/* Unit screen-space direction of the world tangent t at view-space point pv. */
static inline float2 filter_screen_tangent(clh_mat34 w2v, float fx, float fy, float3 pv, float3 t) {
  float3 tv = clh_xform_dir(w2v, t);
  float iz = 1.0f / pv.z;
  float2 d = (float2)(fx * (tv.x - pv.x * tv.z * iz) * iz, -fy * (tv.y - pv.y * tv.z * iz) * iz);
  float l2 = dot(d, d);
  return l2 > 1e-20f ? d * rsqrt(l2) : (float2)(1.0f, 0.0f);
}

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
  const float near_z = groom_g->depth_near;
  const float z_scale = (groom_g->depth_far - near_z) * (1.0f / (float)CLH_DEPTH_MAX_CODE);
  const float z_center = is_center ? filter_depth(gp, near_z, z_scale) : 0.0f;
  const float z_cons = is_cons ? filter_depth(ap, near_z, z_scale) : 0.0f;
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
  const float strip2 = filter_g->strip * filter_g->strip;
  /* The depth tests on the neighbours' 24-bit codes (no decode per tap): a depth
   * near_z + z_scale * code lies within reject of z_ref when the code lies in
   * [code_lo, code_lo + code_span], and at or behind z_ref - reject when it is
   * >= code_behind. */
  const bool coded = z_scale > 0.0f; /* else every code decodes to near_z = z_ref */
  const float c_ref = coded ? (z_ref - near_z) / z_scale : 0.0f;
  const float c_rej = coded ? reject / z_scale : 0.0f;
  const float code_top = (float)CLH_DEPTH_MAX_CODE + 1.0f;
  const float lo_f = coded ? clamp(ceil(c_ref - c_rej), 0.0f, code_top) : 0.0f;
  const float hi_f = coded ? clamp(floor(c_ref + c_rej), -1.0f, code_top) : code_top;
  const uint code_behind = (uint)lo_f; /* the codes at or behind z_ref - reject */
  /* an empty range (no code within reject) starts above every code */
  const uint code_lo = (uint)(hi_f >= lo_f ? lo_f : code_top);
  const uint code_span = hi_f >= lo_f ? (uint)(hi_f - lo_f) : 0u;
  /* With the unit tangent (tx, ty) a tap (dx, dy) has d_par = dx tx + dy ty and the signed
   * d_perp = dy tx - dx ty, so along a window row the spatial exponent
   * d_par^2 / s_par^2 + d_perp^2 / s_perp^2 is the quadratic (k2 dx + k1) dx + k0. */
  const float k2 = tp.x * tp.x * inv_par2 + tp.y * tp.y * inv_perp2;
  const float k1_dy = 2.0f * tp.x * tp.y * (inv_par2 - inv_perp2);
  const float k0_dy2 = tp.y * tp.y * inv_par2 + tp.x * tp.x * inv_perp2;

  float3 sum = (float3)(0.0f);
  float wsum = 0.0f, h_center = 0.0f, h_cons = 0.0f;
  float3 any_sum = (float3)(0.0f);
  float any_wsum = 0.0f;
  /* the window clipped to the image: no bounds test per tap */
  const int dx0 = max(-r, -x), dx1 = min(r, width - 1 - x);
  const int dy0 = max(-r, -y), dy1 = min(r, height - 1 - y);
  for (int dy = dy0; dy <= dy1; ++dy) {
    const float fy = (float)dy;
    const float k1 = k1_dy * fy, k0 = k0_dy2 * fy * fy, perp_row = fy * tp.x;
    const size_t row = (size_t)(y + dy) * (size_t)width + (size_t)x;
    for (int dx = dx0; dx <= dx1; ++dx) {
      const size_t q = row + (size_t)dx;
      const float fx = (float)dx;
      const ulong gq = gbuf_g[q];
      const bool q_hit = gq != CLH_GBUF_EMPTY;
      const uint cq = clh_gbuf_depth(gq);
      const float d_perp = perp_row - fx * tp.y;
      if (d_perp * d_perp <= strip2) {
        if (q_hit && (overlay ? cq - code_lo <= code_span : cq >= code_behind)) {
          h_center += 1.0f;
        } else {
          const ulong aq = gbuf_g[plane + q];
          const uint ca = clh_gbuf_depth(aq);
          if (aq != CLH_GBUF_EMPTY && (overlay ? ca - code_lo <= code_span : ca >= code_behind))
            h_cons += 1.0f;
        }
      }
      const float e_spatial = (k2 * fx + k1) * fx + k0;
      /* exp(-24) < 4e-11: negligible beside any nearer neighbour */
      if (!q_hit || e_spatial > 24.0f) continue;
      /* unsigned: codes below code_lo wrap past the span */
      const bool at_depth = cq - code_lo <= code_span;
      /* a pixel with its own colour never uses the neighbours at other depths */
      if (own_colour && !at_depth) continue;
      const float3 c_q = hair_g[q].xyz;
      /* the spatial and the colour weight as one exponential of the summed exponents
       * (fast_math.h: no library call in the window loop, a short chain) */
      float e = e_spatial;
      if (own_colour) {
        const float3 dc = c_p_disp - filter_display(c_q);
        e += dot(dc, dc) * inv_c2;
      }
      const float w = clh_fast_exp_neg(-e);
      if (!at_depth) {
        any_sum += w * c_q;
        any_wsum += w;
        continue;
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
  /* a faint groom's hits were widened past its fibres: they cover this share of a pixel */
  alpha *= clh_faint_alpha(groom_g, z_ref);
  if (overlay) {
    /* the nearer strand's reconstruction over the center hit, which stays opaque (a faint
     * groom's covers its share) */
    const float3 under = hair_g[idx].xyz;
    const float a_under = clh_faint_alpha(groom_g, z_center);
    out_g[idx] = (float4)(alpha * colour + (1.0f - alpha) * a_under * under,
                          a_under < 1.0f ? alpha + (1.0f - alpha) * a_under : 1.0f);
    return;
  }
  out_g[idx] = (float4)(colour * alpha, alpha);
}
