/* lod.cl — the per-bundle LOD pre-pass and the scan that sizes the strand dispatch.
 *
 * lod_bundles (one work-item per bundle, Lipp §3.2): projects the four corners of every
 * layer quad, accumulates one screen AABB (Eq. 3) widened by the groom's styling reach,
 * culls bundles entirely off screen, and computes L (Eq. 2), N_LOD (Eq. 1 with the
 * bundle's delta) and C (Eq. 4-5). With LOD off L = 1, N_LOD = N and C is the groom's
 * full-detail count; gamma is the vertex-LOD morph factor (lod_math.h). Output: one
 * ClhLodRecord per bundle (N_LOD, C, L, gamma) and the counts for the scan: N_LOD, and the
 * full count of bundles not culled (layout: gpu_types.h, "the LOD counts and their scan").
 *
 * lod_chunks (one work-item per chunk of an explicit groom, strands_explicit.cl): the same
 * record from the chunk's object-space AABB (its 8 corners projected, no styling reach),
 * with 3 as the least control-point count; chunks play the role of bundles, so
 * scan_bundles and the strand dispatch sizing are shared.
 *
 * scan_bundles (one work-group of SCAN_WG items): exclusive scan of the counts into
 * offsets[0..n), then the drawn total (the host reads it back to size the strand pass)
 * and the visible total, the full-detail strand count of the bundles not culled, so
 * shading knows the fraction beta of visible strands LOD kept.
 */
#include "clhair/gpu_types.h"
#include "clhair/lod_math.h"
#include "clh_math.h"

#ifndef SCAN_WG
#define SCAN_WG 256
#endif

/* The LOD record of a bundle or chunk of n_full strands from its screen AABB [lo, hi]:
 * culled (N_LOD = 0) when every corner is behind the camera or the box is off screen;
 * full detail when LOD is off or some corner cannot be projected; otherwise Eq. 1-5 and
 * the morph factor (lod_math.h), C_max being the groom's full detail. */
static inline ClhLodRecord clh_lod_record_for_box(__global const ClhGroomGpu* g, float2 lo,
                                                  float2 hi, bool all_behind, bool unprojectable,
                                                  float width, float height, uint n_full,
                                                  float delta, uint min_points) {
  const uint C_full = clamp(g->control_points, 3u, (uint)CLH_MAX_CONTROL_POINTS);
  bool off_screen = hi.x < 0.0f || hi.y < 0.0f || lo.x > width || lo.y > height;
  if (all_behind || (!unprojectable && off_screen))
    return clh_lod_record_make(0u, C_full, 1.0f, 0.0f);
  if (g->lod_enabled == 0u || unprojectable) return clh_lod_record_make(n_full, C_full, 1.0f, 0.0f);
  float2 ext = hi - lo;
  float L = clh_lod_value(ext.x, ext.y, height, g->lod_lambda); /* Eq. 2 */
  return clh_lod_record_at(L, n_full, delta, min_points, C_full, g->lod_morph_window);
}

__kernel void lod_bundles(__global const ClhGroomGpu* groom_g, __global const ClhViewGpu* view_g,
                          __global const ClhBundle* bundles_g,
                          __global const ClhMeshVertex* verts_g, float reach,
                          __global ClhLodRecord* lod_g, __global uint* counts_g) {
  uint b = (uint)get_global_id(0);
  __global const ClhGroomGpu* g = groom_g;
  if (b >= g->bundle_count) return;
  __global const ClhBundle* bundle = bundles_g + b;
  uint n_full = bundle->strand_count;
  uint layers = clamp(g->layer_count, 2u, (uint)CLH_MAX_LAYERS);
  uint nv = g->vertex_count;
  clh_mat34 to_view = clh_load_mat34(g->obj_to_view);
  float fx = view_g->fx, fy = view_g->fy, cx = view_g->cx, cy = view_g->cy;
  float width = (float)view_g->width, height = (float)view_g->height;

  /* Corners at or behind the camera plane cannot be projected: such a bundle is kept at
   * full detail, unless every corner lies behind the camera by more than the reach. */
  float2 lo = (float2)(INFINITY), hi = (float2)(-INFINITY);
  bool all_behind = true, unprojectable = false;
  for (uint l = 0; l < layers; ++l) {
    for (uint c = 0; c < 4u; ++c) {
      int vi = clamp(bundle->vtx[c], 0, (int)nv - 1);
      float3 p = clh_xform_point(to_view, vload3(0, verts_g[(size_t)l * nv + (uint)vi].pos));
      if (p.z >= -reach) all_behind = false;
      if (p.z <= 1e-4f) {
        unprojectable = true;
        continue;
      }
      float2 s = (float2)(cx + fx * p.x / p.z, cy - fy * p.y / p.z);
      float r = fx * reach / p.z; /* styling can move strands this far off the mesh */
      lo = fmin(lo, s - r);
      hi = fmax(hi, s + r);
    }
  }

  const ClhLodRecord rec = clh_lod_record_for_box(g, lo, hi, all_behind, unprojectable, width,
                                                  height, n_full, bundle->lod_delta, layers);
  lod_g[b] = rec;
  counts_g[b] = rec.strands;
  /* the full-detail count of every bundle not culled, for beta = drawn / visible */
  counts_g[clh_lod_full_count_at(g->bundle_count, b)] = rec.strands > 0u ? n_full : 0u;
}

/* bounds_g: 2 float4 per chunk (AABB min, max); chunks_g: uint4 (first strand, strand
 * count, LOD delta bits, 0). */
__kernel void lod_chunks(__global const ClhGroomGpu* groom_g, __global const ClhViewGpu* view_g,
                         __global const float4* bounds_g, __global const uint4* chunks_g,
                         __global ClhLodRecord* lod_g, __global uint* counts_g) {
  uint c = (uint)get_global_id(0);
  __global const ClhGroomGpu* g = groom_g;
  if (c >= g->bundle_count) return;
  const uint4 chunk = chunks_g[c];
  const uint n_full = chunk.y;
  const float3 blo = bounds_g[2u * c].xyz, bhi = bounds_g[2u * c + 1u].xyz;
  clh_mat34 to_view = clh_load_mat34(g->obj_to_view);
  float fx = view_g->fx, fy = view_g->fy, cx = view_g->cx, cy = view_g->cy;
  float width = (float)view_g->width, height = (float)view_g->height;

  /* as in lod_bundles: corners at or behind the camera plane keep the chunk at full detail
   * unless all of them are behind the camera */
  float2 lo = (float2)(INFINITY), hi = (float2)(-INFINITY);
  bool all_behind = true, unprojectable = false;
  for (uint k = 0; k < 8u; ++k) {
    float3 corner =
        (float3)((k & 1u) ? bhi.x : blo.x, (k & 2u) ? bhi.y : blo.y, (k & 4u) ? bhi.z : blo.z);
    float3 p = clh_xform_point(to_view, corner);
    if (p.z >= 0.0f) all_behind = false;
    if (p.z <= 1e-4f) {
      unprojectable = true;
      continue;
    }
    float2 s = (float2)(cx + fx * p.x / p.z, cy - fy * p.y / p.z);
    lo = fmin(lo, s);
    hi = fmax(hi, s);
  }

  const ClhLodRecord rec = clh_lod_record_for_box(g, lo, hi, all_behind, unprojectable, width,
                                                  height, n_full, as_float(chunk.z), 3u);
  lod_g[c] = rec;
  counts_g[c] = rec.strands;
  counts_g[clh_lod_full_count_at(g->bundle_count, c)] = rec.strands > 0u ? n_full : 0u;
}

__kernel __attribute__((reqd_work_group_size(SCAN_WG, 1, 1))) void scan_bundles(
    __global const uint* counts_g, __global uint* offsets_g, uint n) {
  __local uint sums_l[SCAN_WG];
  uint lid = (uint)get_local_id(0);
  uint carry = 0u;
  for (uint base = 0u; base < n; base += SCAN_WG) {
    uint i = base + lid;
    uint v = i < n ? counts_g[i] : 0u;
    sums_l[lid] = v;
    barrier(CLK_LOCAL_MEM_FENCE);
    /* Hillis-Steele inclusive scan */
    for (uint off = 1u; off < SCAN_WG; off <<= 1) {
      uint add = lid >= off ? sums_l[lid - off] : 0u;
      barrier(CLK_LOCAL_MEM_FENCE);
      sums_l[lid] += add;
      barrier(CLK_LOCAL_MEM_FENCE);
    }
    if (i < n) offsets_g[i] = carry + sums_l[lid] - v;
    carry += sums_l[SCAN_WG - 1];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (lid == 0u) offsets_g[clh_lod_drawn_total_at(n)] = carry;
  /* the visible total: the sum of the full counts, counts[n .. 2n) */
  uint partial = 0u;
  for (uint i = lid; i < n; i += SCAN_WG) partial += counts_g[clh_lod_full_count_at(n, i)];
  barrier(CLK_LOCAL_MEM_FENCE);
  sums_l[lid] = partial;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint off = SCAN_WG / 2u; off > 0u; off >>= 1) {
    if (lid < off) sums_l[lid] += sums_l[lid + off];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (lid == 0u) offsets_g[clh_lod_visible_total_at(n)] = sums_l[0];
}
