/* group_scan.h — work-group reductions and the scan of LOD counts, shared by the LOD
 * pre-pass (lod.cl: scan_bundles) and the segment budget (budget.cl).
 *
 * Every function is called by every work-item of a work-group of SCAN_WG items (a power
 * of two) with uniform control flow; sums_l holds SCAN_WG words of local memory. The
 * reductions combine in a fixed tree, so their results (float sums included) do not
 * depend on the order in which work-items run: a frame stays bit-identical.
 */
#ifndef CLH_GROUP_SCAN_H
#define CLH_GROUP_SCAN_H

#include "clhair/gpu_types.h"

#ifndef SCAN_WG
#define SCAN_WG 256
#endif

/* Sum of v over the work-group (every item must call it; sums_l holds SCAN_WG words). */
static inline uint clh_group_sum(uint v, __local uint* sums_l) {
  const uint lid = (uint)get_local_id(0);
  barrier(CLK_LOCAL_MEM_FENCE);
  sums_l[lid] = v;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint off = SCAN_WG / 2u; off > 0u; off >>= 1) {
    if (lid < off) sums_l[lid] += sums_l[lid + off];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  const uint sum = sums_l[0];
  barrier(CLK_LOCAL_MEM_FENCE);
  return sum;
}

/* The scan of n bundles' counts into offsets with the three totals (gpu_types.h), by one
 * work-group of SCAN_WG items (uniform control flow). */
static void clh_scan_counts(__global const uint* counts_g, __global uint* offsets_g, uint n,
                            __local uint* sums_l) {
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
  /* the visible total, the sum of counts[n .. 2n), and the segment total, counts[2n .. 3n) */
  uint visible = 0u, segments = 0u;
  for (uint i = lid; i < n; i += SCAN_WG) {
    visible += counts_g[clh_lod_full_count_at(n, i)];
    segments += counts_g[clh_lod_segment_count_at(n, i)];
  }
  visible = clh_group_sum(visible, sums_l);
  segments = clh_group_sum(segments, sums_l);
  if (lid == 0u) {
    offsets_g[clh_lod_visible_total_at(n)] = visible;
    offsets_g[clh_lod_segment_total_at(n)] = segments;
  }
}

/* Sum over a work-group of 64-bit values held as two 32-bit halves per item. */
static inline ulong clh_group_sum64(ulong v, __local uint* sums_l) {
  const uint lo = clh_group_sum((uint)(v & 0xFFFFu), sums_l);
  const uint mid = clh_group_sum((uint)((v >> 16) & 0xFFFFu), sums_l);
  const uint hi = clh_group_sum((uint)(v >> 32), sums_l);
  return (ulong)lo + ((ulong)mid << 16) + ((ulong)hi << 32);
}

/* Largest (want_max) or smallest v over the work-group. */
static inline uint clh_group_extreme(uint v, bool want_max, __local uint* sums_l) {
  const uint lid = (uint)get_local_id(0);
  barrier(CLK_LOCAL_MEM_FENCE);
  sums_l[lid] = v;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint off = SCAN_WG / 2u; off > 0u; off >>= 1) {
    if (lid < off) {
      const uint a = sums_l[lid], b = sums_l[lid + off];
      sums_l[lid] = want_max ? max(a, b) : min(a, b);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  const uint r = sums_l[0];
  barrier(CLK_LOCAL_MEM_FENCE);
  return r;
}

/* Sum of float v over the work-group, in a fixed tree. */
static inline float clh_group_sum_f(float v, __local uint* sums_l) {
  const uint lid = (uint)get_local_id(0);
  barrier(CLK_LOCAL_MEM_FENCE);
  sums_l[lid] = as_uint(v);
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint off = SCAN_WG / 2u; off > 0u; off >>= 1) {
    if (lid < off) sums_l[lid] = as_uint(as_float(sums_l[lid]) + as_float(sums_l[lid + off]));
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  const float r = as_float(sums_l[0]);
  barrier(CLK_LOCAL_MEM_FENCE);
  return r;
}

#endif /* CLH_GROUP_SCAN_H */
