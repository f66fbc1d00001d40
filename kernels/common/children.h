/* children.h — children of an explicit groom's guides, drawn by strands_explicit.cl and never
 * stored: the rules of host/groom/children.h (follow hairs as TressFX grows them around a
 * guide, interpolated children as Blender blends the nearest guides), evaluated point by
 * point from the guides' stored points.
 *
 * clh_child_setup runs once per drawn strand (every lane, same values): the child's root
 * offset in the basis across its guide's root direction and, for interpolated children, the
 * three guides nearest its root among the guide and its neighbour table, with their
 * weights. clh_child_point then gives stored point k of the child, which has as many points
 * as its guide. Every access is clamped to the tables.
 */
#ifndef CLH_CHILDREN_H
#define CLH_CHILDREN_H

#include "clhair/gpu_types.h"

typedef struct {
  uint kind;  /* 0: a guide itself, 1: follow, 2: interpolated */
  uint first; /* the guide's first stored point */
  uint n;     /* its stored points (the child's too) */
  float3 off; /* follow: the root offset; interpolated: root - B(0) */
  float spread, clump;
  uint blend_first[3], blend_n[3];
  float blend_w[3];
  uint blend_count;
} clh_child;

static inline float3 clh_child_load(__global const float4* points_g, uint point_count, uint i) {
  return points_g[min(i, point_count - 1u)].xyz;
}

/* Guide (first, m points) at parameter k / (n - 1), linear between its points. */
static inline float3 clh_child_guide_at(__global const float4* points_g, uint point_count,
                                        uint first, uint m, uint k, uint n) {
  const ulong num = (ulong)k * (ulong)(m - 1u);
  const uint i = (uint)(num / (ulong)(n - 1u));
  const float f = (float)(uint)(num % (ulong)(n - 1u)) / (float)(n - 1u);
  const float3 a = clh_child_load(points_g, point_count, first + min(i, m - 1u));
  if (f == 0.0f) return a;
  const float3 b = clh_child_load(points_g, point_count, first + min(i + 1u, m - 1u));
  return a + (b - a) * f;
}

/* The growth F_k of the root offset at stored point k. */
static inline float clh_child_growth(const clh_child* ch, uint k) {
  const float t = (float)k / (float)(ch->n - 1u);
  const float kappa = ch->clump >= 0.0f ? ch->clump * t : -ch->clump * (1.0f - t);
  return (1.0f + ch->spread * (float)k / (float)ch->n) * (1.0f - kappa);
}

/* Child `child` (0: the guide itself) of guide g, whose points are [first, first + n). */
static inline void clh_child_setup(__global const float4* points_g, uint point_count,
                                   __global const uint* strand_offsets_g, uint strand_count,
                                   __global const ClhChildrenGpu* kids_g,
                                   __global const uint* nbr_g, uint g, uint child, uint first,
                                   uint n, clh_child* ch) {
  ch->kind = 0u;
  ch->first = first;
  ch->n = n;
  ch->off = (float3)(0.0f);
  ch->spread = 0.0f;
  ch->clump = 0.0f;
  ch->blend_count = 0u;
  for (uint i = 0; i < 3u; ++i) {
    ch->blend_first[i] = first;
    ch->blend_n[i] = n;
    ch->blend_w[i] = 0.0f;
  }
  if (child == 0u || n < 2u) return;
  const ClhChildrenGpu kids = *kids_g;
  ch->spread = kids.tip_spread;
  ch->clump = kids.clump;

  /* the basis across the root direction, as the CPU rules build it */
  const float3 p0 = clh_child_load(points_g, point_count, first);
  float3 v = clh_child_load(points_g, point_count, first + 1u) - p0;
  const float len = sqrt(dot(v, v));
  v = len > 0.0f ? v / len : (float3)(0.0f, 1.0f, 0.0f);
  const float ax = fabs(v.x), ay = fabs(v.y), az = fabs(v.z);
  const float3 a = (ax <= ay && ax <= az) ? (float3)(1.0f, 0.0f, 0.0f)
                   : (ay <= az)           ? (float3)(0.0f, 1.0f, 0.0f)
                                          : (float3)(0.0f, 0.0f, 1.0f);
  float3 t0 = cross(v, a);
  t0 = t0 / sqrt(dot(t0, t0));
  const float3 t1 = cross(v, t0);
  const uint h = clh_hash3(kids.seed, g, child);
  const float oa = (2.0f * clh_u01(h) - 1.0f) * kids.radius;
  const float ob = (2.0f * clh_u01(clh_hash(h)) - 1.0f) * kids.radius;
  const float3 o = t0 * oa + t1 * ob;
  if (kids.mode != CLH_CHILD_INTERPOLATED) {
    ch->kind = 1u;
    ch->off = o;
    return;
  }

  /* interpolated: the four nearest roots among the guide and its neighbours */
  const float3 root = p0 + o;
  float dist[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  uint gi[4] = {g, g, g, g};
  uint have = 0u;
  const uint K = min(kids.neighbours, (uint)CLH_CHILD_NEIGHBOURS);
  for (uint c = 0; c <= K; ++c) {
    const uint o_g = c == 0u ? g : nbr_g[(ulong)g * K + (c - 1u)];
    if (o_g >= strand_count) continue; /* padding */
    const uint of = min(strand_offsets_g[o_g], point_count - 1u);
    const float3 dv = clh_child_load(points_g, point_count, of) - root;
    const float d2 = dot(dv, dv);
    uint at = have;
    while (at > 0u && d2 < dist[at - 1u]) --at;
    if (at >= 4u) continue;
    for (uint j = min(have, 3u); j > at; --j) {
      dist[j] = dist[j - 1u];
      gi[j] = gi[j - 1u];
    }
    dist[at] = d2;
    gi[at] = o_g;
    have = min(have + 1u, 4u);
  }
  ch->kind = 2u;
  float w[3] = {0.0f, 0.0f, 0.0f};
  uint count = min(have, 3u);
  if (dist[0] < 1e-30f) {
    count = 1u;
    w[0] = 1.0f;
  } else {
    const float far = have == 4u ? 1.0f / dist[3] : 0.0f;
    float sum = 0.0f;
    for (uint i = 0; i < 3u; ++i)
      if (i < count) {
        w[i] = fmax(1.0f / dist[i] - far, 0.0f);
        sum += w[i];
      }
    for (uint i = 0; i < 3u; ++i)
      if (i < count) w[i] = sum > 0.0f ? w[i] / sum : 1.0f / (float)count;
  }
  ch->blend_count = count;
  float3 b0 = (float3)(0.0f);
  for (uint i = 0; i < 3u; ++i) {
    const uint o_g = gi[i];
    const uint of = min(strand_offsets_g[o_g], point_count - 1u);
    const uint ol = clamp(strand_offsets_g[o_g + 1u], of + 1u, point_count);
    ch->blend_first[i] = of;
    ch->blend_n[i] = ol - of;
    ch->blend_w[i] = w[i];
    if (i < count) b0 += clh_child_load(points_g, point_count, of) * w[i];
  }
  ch->off = root - b0;
}

/* Stored point k (< n) of the child, w: the guide's styling w at k. */
static inline float4 clh_child_point(__global const float4* points_g, uint point_count,
                                     const clh_child* ch, uint k) {
  const float4 g = points_g[min(ch->first + k, point_count - 1u)];
  if (ch->kind == 0u) return g;
  const float F = clh_child_growth(ch, k);
  if (ch->kind == 1u) return (float4)(g.xyz + ch->off * F, g.w);
  float3 b = (float3)(0.0f);
  for (uint i = 0; i < 3u; ++i)
    if (i < ch->blend_count)
      b += clh_child_guide_at(points_g, point_count, ch->blend_first[i], ch->blend_n[i], k, ch->n) *
           ch->blend_w[i];
  return (float4)(b + ch->off * F, g.w);
}

#endif /* CLH_CHILDREN_H */
