/* strand_common.h — what the two strand kernels share around the rasteriser: the kernel
 * that generates strands from a hair mesh (strands.cl) and the one that reads stored
 * strands (strands_explicit.cl).
 *
 * - The draw-index lookup over the LOD scan (layout: gpu_types.h, "the LOD counts and
 *   their scan"): the drawn total, and the bundle (or chunk) and slot of a draw index.
 * - The end-tangent rule and the finishing of a lane's tangents once its points and its
 *   neighbours' points are known: central differences inside, Bhokare's reflection rule
 *   (Eq. 5-6) at the root and the tip, one sub-group exchange for the interior tangents
 *   next to the ends.
 *
 * Include after subgroup.h, clh_math.h and raster.h. Every lane must call
 * clh_finish_tangents (it exchanges with its neighbours).
 */
#ifndef CLHAIR_STRAND_COMMON_H
#define CLHAIR_STRAND_COMMON_H

/* ---- the draw-index lookup ------------------------------------------------------------ */

/* Largest i < count with offsets[i] <= index: the bundle (or chunk) whose range of the
 * exclusive prefix sum `offsets` holds draw index `index`. */
static inline uint clh_find_range(__global const uint* offsets_g, uint count, uint index) {
  uint lo = 0u, hi = count;
  while (hi - lo > 1u) {
    uint mid = (lo + hi) >> 1;
    if (offsets_g[mid] <= index) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return lo;
}

/* Strands drawn by all n bundles (or chunks) together. */
static inline uint clh_lod_drawn_total(__global const uint* offsets_g, uint n) {
  return n > 0u ? offsets_g[clh_lod_drawn_total_at(n)] : 0u;
}

/* The bundle (or chunk) that draws `index`, and the strand's slot in it; false when the
 * index is past the drawn total. */
static inline bool clh_lod_find_strand(__global const uint* offsets_g, uint n, uint index,
                                       uint* range, uint* slot) {
  if (n == 0u || index >= offsets_g[clh_lod_drawn_total_at(n)]) return false;
  *range = clh_find_range(offsets_g, n, index);
  *slot = index - offsets_g[*range];
  return true;
}

/* ---- tangents --------------------------------------------------------------------------- */

/* Reflects the neighbour tangent t about the end segment direction q (Bhokare Eq. 5-6). */
static inline float3 clh_end_tangent(float3 q, float3 t_neighbour) {
  return 2.0f * q * dot(t_neighbour, q) - t_neighbour;
}

/* How a kernel makes its tangents unit length. Generated strands use rsqrt
 * (clh_normalize_or); stored strands use the division of raster_core.h (clh_unit_or,
 * clh_end_tangent_unit), the arithmetic of the CPU floor (host/groom/cpu_raster.cpp) that
 * is held equal to them word for word. The two round differently, so each kernel keeps
 * its own; the rule is a constant at every call and folds away. */
#define CLH_TANGENT_RSQRT 0
#define CLH_TANGENT_DIVIDE 1

static inline float3 clh_tangent_unit(float3 v, float3 fallback, int rule) {
  return rule == CLH_TANGENT_DIVIDE ? clh_unit_or(v, fallback) : clh_normalize_or(v, fallback);
}

/* The end tangent from the end segment's unit direction q and the neighbour tangent. */
static inline float3 clh_tangent_end(float3 q, float3 t_neighbour, int rule) {
  return rule == CLH_TANGENT_DIVIDE ? clh_end_tangent_unit(q, t_neighbour)
                                    : clh_normalize_or(clh_end_tangent(q, t_neighbour), q);
}

/* Writes the tangent directions T[i].xyz (w untouched) of a lane's run of points
 * P[0..count), which are points k0 .. k0 + count - 1 of a strand of `total` points;
 * prev_p / next_p are the points just before and after the run (from the neighbouring
 * lanes). `cap` bounds count (the size of P and T). Every lane must call it. */
static inline void clh_finish_tangents(sg_ctx* sg, const float4* P, float4* T, uint cap, uint k0,
                                       uint count, uint total, float4 prev_p, float4 next_p,
                                       int rule) {
  /* interior tangents: central differences */
  for (uint i = 0; i < cap; ++i) {
    uint k = k0 + i;
    if (i < count && k > 0u && k + 1u < total) {
      float3 a = (i > 0u ? P[i - 1u] : prev_p).xyz;
      float3 c = (i + 1u < count ? P[i + 1u] : next_p).xyz;
      T[i].xyz = clh_tangent_unit(c - a, CLH_UP, rule);
    }
  }
  /* exchange 2: interior tangents next to the end points */
  const uint last = count > 0u ? count - 1u : 0u;
  const float4 prev_t = sg_shuffle_up1_f4(sg, T[last], (float4)(0.0f));
  const float4 next_t0 = sg_shuffle_down1_f4(sg, T[0], (float4)(0.0f));
  if (count > 0u && k0 == 0u) { /* root, Bhokare Eq. 6 */
    float3 p1 = (count > 1u ? P[1] : next_p).xyz;
    float3 q = clh_tangent_unit(p1 - P[0].xyz, CLH_UP, rule);
    float3 t1 = (total == 2u) ? q : (count > 1u ? T[1] : next_t0).xyz;
    T[0].xyz = clh_tangent_end(q, t1, rule);
  }
  if (count > 0u && total - 1u >= k0 && total - 1u < k0 + count) { /* tip, Bhokare Eq. 5 */
    uint i = total - 1u - k0;
    float3 pm = (i > 0u ? P[i - 1u] : prev_p).xyz;
    float3 q = clh_tangent_unit(P[i].xyz - pm, CLH_UP, rule);
    float3 tm = (total == 2u) ? q : (i > 0u ? T[i - 1u] : prev_t).xyz;
    T[i].xyz = clh_tangent_end(q, tm, rule);
  }
}

#endif /* CLHAIR_STRAND_COMMON_H */
