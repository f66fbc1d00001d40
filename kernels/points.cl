/* points.cl — the passes of per-point shading around the shading itself (DESIGN.md,
 * "Shading once per visible strand point").
 *
 * The strand pass built with CLH_POINT_ID leaves, next to every sample word, the sample's
 * identity: the first point of the segment that drew it and the sample's place between
 * that point and the next (gpu_types.h, layers CLH_MSAA + 1 .. 2 CLH_MSAA). Then:
 *   points_mark     one work-item per pixel of the groom's box: both points of every
 *                   sample's segment get their bit in the groom's point bitmap;
 *   points_count    one work-item per block of CLH_POINT_BLOCK bitmap words: its marked
 *                   points;
 *   points_scan     one work-group: the exclusive scan of the block counts, the total last;
 *   points_offsets  one work-item per block: the marked points before each of its words
 *                   (the total after the last), so a marked point's slot is the rank of its
 *                   bit: offsets[w] + popcount(the word's bits below it);
 * the strand kernels' point pass (CLH_RASTER_POINTS) writes each marked point's shading
 * inputs at its slot, shade_points (shade.cl) shades each once, and
 *   points_resolve  one work-item per pixel of the box: each sample takes its segment's
 *                   two point colours interpolated at its place, the pixel their mean over
 *                   CLH_MSAA and alpha the share of samples hit (premultiplied RGBA, as
 *                   shade_deferred writes it).
 * Every pass is deterministic: bits are set with atomic_or (order-free), ranks come from
 * the bitmap, colours from fixed slots.
 */
#include "clhair/gpu_types.h"
#include "clh_math.h"

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable

#ifndef CLH_MSAA
#define CLH_MSAA 1
#endif
#ifndef CLH_POINT_SCAN_WG
#define CLH_POINT_SCAN_WG 256 /* work-items of points_scan's one work-group */
#endif

static inline void points_set(__global uint* bits_g, uint words, uint point) {
  const uint w = point >> 5, m = 1u << (point & 31u);
  if (w < words && (bits_g[w] & m) == 0u) atomic_or(bits_g + w, m);
}

__kernel void points_mark(__global const ulong* gbuf_g, uint width, uint height, int4 box,
                          __global uint* bits_g, uint words) {
  int x, y;
  if (!clh_box_pixel(box, (int)width, (int)height, &x, &y)) return;
  const size_t plane = (size_t)width * height, idx = (size_t)y * width + (size_t)x;
  for (uint s = 0; s < (uint)CLH_MSAA; ++s) {
    const ulong id = gbuf_g[(CLH_LAYER_POINT_ID(CLH_MSAA) + s) * plane + idx];
    if (id == CLH_GBUF_EMPTY) continue;
    const uint p = clh_pt_point(id);
    points_set(bits_g, words, p);
    points_set(bits_g, words, p + 1u);
  }
}

__kernel void points_count(__global const uint* bits_g, uint words, __global uint* blocks_g,
                           uint blocks) {
  const uint b = (uint)get_global_id(0);
  if (b >= blocks) return;
  uint n = 0u;
  for (uint i = 0; i < CLH_POINT_BLOCK; ++i) {
    const uint w = b * CLH_POINT_BLOCK + i;
    if (w < words) n += popcount(bits_g[w]);
  }
  blocks_g[b] = n;
}

/* blocks_g: `blocks` counts in, their exclusive scan out, the total at [blocks]. */
__kernel __attribute__((reqd_work_group_size(CLH_POINT_SCAN_WG, 1, 1))) void points_scan(
    __global uint* blocks_g, uint blocks) {
  __local uint sums_l[CLH_POINT_SCAN_WG];
  const uint lid = (uint)get_local_id(0);
  uint carry = 0u;
  for (uint base = 0u; base < blocks; base += CLH_POINT_SCAN_WG) {
    const uint i = base + lid;
    const uint v = i < blocks ? blocks_g[i] : 0u;
    sums_l[lid] = v;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint off = 1u; off < CLH_POINT_SCAN_WG; off <<= 1) { /* inclusive, Hillis-Steele */
      const uint t = lid >= off ? sums_l[lid - off] : 0u;
      barrier(CLK_LOCAL_MEM_FENCE);
      sums_l[lid] += t;
      barrier(CLK_LOCAL_MEM_FENCE);
    }
    if (i < blocks) blocks_g[i] = carry + sums_l[lid] - v;
    carry += sums_l[CLH_POINT_SCAN_WG - 1];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (lid == 0u) blocks_g[blocks] = carry;
}

__kernel void points_offsets(__global const uint* bits_g, uint words, __global const uint* blocks_g,
                             uint blocks, __global uint* offsets_g) {
  const uint b = (uint)get_global_id(0);
  if (b >= blocks) return;
  uint run = blocks_g[b];
  for (uint i = 0; i < CLH_POINT_BLOCK; ++i) {
    const uint w = b * CLH_POINT_BLOCK + i;
    if (w < words) {
      offsets_g[w] = run;
      run += popcount(bits_g[w]);
    }
  }
  if (b + 1u == blocks) offsets_g[words] = blocks_g[blocks];
}

/* The slot of a marked point, or `capacity` when it is not marked or has none. */
static inline uint points_slot(__global const uint* bits_g, __global const uint* offsets_g,
                               uint words, uint capacity, uint point) {
  const uint w = point >> 5;
  if (w >= words) return capacity;
  const uint bits = bits_g[w], bit = point & 31u;
  if (((bits >> bit) & 1u) == 0u) return capacity;
  return min(offsets_g[w] + popcount(bits & ((1u << bit) - 1u)), capacity);
}

__kernel void points_resolve(__global const ClhViewGpu* view_g, __global const ulong* gbuf_g,
                             __global const uint* bits_g, __global const uint* offsets_g,
                             uint words, __global const float4* colors_g, uint capacity,
                             __global float4* hair_g, int4 box) {
  const uint width = view_g->width, height = view_g->height;
  int x, y;
  if (!clh_box_pixel(box, (int)width, (int)height, &x, &y)) return;
  const size_t plane = (size_t)width * height, idx = (size_t)y * width + (size_t)x;
  float4 sum = (float4)(0.0f);
  for (uint s = 0; s < (uint)CLH_MSAA; ++s) {
    const ulong id = gbuf_g[(CLH_LAYER_POINT_ID(CLH_MSAA) + s) * plane + idx];
    if (id == CLH_GBUF_EMPTY) continue;
    const uint p = clh_pt_point(id);
    const uint a = points_slot(bits_g, offsets_g, words, capacity, p);
    const uint b = points_slot(bits_g, offsets_g, words, capacity, p + 1u);
    const float4 ca = a < capacity ? colors_g[a] : (float4)(0.0f, 0.0f, 0.0f, 1.0f);
    const float4 cb = b < capacity ? colors_g[b] : ca;
    const float f = clh_pt_fraction(id);
    sum += (float4)(ca.xyz + (cb.xyz - ca.xyz) * f, 1.0f);
  }
  hair_g[idx] = sum / (float)CLH_MSAA;
}
