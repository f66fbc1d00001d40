/* strands_explicit.cl — stored strands (cyHair / USC-HairSalon files, StrandGroom) drawn
 * through the same rasteriser as generated ones: one work-group (one logical sub-group of
 * SG_SIZE lanes) per strand.
 *
 * Inputs (host/groom/explicit_data.h has the tables): the groom record (ClhGroomGpu, with
 * bundle_count = chunk count and control_points = the full-detail C of the LOD formulas),
 * the points (float4: object-space xyz, styling w), the strand offsets (strand s owns
 * points [offsets[s], offsets[s+1])), optional packed root uv (unorm16 u | v << 16), the
 * chunk table (uint4: first strand, strand count, LOD delta bits, 0), and per chunk the LOD
 * record of lod_chunks (ClhLodRecord: N_LOD, C, widening, gamma) with the offsets of its scan
 * (scan_bundles: chunk_count + 2 entries, the drawn total at [chunk_count]; gpu_types.h
 * has the layout).
 *
 * Drawn strand g is the (g - scan[c])-th strand of the chunk c that holds it, drawn only
 * when it is among the chunk's first N_LOD (the chunk's strands are in random order, so
 * that is a uniform sample); its hit diameter is widened by N / N_LOD like strands.cl.
 * With children (ClhChildrenGpu count > 0) a chunk of n stored strands (guides) draws
 * n (1 + count) strands: slot j is child j / n of guide j % n, child 0 the guide itself,
 * so LOD keeps the guides first and then the children layer by layer, evenly over the
 * chunk. A child's points are made from its guide's (and, interpolated, two neighbours')
 * stored points as they are loaded (common/children.h), never stored; its identity is
 * guide + child * strand_count.
 * Vertex LOD skips points: every step-th stored point is drawn plus the tip, step = 2^k
 * with (C - 1) step = C_full - 1 (C from Lipp Eq. 4-5), halved while the strand would keep
 * fewer than 3 points. Inside the transition window (gamma > 0, Bhokare Eq. 10-12) the odd
 * drawn points move toward the midpoint of their neighbours, so a level hands over to the
 * next without a jump; tangents are then taken from the moved points.
 *
 * Assembly: the drawn points are processed in rounds of CLH_X_ROUND segments. Within a
 * round lane i owns points [i*S, i*S + S) (the last lane also the round's last point),
 * S = ceil(segments / SG_SIZE), like strands.cl. Each lane loads its run of stored points;
 * neighbouring lanes exchange first/last points and tangents with sub-group shuffles, and
 * the round's edge lanes take the point beyond the round from global memory as the
 * shuffle's fill value. Tangents are central differences inside and Bhokare's reflection
 * rule (Eq. 5-6) at the root and the tip, finished as in strands.cl (strand_common.h) but
 * with raster_core.h's normalisation, like the CPU floor. The G-buffer word means the
 * same as for generated strands: u, v from the stored root uv or a per-strand hash, w from
 * the point, AO 1; with per-point file colour (look[2]) u, v and AO hold the colour instead
 * (clh_x_file_look). The points table then holds twice point_count entries.
 *
 * Kernels: strands_explicit_raster (group g draws strand strand_base + g; read-back and
 * over-launch sizing), strands_explicit_raster_persistent (group g draws every
 * strand_stride-th strand from g), strands_explicit_opacity (-DCLH_RASTER_OPACITY=1: deep
 * opacity layers of one light), strands_explicit_export (drawn points and tangents, tests).
 */
#include "clhair/gpu_types.h"
#include "clhair/lod_math.h"
#include "subgroup.h"
#include "clh_math.h"
#include "raster.h"
#include "strand_common.h"
#include "children.h"

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_int64_extended_atomics : enable

#define CLH_X_PER_LANE 4
#define CLH_X_ROUND (SG_SIZE * CLH_X_PER_LANE) /* segments per round */
#define CLH_X_CAP (CLH_X_PER_LANE + 1)         /* points a lane can own in a round */

/* The stored strand tables of one groom. */
typedef struct {
  __global const float4* points;
  __global const uint* strand_offsets;
  __global const uint* uv;
  __global const uint4* chunks;
  __global const ClhChildrenGpu* kids;
  __global const uint* nbr;
  uint strand_count;
  uint point_count;
  uint has_uv;
} clh_x_tables;

/* What a work-group draws. */
typedef struct {
  uint strand;    /* index into the strand tables (a child's: its guide's) */
  uint id;        /* strand identity: strand + child * strand_count */
  uint child;     /* 0: the stored strand; k >= 1: its k-th child (children.h) */
  uint first;     /* its first stored point */
  uint n;         /* stored points */
  uint step;      /* drawn point j is stored point min(j * step, n - 1) */
  uint M;         /* drawn points */
  float coverage; /* N / N_LOD of its chunk */
  float gamma;    /* vertex-LOD morph toward step * 2 */
  clh_child ch;   /* how the points are made from the stored ones */
} clh_x_job;

/* The strand drawn by draw index `index`; false when there is none (uniform per group). */
static inline bool clh_x_find_job(__global const ClhGroomGpu* g, const clh_x_tables* tb,
                                  __global const ClhLodRecord* lod_g,
                                  __global const uint* offsets_g, uint index, clh_x_job* job) {
  uint c = 0u, slot = 0u;
  if (!clh_lod_find_strand(offsets_g, g->bundle_count, index, &c, &slot)) return false;
  const ClhLodRecord lod = lod_g[c];
  const uint4 chunk = tb->chunks[c];
  if (slot >= lod.strands || slot >= chunk.y) return false;
  /* slot j: child j / guides of the chunk's guide j % guides (chunk table, explicit_data.h) */
  const uint guides = max(min(chunk.w, chunk.y), 1u);
  const uint child = slot / guides;
  const uint s = chunk.x + slot % guides;
  if (s >= tb->strand_count) return false;
  const uint first = min(tb->strand_offsets[s], tb->point_count);
  const uint last = clamp(tb->strand_offsets[s + 1u], first, tb->point_count);
  const uint n = last - first;
  if (n < 2u) return false;
  const uint c_full = clamp(g->control_points, 3u, (uint)CLH_MAX_CONTROL_POINTS);
  const uint C = clamp(lod.control_points, 3u, c_full);
  uint coarse = 1u;
  while ((C - 1u) * coarse < c_full - 1u) coarse <<= 1;
  const uint step = clh_explicit_step(n, C, c_full); /* lod_math.h, shared with lod_chunks */
  float gamma = clamp(lod.gamma, 0.0f, 1.0f);
  if (step < coarse) gamma = 0.0f;      /* the strand is already at its coarsest level */
  if (n - 1u < 4u * step) gamma = 0.0f; /* the next level would keep fewer than 3 points */
  job->strand = s;
  job->child = child;
  job->id = s + child * tb->strand_count;
  job->first = first;
  job->n = n;
  job->step = step;
  job->M = (n - 1u + step - 1u) / step + 1u;
  job->coverage = clh_lod_record_coverage(lod);
  job->gamma = gamma;
  clh_child_setup(tb->points, tb->point_count, tb->strand_offsets, tb->strand_count, tb->kids,
                  tb->nbr, s, child, first, n, &job->ch);
  return true;
}

/* Drawn point j of the job (bounds-safe). */
static inline float4 clh_x_point(const clh_x_tables* tb, const clh_x_job* job, uint j) {
  const uint k = min(j * job->step, job->n - 1u);
  return clh_child_point(tb->points, tb->point_count, &job->ch, k);
}

/* The lane's share of one round. */
typedef struct {
  uint first;    /* round-local index of the lane's first point */
  uint count;    /* points it owns */
  uint points;   /* points in the round */
  uint base;     /* drawn index of the round's first point */
  float4 next_p; /* the next lane's first point and final tangent */
  float4 next_t;
} clh_x_span;

/* Loads and finishes the round starting at drawn point `base` into P, T (tangent, AO in
 * w). Every lane must call it. */
static inline void clh_x_round(sg_ctx* sg, const clh_x_tables* tb, const clh_x_job* job, uint base,
                               float4* P, float4* T, clh_x_span* span) {
  const uint lane = sg_lane();
  const uint M = job->M;
  const uint E = min(base + (uint)CLH_X_ROUND, M - 1u); /* the round's last drawn point */
  const uint Cr = E - base + 1u;
  const uint S = (Cr - 1u + SG_SIZE - 1u) / SG_SIZE;
  const uint first = lane * S;
  const uint end = (lane == (uint)(SG_SIZE - 1)) ? Cr : min(first + S, Cr);
  const uint count = end > first ? min(end - first, (uint)CLH_X_CAP) : 0u;
  const uint k0 = base + first;
  for (uint i = 0; i < CLH_X_CAP; ++i) {
    P[i] = (float4)(0.0f);
    T[i] = (float4)(0.0f, 0.0f, 0.0f, 1.0f);
    if (i < count) P[i] = clh_x_point(tb, job, k0 + i);
  }
  /* the points just outside the round, from memory: the fills of the edge lanes */
  const float4 halo_prev =
      (lane == 0u && base > 0u) ? clh_x_point(tb, job, base - 1u) : (float4)(0.0f);
  const float4 halo_next =
      (lane == (uint)(SG_SIZE - 1) && E + 1u < M) ? clh_x_point(tb, job, E + 1u) : (float4)(0.0f);
  const uint last = count > 0u ? count - 1u : 0u;

  /* exchange 1: neighbour points */
  float4 prev_p = sg_shuffle_up1_f4(sg, P[last], halo_prev);
  float4 next_p = sg_shuffle_down1_f4(sg, P[0], halo_next);

  if (job->gamma > 0.0f) {
    /* vertex-LOD transition (Bhokare Eq. 11): odd drawn points (and their w) move toward
     * the midpoint of their neighbours, which the coarser level keeps (even points, or the
     * tip). The neighbours of an odd point are never moved, so this works in place; the
     * edge lanes morph the point beyond the round themselves, then the edges are
     * exchanged again. */
    for (uint i = 0; i < CLH_X_CAP; ++i) {
      uint k = k0 + i;
      if (i < count && (k & 1u) == 1u && k + 1u < M) {
        float4 a = i > 0u ? P[i - 1u] : prev_p;
        float4 c = i + 1u < count ? P[i + 1u] : next_p;
        P[i] = mix(P[i], 0.5f * (a + c), job->gamma);
      }
    }
    float4 hp = halo_prev, hn = halo_next;
    if (lane == 0u && base > 0u && ((base - 1u) & 1u) == 1u)
      hp = mix(halo_prev, 0.5f * (clh_x_point(tb, job, base - 2u) + P[0]), job->gamma);
    if (lane == (uint)(SG_SIZE - 1) && E + 2u < M && ((E + 1u) & 1u) == 1u)
      hn = mix(halo_next, 0.5f * (P[last] + clh_x_point(tb, job, E + 2u)), job->gamma);
    prev_p = sg_shuffle_up1_f4(sg, P[last], hp);
    next_p = sg_shuffle_down1_f4(sg, P[0], hn);
  }

  clh_finish_tangents(sg, P, T, CLH_X_CAP, k0, count, M, prev_p, next_p, CLH_TANGENT_DIVIDE);
  /* last exchange: the next lane's first tangent, now final */
  span->next_t = sg_shuffle_down1_f4(sg, T[0], (float4)(0.0f, 0.0f, 0.0f, 1.0f));
  span->next_p = next_p;
  span->first = first;
  span->count = count;
  span->points = Cr;
  span->base = base;
}

/* Per-point colour and thickness of a strand file (groom look[2] = 1: colour, look[3] > 0:
 * thickness times that object -> world scale; look[3] < 0: the groom's width times the
 * opacity -w), stored after the points as float4 linear rgb and thickness (or -opacity). A lane's
 * run is drawn with their means over its points: the colour in the word's u, v and AO fields
 * (gpu_types.h; AO through the tangents' w), the width in the raster's pixels per unit depth. */
static inline void clh_x_file_look(clh_raster_ctx* rc, __global const ClhGroomGpu* g,
                                   const clh_x_tables* tb, const clh_x_job* job, clh_x_span* span,
                                   float4* T) {
  if (span->count == 0u) return;
  float4 sum = (float4)(0.0f);
  for (uint i = 0; i < CLH_X_CAP; ++i)
    if (i < span->count) {
      const uint k = min((span->base + span->first + i) * job->step, job->n - 1u);
      sum += tb->points[tb->point_count + min(job->first + k, tb->point_count - 1u)];
    }
  const float4 a = sum / (float)span->count;
  if (g->look[2] > 0.5f) {
    rc->u6 = clh_file_color_code(a.x);
    rc->v6 = clh_file_color_code(a.y);
    const float b = clh_unorm_value(clh_file_color_code(a.z), 6u);
    for (uint i = 0; i < CLH_X_CAP; ++i) T[i].w = b;
    span->next_t.w = b;
  }
  if (g->look[3] > 0.0f) rc->width_px1 = rc->fy * a.w * g->look[3];
  if (g->look[3] < 0.0f) rc->width_px1 = rc->fy * g->strand_width * fmax(-a.w, 0.0f);
}

/* Draws strand `index` (when it exists). Uniform per group. */
static inline void clh_x_draw(sg_ctx* sg, clh_raster_ctx* rc, __global const ClhGroomGpu* g,
                              const clh_x_tables* tb, __global const ClhLodRecord* lod_g,
                              __global const uint* offsets_g, __global const float* scene_depth_g,
                              __global ulong* gbuf_g, __global uint* stats_g, uint index) {
  clh_x_job job;
  if (!clh_x_find_job(g, tb, lod_g, offsets_g, index, &job)) return;
#if CLH_RASTER_CURVE
  if (!clh_raster_curve_wanted(rc, job.id)) return; /* uniform per group */
#endif
#if CLH_POINT_ID || CLH_RASTER_POINTS
  /* drawn point j of the strand is point first + j (j < M <= n: within its stored points);
   * child c of a guide numbers its points after c copies of the stored ones, as export does */
  rc->point_base = job.child * tb->point_count + job.first;
#endif
#if CLH_RASTER_POINTS
  if (!clh_points_any(rc, rc->point_base, job.M)) return; /* uniform per group */
#endif
  float u, v;
  if (tb->has_uv != 0u) {
    const uint packed = tb->uv[job.strand];
    u = (float)(packed & 0xFFFFu) / 65535.0f;
    v = (float)(packed >> 16) / 65535.0f;
  } else {
    const uint h = clh_hash2(g->seed, job.id);
    u = clh_u01(h);
    v = clh_u01(clh_hash(h));
  }
  rc->u6 = clh_unorm_bits(u, 6u);
  rc->v6 = clh_unorm_bits(v, 6u);
  rc->coverage = job.coverage;
  for (uint base = 0u; base + 1u < job.M; base += (uint)CLH_X_ROUND) {
    float4 P[CLH_X_CAP], T[CLH_X_CAP];
    clh_x_span span;
    clh_x_round(sg, tb, &job, base, P, T, &span);
    if (g->look[2] > 0.5f || g->look[3] != 0.0f) clh_x_file_look(rc, g, tb, &job, &span, T);
    clh_raster_identity(rc, job.id, (float)span.base, 1.0f / (float)(job.M - 1u));
#if CLH_RASTER_POINTS
    clh_points_lane(rc, g, P, T, span.first, span.count);
#else
    clh_raster_lane(rc, scene_depth_g, gbuf_g, stats_g, g, P, T, span.first, span.count,
                    span.points, span.next_p, span.next_t);
#endif
  }
#if CLH_RASTER_POINTS
  (void)scene_depth_g;
  (void)gbuf_g;
  (void)stats_g;
#endif
}

#define CLH_X_PARAMS                                                                         \
  __global const ClhGroomGpu *groom_g, __global const ClhViewGpu *view_g,                    \
      __global const float4 *points_g, __global const uint *strand_offsets_g,                \
      __global const uint *uv_g, __global const uint4 *chunks_g,                             \
      __global const ClhLodRecord *lod_g, __global const uint *offsets_g, uint strand_count, \
      uint point_count, uint has_uv, __global const ClhChildrenGpu *kids_g,                  \
      __global const uint *nbr_g

#define CLH_X_TABLES(tb)                \
  clh_x_tables tb;                      \
  tb.points = points_g;                 \
  tb.strand_offsets = strand_offsets_g; \
  tb.uv = uv_g;                         \
  tb.chunks = chunks_g;                 \
  tb.kids = kids_g;                     \
  tb.nbr = nbr_g;                       \
  tb.strand_count = strand_count;       \
  tb.point_count = point_count;         \
  tb.has_uv = has_uv

#if CLH_RASTER_MOTION
/* The motion pass of per-frame strand files (-DCLH_RASTER_MOTION=1), after
 * strands_explicit_raster over the same LOD records, scene depth and finished G-buffer:
 * prev_points_g holds the previous frame's points in this frame's strand order and layout
 * (point_count entries), so each round is assembled twice, and every fragment whose word
 * is the one the pixel's depth comes from (ClhMotionGpu::depth_layers) writes the screen
 * motion between the two to motion_g (raster.h, clh_raster_lane_motion). One strand per
 * work-group. */
__kernel SG_KERNEL_ATTRS void strands_explicit_motion(CLH_X_PARAMS,
                                                      __global const float* scene_depth_g,
                                                      __global ulong* gbuf_g,
                                                      __global const float4* prev_points_g,
                                                      __global const ClhMotionGpu* motion_params_g,
                                                      __global ulong* motion_g, uint strand_base) {
  SG_DECLARE(sg);
  CLH_X_TABLES(tb);
  clh_x_tables tbp = tb;
  tbp.points = prev_points_g;
  clh_raster_ctx rc;
  clh_raster_setup(&rc, groom_g, view_g);
  rc.motion_g = motion_g;
  clh_x_job job, pjob;
  if (!clh_x_find_job(groom_g, &tb, lod_g, offsets_g, sg_strand_index(strand_base), &job)) return;
  /* the same strand in the previous frame: children grown from the previous guides */
  if (!clh_x_find_job(groom_g, &tbp, lod_g, offsets_g, sg_strand_index(strand_base), &pjob)) return;
  float u, v;
  if (tb.has_uv != 0u) {
    const uint packed = tb.uv[job.strand];
    u = (float)(packed & 0xFFFFu) / 65535.0f;
    v = (float)(packed >> 16) / 65535.0f;
  } else {
    const uint h = clh_hash2(groom_g->seed, job.id);
    u = clh_u01(h);
    v = clh_u01(clh_hash(h));
  }
  rc.u6 = clh_unorm_bits(u, 6u);
  rc.v6 = clh_unorm_bits(v, 6u);
  rc.coverage = job.coverage;
  for (uint base = 0u; base + 1u < job.M; base += (uint)CLH_X_ROUND) {
    float4 P[CLH_X_CAP], T[CLH_X_CAP], PP[CLH_X_CAP], TP[CLH_X_CAP];
    clh_x_span span, prev_span;
    clh_x_round(&sg, &tb, &job, base, P, T, &span);
    clh_x_round(&sg, &tbp, &pjob, base, PP, TP, &prev_span);
    if (groom_g->look[2] > 0.5f || groom_g->look[3] != 0.0f)
      clh_x_file_look(&rc, groom_g, &tb, &job, &span, T);
    clh_raster_lane_motion(&rc, scene_depth_g, gbuf_g, groom_g, motion_params_g, P, T, PP,
                           span.first, span.count, span.points, span.next_p, span.next_t,
                           prev_span.next_p);
  }
}
#elif !CLH_RASTER_OPACITY
/* One strand per work-group: strand_base + group (read-back and over-launch sizing). */
#if CLH_RASTER_CURVE
#define CLH_X_CURVE_PARAMS , __global const uint *link_flags_g, uint link_words
#elif CLH_RASTER_POINTS
#define CLH_X_CURVE_PARAMS                                                                     \
  , __global const uint *point_bits_g, __global const uint *point_offsets_g, uint point_words, \
      __global ClhPointGpu *point_records_g, uint point_capacity
#else
#define CLH_X_CURVE_PARAMS
#endif
#if CLH_HAS_ENTRY(CLH_ENTRY_RASTER)
__kernel SG_KERNEL_ATTRS void strands_explicit_raster(CLH_X_PARAMS,
                                                      __global const float* scene_depth_g,
                                                      __global ulong* gbuf_g,
                                                      __global uint* stats_g,
                                                      uint strand_base CLH_X_CURVE_PARAMS) {
  SG_DECLARE(sg);
  CLH_X_TABLES(tb);
  clh_raster_ctx rc;
  clh_raster_setup(&rc, groom_g, view_g);
#if CLH_RASTER_CURVE
  rc.link_flags_g = link_flags_g;
  rc.link_words = link_words;
#elif CLH_RASTER_POINTS
  clh_points_setup(&rc, point_bits_g, point_offsets_g, point_words, point_records_g,
                   point_capacity);
#endif
  clh_x_draw(&sg, &rc, groom_g, &tb, lod_g, offsets_g, scene_depth_g, gbuf_g, stats_g,
             sg_strand_index(strand_base));
}
#endif

#if CLH_HAS_ENTRY(CLH_ENTRY_RASTER_PERSISTENT)
/* Persistent grid: group g draws strands g, g + stride, g + 2 stride, ... below the total. */
__kernel SG_KERNEL_ATTRS void strands_explicit_raster_persistent(
    CLH_X_PARAMS, __global const float* scene_depth_g, __global ulong* gbuf_g,
    __global uint* stats_g, uint strand_stride) {
  SG_DECLARE(sg);
  CLH_X_TABLES(tb);
  clh_raster_ctx rc;
  clh_raster_setup(&rc, groom_g, view_g);
#if CLH_RASTER_CURVE
  rc.link_flags_g = 0; /* the curve pass uses strands_explicit_raster */
  rc.link_words = 0u;
#elif CLH_RASTER_POINTS
  clh_points_setup(&rc, 0, 0, 0u, 0, 0u); /* the point pass uses strands_explicit_raster */
#endif
  const uint total = clh_lod_drawn_total(offsets_g, groom_g->bundle_count);
  for (uint index = sg_strand_index(0u); index < total;
       index += SG_STRAND_STRIDE(max(strand_stride, 1u)))
    clh_x_draw(&sg, &rc, groom_g, &tb, lod_g, offsets_g, scene_depth_g, gbuf_g, stats_g, index);
}
#endif

#if CLH_HAS_ENTRY(CLH_ENTRY_EXPORT)
/* Writes the drawn strands: strand s's drawn points and tangents (w: styling w / AO) at
 * out_points_g/out_tangents_g[offsets[s] + j], its drawn point count at out_counts_g[s];
 * child c of guide s at [c point_count + offsets[s] + j] and count [s + c strand_count]. */
__kernel SG_KERNEL_ATTRS void strands_explicit_export(CLH_X_PARAMS, __global float4* out_points_g,
                                                      __global float4* out_tangents_g,
                                                      __global uint* out_counts_g,
                                                      uint strand_base) {
  SG_DECLARE(sg);
  CLH_X_TABLES(tb);
  (void)view_g;
  clh_x_job job;
  if (!clh_x_find_job(groom_g, &tb, lod_g, offsets_g, sg_strand_index(strand_base), &job)) return;
  for (uint base = 0u; base + 1u < job.M; base += (uint)CLH_X_ROUND) {
    float4 P[CLH_X_CAP], T[CLH_X_CAP];
    clh_x_span span;
    clh_x_round(&sg, &tb, &job, base, P, T, &span);
    /* child c of a guide writes after c copies of the stored points */
    const ulong at = (ulong)job.child * (ulong)tb.point_count + (ulong)job.first;
    for (uint i = 0; i < CLH_X_CAP; ++i) {
      uint j = span.base + span.first + i;
      if (i < span.count && j < job.n) {
        out_points_g[at + j] = P[i];
        out_tangents_g[at + j] = T[i];
      }
    }
  }
  if (sg_lane() == 0u) out_counts_g[job.id] = job.M;
}
#endif
#else
/* Deep-opacity layers of one light (built with -DCLH_RASTER_OPACITY=1), like strands_opacity. */
__kernel SG_KERNEL_ATTRS void strands_explicit_opacity(CLH_X_PARAMS,
                                                       __global const float* opaque_depth_g,
                                                       __global const ClhShadowGpu* shadow_g,
                                                       __global const float* hair_depth_g,
                                                       __global uint* opacity_g, uint strand_base) {
  SG_DECLARE(sg);
  CLH_X_TABLES(tb);
  clh_raster_ctx rc;
  clh_raster_setup(&rc, groom_g, view_g);
  clh_raster_opacity_setup(&rc, shadow_g, hair_depth_g);
  clh_x_draw(&sg, &rc, groom_g, &tb, lod_g, offsets_g, opaque_depth_g + shadow_g->offset,
             (__global ulong*)opacity_g, 0, sg_strand_index(strand_base));
}
#endif
