/* strands.cl — strand assembly and rasterisation: one work-group (one logical sub-group of
 * SG_SIZE lanes) per strand.
 *
 * Inputs: the groom (ClhGroomGpu), its bundles and hair-mesh vertices, the per-bundle LOD
 * records (ClhLodRecord: N_LOD, C, widening, morph gamma) and the offsets of their scan
 * (bundle_count + 2 entries: the exclusive scan, then the drawn total at [bundle_count]
 * and the visible total; gpu_types.h has the layout), and the progressive blue-noise
 * root sets.
 *
 * Assembly (Lipp §3.1.1, Bhokare §3.3-3.6): the lanes interpolate the bundle's layers at
 * the strand's root sample into local memory (finite-difference tangents, neighbours
 * exchanged by shuffles); then each lane evaluates its own run of the C control points on
 * the Hermite base spline, styles them, and swaps its first/last points and tangents with
 * its neighbours, so every point and tangent is computed exactly once (the tangents are
 * finished as for stored strands, strand_common.h). Lane i owns points
 * [i*S, i*S + S) with S = ceil((C-1)/SG_SIZE); when SG_SIZE*S == C-1 the last lane also
 * owns the tip. Inside a vertex-LOD transition window (gamma > 0) odd points move toward
 * their neighbours' midpoint and tangents blend with those of the coarser level
 * (Bhokare Eq. 11-12); that path reads the raw points from local memory.
 *
 * Rasterisation: every segment is drawn into the G-buffer layers with 64-bit atom_min,
 * depth tested against the scene depth:
 *   layers 0..CLH_MSAA-1  sample layers: a sample is hit when the strand passes within
 *                         half the hit diameter of it (CLH_MSAA = 1: the pixel center);
 *   layer CLH_MSAA        conservative: every pixel the segment touches (and every pixel
 *                         with a sample hit, so it contains all sample layers).
 * The hit diameter is the strand's projected width (at least the groom's minimum),
 * widened by N / N_LOD to compensate strands removed by LOD.
 *
 * Dispatch: in strands_raster group g draws strand strand_base + g, and groups past the
 * total leave at once (read-back and over-launch sizing); in strands_raster_persistent
 * group g draws every strand_stride-th strand from g on (a persistent grid). The two are
 * separate kernels so the common one has no loop around its barriers. strands_export
 * writes points and tangents instead of drawing; strands_store keeps a still's strands
 * (RenderOptions::reuseAssembly) and strands_raster_stored draws them in each of its passes,
 * word for word what strands_raster draws from the same records.
 */
#include "clhair/gpu_types.h"
#include "subgroup.h"
#include "clh_math.h"
#include "clhair/fast_math.h"
#include "hair_style.h"
#include "raster.h"
#include "strand_common.h"

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_int64_extended_atomics : enable

#include "strand_assembly.h"

/* Whether this pass draws the strand with identity `id` and C points (the curve pass and
 * the point pass draw only some); sets the strand's point base. Uniform per group. */
static inline bool clh_strand_wanted(clh_raster_ctx* rc, uint id, uint C) {
  (void)rc;
  (void)id;
  (void)C;
#if CLH_RASTER_CURVE
  if (!clh_raster_curve_wanted(rc, id)) return false;
#endif
#if CLH_POINT_ID || CLH_RASTER_POINTS
  rc->point_base = id * (uint)CLH_MAX_CONTROL_POINTS; /* point k of the strand: base + k */
#endif
#if CLH_RASTER_POINTS
  if (!clh_points_any(rc, rc->point_base, C)) return false;
#endif
  return true;
}

/* Draws the lane's share of an assembled (or loaded) strand. */
static inline void clh_draw_span(clh_raster_ctx* rc, __global const float* scene_depth_g,
                                 __global ulong* gbuf_g, __global uint* stats_g,
                                 __global const ClhGroomGpu* g, const float4* P, const float4* T,
                                 const clh_lane_span* span, uint id, float coverage) {
  rc->u6 = clh_unorm_bits(span->uv.x, 6u);
  rc->v6 = clh_unorm_bits(span->uv.y, 6u);
  rc->coverage = coverage;
  clh_raster_identity(rc, id, 0.0f, 1.0f / (float)(span->C - 1u));
#if CLH_RASTER_POINTS
  (void)scene_depth_g;
  (void)gbuf_g;
  (void)stats_g;
  clh_points_lane(rc, g, P, T, span->first, span->count);
#else
  clh_raster_lane(rc, scene_depth_g, gbuf_g, stats_g, g, P, T, span->first, span->count, span->C,
                  span->next_p, span->next_t);
#endif
}

/* Assembles strand `strand` (when it exists) and draws its segments. Uniform per group. */
static inline void clh_draw_strand(
    sg_ctx* sg, clh_strand_scratch scratch, clh_raster_ctx* rc, __global const ClhGroomGpu* g,
    __global const ClhBundle* bundles_g, __global const ClhMeshVertex* verts_g,
    __global const ClhLodRecord* lod_g, __global const uint* offsets_g,
    __global const float2* roots_quad_g, __global const float2* roots_tri_g,
    __global const float* scene_depth_g, __global ulong* gbuf_g, __global uint* stats_g,
    uint strand) {
  uint bundle = 0u, local_index = 0u, C = 2u;
  float gamma = 0.0f, coverage = 1.0f;
  if (!clh_strand_job(g, lod_g, offsets_g, bundles_g, strand, &bundle, &local_index, &C, &gamma,
                      &coverage))
    return;
  const uint id = bundles_g[bundle].first_strand + local_index;
  if (!clh_strand_wanted(rc, id, C)) return; /* uniform per group */
  float4 P[CLH_PTS_CAP], T[CLH_PTS_CAP];
  clh_lane_span span;
  clh_assemble_strand(sg, scratch.layers, scratch.strand, scratch.pts, g, bundles_g + bundle,
                      verts_g, roots_quad_g, roots_tri_g, bundle, local_index, C, gamma, P, T,
                      &span);
  clh_draw_span(rc, scene_depth_g, gbuf_g, stats_g, g, P, T, &span, id, coverage);
}

#define CLH_RASTER_PARAMS                                                                  \
  __global const ClhGroomGpu *groom_g, __global const ClhViewGpu *view_g,                  \
      __global const ClhBundle *bundles_g, __global const ClhMeshVertex *verts_g,          \
      __global const ClhLodRecord *lod_g, __global const uint *offsets_g,                  \
      __global const float2 *roots_quad_g, __global const float2 *roots_tri_g,             \
      __global const float *scene_depth_g, __global ulong *gbuf_g, __global uint *stats_g, \
      uint strand_base, uint strand_stride CLH_CURVE_PARAMS

#if CLH_RASTER_CURVE
/* the curve pass (hair linking): the source strands' bitmap */
#define CLH_CURVE_PARAMS , __global const uint *link_flags_g, uint link_words
#define CLH_CURVE_SETUP(rc)         \
  (rc).link_flags_g = link_flags_g; \
  (rc).link_words = link_words
#elif CLH_RASTER_POINTS
/* the point pass (per-point shading): the marked points, their ranks and their records */
#define CLH_CURVE_PARAMS                                                                       \
  , __global const uint *point_bits_g, __global const uint *point_offsets_g, uint point_words, \
      __global ClhPointGpu *point_records_g, uint point_capacity
#define CLH_CURVE_SETUP(rc)                                                            \
  clh_points_setup(&(rc), point_bits_g, point_offsets_g, point_words, point_records_g, \
                   point_capacity)
#else
#define CLH_CURVE_PARAMS
#define CLH_CURVE_SETUP(rc) (void)0
#endif

#define CLH_RASTER_PROLOGUE                        \
  SG_DECLARE(sg);                                  \
  SG_SHARED clh_layer_pt layers_l[CLH_MAX_LAYERS]; \
  SG_SHARED clh_strand strand_l[1];                \
  SG_SHARED float4 pts_l[CLH_MAX_CONTROL_POINTS];  \
  clh_strand_scratch scratch;                      \
  scratch.layers = layers_l;                       \
  scratch.strand = strand_l;                       \
  scratch.pts = pts_l;                             \
  clh_raster_ctx rc;                               \
  clh_raster_setup(&rc, groom_g, view_g);          \
  CLH_CURVE_SETUP(rc)

#if CLH_RASTER_MOTION
/* The motion pass of a deforming hair mesh (built with -DCLH_RASTER_MOTION=1), run after
 * strands_raster (and hair linking's merge) over the same LOD records, scene depth and
 * finished G-buffer: each strand
 * is assembled from this frame's layer vertices, exactly as strands_raster drew it, and
 * from the previous frame's (prev_verts_g: the same strand, root sample and control points
 * on the previous cage); every fragment whose word is the one the pixel's depth comes from
 * (ClhMotionGpu::depth_layers) writes the screen motion between the two (raster.h,
 * clh_raster_lane_motion) to motion_g. One strand per work-group. */
__kernel SG_KERNEL_ATTRS void strands_motion(CLH_RASTER_PARAMS,
                                             __global const ClhMeshVertex* prev_verts_g,
                                             __global const ClhMotionGpu* motion_params_g,
                                             __global ulong* motion_g) {
  CLH_RASTER_PROLOGUE;
  (void)strand_stride;
  (void)stats_g;
  rc.motion_g = motion_g;
  const uint strand = sg_strand_index(strand_base);
  uint bundle = 0u, local_index = 0u, C = 2u;
  float gamma = 0.0f, coverage = 1.0f;
  if (!clh_strand_job(groom_g, lod_g, offsets_g, bundles_g, strand, &bundle, &local_index, &C,
                      &gamma, &coverage))
    return;
  float4 P[CLH_PTS_CAP], T[CLH_PTS_CAP], PP[CLH_PTS_CAP], TP[CLH_PTS_CAP];
  clh_lane_span span, prev_span;
  clh_assemble_strand(&sg, layers_l, strand_l, pts_l, groom_g, bundles_g + bundle, verts_g,
                      roots_quad_g, roots_tri_g, bundle, local_index, C, gamma, P, T, &span);
  sg_barrier(); /* the scratch is assembled into again */
  clh_assemble_strand(&sg, layers_l, strand_l, pts_l, groom_g, bundles_g + bundle, prev_verts_g,
                      roots_quad_g, roots_tri_g, bundle, local_index, C, gamma, PP, TP, &prev_span);
  rc.u6 = clh_unorm_bits(span.uv.x, 6u);
  rc.v6 = clh_unorm_bits(span.uv.y, 6u);
  rc.coverage = coverage;
  clh_raster_lane_motion(&rc, scene_depth_g, gbuf_g, groom_g, motion_params_g, P, T, PP, span.first,
                         span.count, span.C, span.next_p, span.next_t, prev_span.next_p);
}
#elif !CLH_RASTER_OPACITY
#if CLH_HAS_ENTRY(CLH_ENTRY_RASTER)
/* One strand per work-group: strand_base + group (read-back and over-launch sizing). */
__kernel SG_KERNEL_ATTRS void strands_raster(CLH_RASTER_PARAMS) {
  CLH_RASTER_PROLOGUE;
  (void)strand_stride;
  clh_draw_strand(&sg, scratch, &rc, groom_g, bundles_g, verts_g, lod_g, offsets_g, roots_quad_g,
                  roots_tri_g, scene_depth_g, gbuf_g, stats_g, sg_strand_index(strand_base));
}
#endif

#if CLH_HAS_ENTRY(CLH_ENTRY_RASTER_VIEWS)
/* Several views of one assembly: each strand is assembled once (with groom_g, the record
 * of the view its LOD was chosen in) and drawn into every view's G-buffer. View v has its
 * own record view_grooms_g[v] (object -> view transform, depth mapping) and view record
 * views_g[v]; scene_depth_g and gbuf_g hold view_count slices of width * height (times the
 * layers) in view order, every view of the same size, view v's slice starting depth_stride
 * floats and gbuf_stride words after view v - 1's (the host pads them so that each slice is
 * a sub-buffer the later stages of its view use in place). One strand per work-group. */
__kernel SG_KERNEL_ATTRS void strands_raster_views(CLH_RASTER_PARAMS,
                                                   __global const ClhGroomGpu* view_grooms_g,
                                                   __global const ClhViewGpu* views_g,
                                                   uint view_count, ulong depth_stride,
                                                   ulong gbuf_stride) {
  CLH_RASTER_PROLOGUE;
  (void)strand_stride;
  uint bundle = 0u, local_index = 0u, C = 2u;
  float gamma = 0.0f, coverage = 1.0f;
  if (!clh_strand_job(groom_g, lod_g, offsets_g, bundles_g, sg_strand_index(strand_base), &bundle,
                      &local_index, &C, &gamma, &coverage))
    return;
  float4 P[CLH_PTS_CAP], T[CLH_PTS_CAP];
  clh_lane_span span;
  clh_assemble_strand(&sg, layers_l, strand_l, pts_l, groom_g, bundles_g + bundle, verts_g,
                      roots_quad_g, roots_tri_g, bundle, local_index, C, gamma, P, T, &span);
  for (uint v = 0; v < view_count; ++v) {
    clh_raster_setup(&rc, view_grooms_g + v, views_g + v);
    rc.u6 = clh_unorm_bits(span.uv.x, 6u);
    rc.v6 = clh_unorm_bits(span.uv.y, 6u);
    rc.coverage = coverage;
    clh_raster_lane(&rc, scene_depth_g + v * depth_stride, gbuf_g + v * gbuf_stride, stats_g,
                    view_grooms_g + v, P, T, span.first, span.count, span.C, span.next_p,
                    span.next_t);
  }
}
#endif

#if CLH_HAS_ENTRY(CLH_ENTRY_RASTER_STORED)
/* A strand stored by strands_store (below: the layout), loaded as the lanes of
 * its assembly held it: each lane's run of points and tangents and the next lane's first
 * ones, exactly what the shuffles of clh_assemble_strand handed over. */
static inline void clh_load_strand(__global const float4* points_g,
                                   __global const float4* tangents_g, size_t base, uint C,
                                   float4* P, float4* T, clh_lane_span* span) {
  const uint lane = sg_lane();
  const uint S = (C - 1u + SG_SIZE - 1u) / SG_SIZE;
  const uint first = lane * S;
  const uint end = (lane == (uint)(SG_SIZE - 1)) ? C : min(first + S, C);
  const uint count = end > first ? min(end - first, (uint)CLH_PTS_CAP) : 0u;
  for (uint i = 0; i < CLH_PTS_CAP; ++i) {
    P[i] = i < count ? points_g[base + first + i] : (float4)(0.0f);
    T[i] = i < count ? tangents_g[base + first + i] : (float4)(0.0f);
  }
  const uint next_first = first + S;
  const uint next_end = (lane + 1u == (uint)(SG_SIZE - 1)) ? C : min(next_first + S, C);
  const bool next = lane + 1u < (uint)SG_SIZE && next_end > next_first;
  span->next_p = next ? points_g[base + next_first] : (float4)(0.0f);
  span->next_t = next ? tangents_g[base + next_first] : (float4)(0.0f);
  span->C = C;
  span->first = first;
  span->count = count;
}

/* The strands of a still drawn from their stored assembly (strands_store): the LOD records
 * and scan they were stored with (lod_g, offsets_g), point_base_g the first stored point of
 * each bundle's strands (C points per strand), uv_g the root coordinates per draw index.
 * Draws exactly what strands_raster draws from the same records when subset is 1. With
 * subset N > 1 (RenderOptions::finalSubset) the pass draws the strands whose hash plus
 * `pass` is a multiple of N, widened N-fold: N passes in a row draw every strand once, at
 * the coverage of all of them. One strand per group. */
__kernel SG_KERNEL_ATTRS void strands_raster_stored(
    CLH_RASTER_PARAMS, __global const uint* point_base_g, __global const float4* points_g,
    __global const float4* tangents_g, __global const float2* uv_g, ulong point_capacity,
    uint strand_capacity, uint subset, uint pass) {
  clh_raster_ctx rc;
  clh_raster_setup(&rc, groom_g, view_g);
  CLH_CURVE_SETUP(rc);
  (void)verts_g;
  (void)roots_quad_g;
  (void)roots_tri_g;
  (void)strand_stride;
  const uint strand = sg_strand_index(strand_base);
  uint bundle = 0u, local_index = 0u, C = 2u;
  float gamma = 0.0f, coverage = 1.0f;
  size_t base = 0;
  if (!clh_stored_job(groom_g, lod_g, offsets_g, bundles_g, point_base_g, point_capacity,
                      strand_capacity, strand, &bundle, &local_index, &C, &gamma, &coverage, &base))
    return;
  const uint id = bundles_g[bundle].first_strand + local_index;
  if (subset > 1u) {
    if ((clh_hash(id) + pass) % subset != 0u) return; /* uniform per group */
    coverage *= (float)subset;
  }
  if (!clh_strand_wanted(&rc, id, C)) return;
  float4 P[CLH_PTS_CAP], T[CLH_PTS_CAP];
  clh_lane_span span;
  clh_load_strand(points_g, tangents_g, base, C, P, T, &span);
  span.uv = uv_g[strand];
  clh_draw_span(&rc, scene_depth_g, gbuf_g, stats_g, groom_g, P, T, &span, id, coverage);
}
#endif

#if CLH_HAS_ENTRY(CLH_ENTRY_RASTER_PERSISTENT)
/* Persistent grid: group g draws strands g, g + stride, g + 2 stride, ... below the total. */
__kernel SG_KERNEL_ATTRS void strands_raster_persistent(CLH_RASTER_PARAMS) {
  CLH_RASTER_PROLOGUE;
  const uint total = clh_lod_drawn_total(offsets_g, groom_g->bundle_count);
  for (uint strand = sg_strand_index(strand_base); strand < total;
       strand += SG_STRAND_STRIDE(max(strand_stride, 1u))) {
    clh_draw_strand(&sg, scratch, &rc, groom_g, bundles_g, verts_g, lod_g, offsets_g, roots_quad_g,
                    roots_tri_g, scene_depth_g, gbuf_g, stats_g, strand);
  }
}
#endif
#else
/* Deep-opacity layers of one light (built with -DCLH_RASTER_OPACITY=1): the strands seen
 * from the light, every texel they touch in front of the opaque scene adding coverage to
 * the layer of its depth past z0. One strand per work-group. */
__kernel SG_KERNEL_ATTRS void strands_opacity(
    __global const ClhGroomGpu* groom_g, __global const ClhViewGpu* view_g,
    __global const ClhBundle* bundles_g, __global const ClhMeshVertex* verts_g,
    __global const ClhLodRecord* lod_g, __global const uint* offsets_g,
    __global const float2* roots_quad_g, __global const float2* roots_tri_g,
    __global const float* opaque_depth_g, __global const ClhShadowGpu* shadow_g,
    __global const float* hair_depth_g, __global uint* opacity_g, uint strand_base) {
  SG_DECLARE(sg);
  SG_SHARED clh_layer_pt layers_l[CLH_MAX_LAYERS];
  SG_SHARED clh_strand strand_l[1];
  SG_SHARED float4 pts_l[CLH_MAX_CONTROL_POINTS];
  clh_strand_scratch scratch;
  scratch.layers = layers_l;
  scratch.strand = strand_l;
  scratch.pts = pts_l;
  clh_raster_ctx rc;
  clh_raster_setup(&rc, groom_g, view_g);
  clh_raster_opacity_setup(&rc, shadow_g, hair_depth_g);
  clh_draw_strand(&sg, scratch, &rc, groom_g, bundles_g, verts_g, lod_g, offsets_g, roots_quad_g,
                  roots_tri_g, opaque_depth_g + shadow_g->offset, (__global ulong*)opacity_g, 0,
                  sg_strand_index(strand_base));
}
#endif

#if !CLH_RASTER_OPACITY && !CLH_RASTER_MOTION && CLH_HAS_ENTRY(CLH_ENTRY_EXPORT)
/* Writes the assembled strands: points_g/tangents_g hold CLH_MAX_CONTROL_POINTS float4 per
 * strand (object space; w = styling w / ambient occlusion), counts_g the point count. */
__kernel SG_KERNEL_ATTRS void strands_export(
    __global const ClhGroomGpu* groom_g, __global const ClhBundle* bundles_g,
    __global const ClhMeshVertex* verts_g, __global const ClhLodRecord* lod_g,
    __global const uint* offsets_g, __global const float2* roots_quad_g,
    __global const float2* roots_tri_g, __global float4* points_g, __global float4* tangents_g,
    __global uint* counts_g, uint strand_base, uint strand_capacity) {
  SG_DECLARE(sg);
  SG_SHARED clh_layer_pt layers_l[CLH_MAX_LAYERS];
  SG_SHARED clh_strand strand_l[1];
  SG_SHARED float4 pts_l[CLH_MAX_CONTROL_POINTS];
  uint strand = sg_strand_index(strand_base);
  uint bundle = 0u, local_index = 0u, C = 2u;
  float gamma = 0.0f, coverage = 1.0f;
  if (strand >= strand_capacity || !clh_strand_job(groom_g, lod_g, offsets_g, bundles_g, strand,
                                                   &bundle, &local_index, &C, &gamma, &coverage))
    return;

  float4 P[CLH_PTS_CAP], T[CLH_PTS_CAP];
  clh_lane_span span;
  clh_assemble_strand(&sg, layers_l, strand_l, pts_l, groom_g, bundles_g + bundle, verts_g,
                      roots_quad_g, roots_tri_g, bundle, local_index, C, gamma, P, T, &span);
  clh_write_lane(points_g, tangents_g, (size_t)strand * CLH_MAX_CONTROL_POINTS, P, T, &span);
  if (sg_lane() == 0u) counts_g[strand] = span.C;
}
#endif

#if !CLH_RASTER_OPACITY && !CLH_RASTER_MOTION && CLH_HAS_ENTRY(CLH_ENTRY_STORE)
/* Stores the assembled strands of a still once, for strands_raster_stored to draw in every
 * pass: strand `local_index` of bundle b keeps its C points and tangents (object space, w as
 * in the raster) from point_base_g[b] + local_index * C on (the host's scan of the records'
 * strands times their C), its root coordinates at uv_g[draw index]. */
__kernel SG_KERNEL_ATTRS void strands_store(
    __global const ClhGroomGpu* groom_g, __global const ClhBundle* bundles_g,
    __global const ClhMeshVertex* verts_g, __global const ClhLodRecord* lod_g,
    __global const uint* offsets_g, __global const float2* roots_quad_g,
    __global const float2* roots_tri_g, __global const uint* point_base_g,
    __global float4* points_g, __global float4* tangents_g, __global float2* uv_g,
    ulong point_capacity, uint strand_base, uint strand_capacity) {
  SG_DECLARE(sg);
  SG_SHARED clh_layer_pt layers_l[CLH_MAX_LAYERS];
  SG_SHARED clh_strand strand_l[1];
  SG_SHARED float4 pts_l[CLH_MAX_CONTROL_POINTS];
  const uint strand = sg_strand_index(strand_base);
  uint bundle = 0u, local_index = 0u, C = 2u;
  float gamma = 0.0f, coverage = 1.0f;
  size_t base = 0;
  if (!clh_stored_job(groom_g, lod_g, offsets_g, bundles_g, point_base_g, point_capacity,
                      strand_capacity, strand, &bundle, &local_index, &C, &gamma, &coverage, &base))
    return;
  float4 P[CLH_PTS_CAP], T[CLH_PTS_CAP];
  clh_lane_span span;
  clh_assemble_strand(&sg, layers_l, strand_l, pts_l, groom_g, bundles_g + bundle, verts_g,
                      roots_quad_g, roots_tri_g, bundle, local_index, C, gamma, P, T, &span);
  clh_write_lane(points_g, tangents_g, base, P, T, &span);
  if (sg_lane() == 0u) uv_g[strand] = span.uv;
}
#endif
