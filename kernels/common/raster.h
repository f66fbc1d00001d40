/* raster.h — the device side of strand rasterisation, shared by the kernels that generate
 * strands (strands.cl) and those that read stored ones (strands_explicit.cl): the per-view
 * setup (and that of a light's deep-opacity pass), and the loop that draws a lane's run of
 * segments.
 * The segment walk itself (layers, hit rule, G-buffer word, atomics) is
 * kernels/include/clhair/raster_core.h, which the CPU floor of the benchmark compiles too.
 */
#ifndef CLHAIR_RASTER_H
#define CLHAIR_RASTER_H

#include "clhair/raster_core.h"

#define CLH_UP ((float3)(0.0f, 1.0f, 0.0f))

/* float3 faces of the scalar helpers of raster_core.h (same arithmetic, same rounding) */
static inline float3 clh_unit_or(float3 v, float3 fallback) {
  float a[3] = {v.x, v.y, v.z};
  const float f[3] = {fallback.x, fallback.y, fallback.z};
  clh_normalize3(a, f);
  return (float3)(a[0], a[1], a[2]);
}
static inline float3 clh_end_tangent_unit(float3 q, float3 t_neighbour) {
  const float qa[3] = {q.x, q.y, q.z};
  float t[3] = {t_neighbour.x, t_neighbour.y, t_neighbour.z};
  clh_end_tangent3(qa, t);
  return (float3)(t[0], t[1], t[2]);
}

/* Fills the per-view raster constants (written through a pointer: Oclgrind's LLVM lacks
 * the noalias-scope intrinsic clang emits when a returned struct is inlined). */
static inline void clh_raster_setup(clh_raster_ctx* rcp, __global const ClhGroomGpu* g,
                                    __global const ClhViewGpu* view_g) {
  clh_raster_ctx rc;
  clh_raster_init(&rc, view_g->fx, view_g->fy, view_g->cx, view_g->cy, view_g->width,
                  view_g->height, g->depth_near, g->depth_far, g->strand_width, g->hit_diameter_px);
  *rcp = rc;
}

#if CLH_RASTER_CURVE
/* The curve pass draws only the strands hair linking chose as sources (filter.cl). */
static inline bool clh_raster_curve_wanted(const clh_raster_ctx* rc, uint strand) {
  const uint word = strand >> 5;
  return word < rc->link_words && ((rc->link_flags_g[word] >> (strand & 31u)) & 1u) != 0u;
}
#endif

#if CLH_RASTER_OPACITY
/* The deep-opacity pass of one light (-DCLH_RASTER_OPACITY=1): its texels in the shared
 * maps and its layer bounds (ClhShadowGpu), and the nearest hair depth z0 per texel. */
static inline void clh_raster_opacity_setup(clh_raster_ctx* rc,
                                            __global const ClhShadowGpu* shadow_g,
                                            __global const float* hair_depth_g) {
  rc->hair_depth_g = hair_depth_g;
  rc->dom_offset = shadow_g->offset;
  for (int k = 0; k < CLH_DOM_LAYERS; ++k) rc->bound[k] = shadow_g->bound[k];
}
#endif

/* Draws a lane's run of a strand: segments (k, k + 1) for its `count` points from
 * `first` on (positions with styling w in P[i].w, tangents with AO in T[i].w, object
 * space), the last one closed by the next lane's first point next_p/next_t; no segment
 * reaches past point total - 1. */
static inline void clh_raster_lane(clh_raster_ctx* rc, __global const float* scene_depth_g,
                                   __global ulong* gbuf_g, __global uint* stats_g,
                                   __global const ClhGroomGpu* g, const float4* P, const float4* T,
                                   uint first, uint count, uint total, float4 next_p,
                                   float4 next_t) {
  float to_view[12], to_world[12];
  for (int k = 0; k < 12; ++k) {
    to_view[k] = g->obj_to_view[k];
    to_world[k] = g->obj_to_world[k];
  }
  ClhRasterVertex prev;
  uint counts[4] = {0u, 0u, 0u, 0u};
  for (uint i = 0; i <= count; ++i) {
    if (first + i >= total) break;
    const float4 p = (i < count) ? P[i] : next_p;
    const float4 t = (i < count) ? T[i] : next_t;
    ClhRasterVertex v;
    float o[3];
    clh_xform3(to_view, p.x, p.y, p.z, 1.0f, o);
    v.x = o[0];
    v.y = o[1];
    v.z = o[2];
    clh_xform3(to_world, t.x, t.y, t.z, 0.0f, o);
    v.tx = o[0];
    v.ty = o[1];
    v.tz = o[2];
    v.ao = t.w;
    v.w = p.w;
    v.u = (rc->u_base + (float)(first + i)) * rc->u_scale;
#if CLH_POINT_ID
    v.k = rc->u_base + (float)(first + i);
#endif
    clh_raster_project(rc, &v);
    if (i > 0u) clh_raster_segment(rc, scene_depth_g, gbuf_g, counts, prev, v);
    prev = v;
  }
#if CLH_RASTER_STATS
  for (int c = 0; c < 4; ++c)
    if (counts[c] > 0u) atomic_add(stats_g + c, counts[c]);
#else
  (void)stats_g;
#endif
}

#if CLH_RASTER_POINTS
/* The point pass of per-point shading (-DCLH_RASTER_POINTS=1): the marked-point bitmap and
 * its per-word ranks (kernels/points.cl), and where the marked points' inputs go. */
static inline void clh_points_setup(clh_raster_ctx* rc, __global const uint* bits_g,
                                    __global const uint* offsets_g, uint words,
                                    __global ClhPointGpu* points_g, uint capacity) {
  rc->point_bits_g = bits_g;
  rc->point_offsets_g = offsets_g;
  rc->point_words = words;
  rc->points_g = points_g;
  rc->point_capacity = capacity;
}

static inline bool clh_point_marked(const clh_raster_ctx* rc, uint point) {
  const uint w = point >> 5;
  return w < rc->point_words && ((rc->point_bits_g[w] >> (point & 31u)) & 1u) != 0u;
}

/* Whether any of points [base, base + n) is marked (the same answer in every lane). */
static inline bool clh_points_any(const clh_raster_ctx* rc, uint base, uint n) {
  if (n == 0u) return false;
  const uint w0 = base >> 5, w1 = (base + n - 1u) >> 5;
  for (uint w = w0; w <= w1 && w < rc->point_words; ++w) {
    uint bits = rc->point_bits_g[w];
    if (w == w0) bits &= ~0u << (base & 31u);
    if (w == w1 && ((base + n) & 31u) != 0u) bits &= ~(~0u << ((base + n) & 31u));
    if (bits != 0u) return true;
  }
  return false;
}

/* Writes the shading inputs of the marked points of a lane's run (the points it owns,
 * first + i for i < count, numbered as clh_raster_lane numbers them) at their slots: the
 * world position and view depth, and the G-buffer word the raster forms at the point. */
static inline void clh_points_lane(const clh_raster_ctx* rc, __global const ClhGroomGpu* g,
                                   const float4* P, const float4* T, uint first, uint count) {
  float to_view[12], to_world[12];
  for (int k = 0; k < 12; ++k) {
    to_view[k] = g->obj_to_view[k];
    to_world[k] = g->obj_to_world[k];
  }
  for (uint i = 0; i < count; ++i) {
    const uint point = rc->point_base + (uint)rc->u_base + first + i;
    if (!clh_point_marked(rc, point)) continue;
    const uint w = point >> 5, below = rc->point_bits_g[w] & ((1u << (point & 31u)) - 1u);
    const uint slot = rc->point_offsets_g[w] + popcount(below);
    if (slot >= rc->point_capacity) continue;
    float wp[3], vp[3], wt[3];
    clh_xform3(to_world, P[i].x, P[i].y, P[i].z, 1.0f, wp);
    clh_xform3(to_view, P[i].x, P[i].y, P[i].z, 1.0f, vp);
    clh_xform3(to_world, T[i].x, T[i].y, T[i].z, 0.0f, wt);
    const float l1 = fabs(wt[0]) + fabs(wt[1]) + fabs(wt[2]);
    const uint oct = (l1 > 1e-30f && l1 < 1e30f) ? clh_oct_encode(wt[0], wt[1], wt[2])
                                                 : clh_oct_encode(0.0f, 1.0f, 0.0f);
    const ulong word = clh_gbuf_pack(0u, oct, rc->u6, rc->v6, clh_unorm_bits(P[i].w, 6u),
                                     clh_unorm_bits(T[i].w, 6u));
    __global ClhPointGpu* out = rc->points_g + slot;
    out->pos[0] = wp[0];
    out->pos[1] = wp[1];
    out->pos[2] = wp[2];
    out->pos[3] = vp[2];
    out->word_lo = (uint)word;
    out->word_hi = (uint)(word >> 32);
    out->pad0 = 0u;
    out->pad1 = 0u;
  }
}
#endif

#if CLH_RASTER_MOTION
/* The motion pass (-DCLH_RASTER_MOTION=1): a lane's run drawn as clh_raster_lane draws it,
 * each vertex carrying its screen motion to the previous frame: the same point of the
 * strand evaluated from the previous frame's cage or points (PP, next_pp: object space of
 * that frame), projected with the previous transform and camera (m_g), minus its projection
 * now. A vertex behind either camera's near plane moves by 0. */
static inline void clh_raster_lane_motion(clh_raster_ctx* rc, __global const float* scene_depth_g,
                                          __global ulong* gbuf_g, __global const ClhGroomGpu* g,
                                          __global const ClhMotionGpu* m_g, const float4* P,
                                          const float4* T, const float4* PP, uint first, uint count,
                                          uint total, float4 next_p, float4 next_t,
                                          float4 next_pp) {
  float to_view[12], to_world[12], prev_view[12];
  for (int k = 0; k < 12; ++k) {
    to_view[k] = g->obj_to_view[k];
    to_world[k] = g->obj_to_world[k];
    prev_view[k] = m_g->prev_obj_to_view[k];
  }
  const float pfx = m_g->fx, pfy = m_g->fy, pcx = m_g->cx, pcy = m_g->cy;
  /* at least the centre sample, at most the samples and the conservative layer */
  rc->motion_layers = clamp(m_g->depth_layers, 1u, (uint)CLH_MSAA + 1u);
  ClhRasterVertex prev;
  uint counts[4] = {0u, 0u, 0u, 0u};
  for (uint i = 0; i <= count; ++i) {
    if (first + i >= total) break;
    const float4 p = (i < count) ? P[i] : next_p;
    const float4 t = (i < count) ? T[i] : next_t;
    const float4 pp = (i < count) ? PP[i] : next_pp;
    ClhRasterVertex v;
    float o[3];
    clh_xform3(to_view, p.x, p.y, p.z, 1.0f, o);
    v.x = o[0];
    v.y = o[1];
    v.z = o[2];
    clh_xform3(to_world, t.x, t.y, t.z, 0.0f, o);
    v.tx = o[0];
    v.ty = o[1];
    v.tz = o[2];
    v.ao = t.w;
    v.w = p.w;
    clh_raster_project(rc, &v);
    clh_xform3(prev_view, pp.x, pp.y, pp.z, 1.0f, o);
    v.mx = 0.0f;
    v.my = 0.0f;
    if (o[2] >= rc->near_z && v.z >= rc->near_z) {
      v.mx = pcx + pfx * o[0] / o[2] - v.sx;
      v.my = pcy - pfy * o[1] / o[2] - v.sy;
    }
    if (i > 0u) clh_raster_segment(rc, scene_depth_g, gbuf_g, counts, prev, v);
    prev = v;
  }
}
#endif

#endif /* CLHAIR_RASTER_H */
