/* raster_core.h — drawing one strand segment into the visibility layers, written once in
 * the common subset of C++17 and OpenCL C (like gpu_types.h) so the strand kernels and the
 * benchmark's CPU floor (host/groom/cpu_raster.cpp) run the same instructions and can be
 * compared word for word.
 *
 * A segment (view-space endpoints with world tangents, styling w and AO) is walked along
 * its major axis one column (x-major) or row (y-major) at a time:
 *   - the conservative layer (index CLH_MSAA) receives every pixel the segment touches;
 *   - sample layer s receives the pixel when sample position s lies within half the hit
 *     diameter of the segment (CLH_MSAA = 1: the pixel center; 2/4/8: the Direct3D
 *     standard patterns), and a sample belongs to the segment when its major coordinate
 *     lies in [start, end), so consecutive segments never hit a sample twice. Every
 *     sample hit also marks the conservative layer, which therefore contains all samples.
 * The hit diameter is the strand's projected width at the segment's middle, at least the
 * groom's minimum, widened by the LOD compensation and capped at CLH_MAX_HIT_DIAMETER.
 * Writes are 64-bit atomic minima of the G-buffer word after a depth test against the
 * scene depth, skipped when a plain load shows they cannot lower the word. With
 * CLH_RASTER_OPACITY (device only) the conservative pixels add the strand's area in them
 * (width times the length of its path through the texel) to the deep-opacity layer of
 * their depth instead (Yuksel & Keyser 2008).
 *
 * With CLH_RASTER_COVER (device only, MSAA 1) the segment is a trapezoid of the strand's
 * true projected width at each end (no minimum hit diameter; widened for LOD, capped at
 * CLH_MAX_HIT_DIAMETER): every pixel it overlaps gets the exact overlap area as coverage,
 * and, in front of the scene depth, its word (at the point of the segment nearest the
 * pixel centre) enters the three depth-ordered layers by chained atom_min and its coverage
 * x 1024 is added to the coverage plane (clhair/coverage.h has the layout).
 *
 * With CLH_STRAND_ID every centre-sample write (MSAA 1) is followed by one of the strand
 * identity word (gpu_types.h) into layer CLH_MSAA + 1, with its own atom_min; off, the walk
 * is the same instructions as before. With CLH_POINT_ID (device only, any MSAA; per-point
 * shading) every sample write of layer s is followed by one of the sample identity word
 * (the segment's first point and the sample's place between its two points, gpu_types.h)
 * into layer CLH_MSAA + 1 + s. With CLH_RASTER_POINTS (device only) nothing is drawn: the
 * strand kernels' point pass writes the shading inputs of the points marked visible
 * (raster.h, clh_points_lane). With CLH_RASTER_CURVE (device only, hair linking)
 * the segment leaves only its centre line, one pixel per column (the pixel holding the line
 * at the column's centre), as G-buffer word and identity in layers CLH_LAYER_CURVE and
 * CLH_LAYER_CURVE_ID.
 *
 * Speed (DESIGN.md, "Vectorizable kernels"): scalar arithmetic only, no vector types and no
 * library calls besides floor/ceil/sqrt; one G-buffer word per column, evaluated at the
 * column's centre clamped to the segment and shared by the conservative pixels and the
 * centre sample (MSAA 1); the tangent is octahedral-encoded without normalising it (the
 * encoding divides by its L1 norm anyway), and only the attributes that need it are
 * divided by the interpolated 1/z. Float contraction is off so every compiler rounds the
 * same way.
 */
#ifndef CLHAIR_RASTER_CORE_H
#define CLHAIR_RASTER_CORE_H

#include "clhair/coverage.h"
#include "clhair/gpu_types.h"

#ifdef CLH_DEVICE_CODE
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_int64_extended_atomics : enable
#define CLH_GLOBAL __global
#else
#define CLH_GLOBAL
namespace clhair {
namespace gpu {
#endif

#ifndef CLH_ATOMIC_LOAD_SKIP
#define CLH_ATOMIC_LOAD_SKIP 1 /* plain load before the atomic (DESIGN.md, Atomics) */
#endif
#ifndef CLH_MSAA
#define CLH_MSAA 1
#endif
#ifndef CLH_RASTER_STATS
#define CLH_RASTER_STATS 0 /* count writes and atomics (benchmark only) */
#endif
#ifndef CLH_RASTER_OPACITY
#define CLH_RASTER_OPACITY 0 /* 1: build deep-opacity layers instead of the G-buffer */
#endif
#ifndef CLH_RASTER_MOTION
#define CLH_RASTER_MOTION 0 /* 1: resolve the motion of the words already drawn */
#endif
#ifndef CLH_STRAND_ID
#define CLH_STRAND_ID 0 /* 1: write the identity layer next to the centre layer */
#endif
#ifndef CLH_RASTER_CURVE
#define CLH_RASTER_CURVE 0 /* 1: draw the centre lines of hair linking's source strands */
#endif
#ifndef CLH_RASTER_COVER
#define CLH_RASTER_COVER 0 /* 1: coverage mode, trapezoids into three layers + coverage */
#endif
#ifndef CLH_POINT_ID
#define CLH_POINT_ID 0 /* 1: write the sample identity layers (per-point shading) */
#endif
#ifndef CLH_RASTER_POINTS
#define CLH_RASTER_POINTS 0 /* 1: the point pass: write the marked points' shading inputs */
#endif
#if CLH_RASTER_POINTS &&                                                               \
    (!defined(CLH_DEVICE_CODE) || CLH_POINT_ID || CLH_STRAND_ID || CLH_RASTER_CURVE || \
     CLH_RASTER_COVER || CLH_RASTER_OPACITY || CLH_RASTER_MOTION)
#error "the point pass exists on the device only, on its own"
#endif
#if CLH_POINT_ID && (!defined(CLH_DEVICE_CODE) || CLH_STRAND_ID || CLH_RASTER_CURVE || \
                     CLH_RASTER_COVER || CLH_RASTER_OPACITY || CLH_RASTER_MOTION)
#error "the sample identity layers exist on the device only, in the plain raster"
#endif
/* The entry points of the strand programs (strands.cl, strands_explicit.cl). A build with
 * -DCLH_ENTRY=<one of these> holds that kernel alone: drivers that compile every kernel of a
 * program when it is built or its binary is read back (PoCL compiles each kernel for any
 * local size then) compile only the one the host runs. Without CLH_ENTRY a build holds
 * every kernel of its pass. */
#define CLH_ENTRY_ALL 0
#define CLH_ENTRY_RASTER 1
#define CLH_ENTRY_RASTER_VIEWS 2
#define CLH_ENTRY_RASTER_PERSISTENT 3
#define CLH_ENTRY_EXPORT 4
#define CLH_ENTRY_STORE 5
#define CLH_ENTRY_RASTER_STORED 6
#ifndef CLH_ENTRY
#define CLH_ENTRY CLH_ENTRY_ALL
#endif
#define CLH_HAS_ENTRY(e) (CLH_ENTRY == CLH_ENTRY_ALL || CLH_ENTRY == (e))
#if CLH_RASTER_COVER && (!defined(CLH_DEVICE_CODE) || CLH_MSAA != 1 || CLH_RASTER_OPACITY || \
                         CLH_RASTER_MOTION || CLH_RASTER_CURVE || CLH_STRAND_ID)
#error "the coverage mode exists on the device only, at MSAA 1, without the other passes"
#endif
#if CLH_RASTER_CURVE && !defined(CLH_DEVICE_CODE)
#error "the curve pass exists on the device only"
#endif
#if CLH_RASTER_OPACITY && !defined(CLH_DEVICE_CODE)
#error "the opacity pass exists on the device only"
#endif
#if CLH_RASTER_MOTION && (!defined(CLH_DEVICE_CODE) || CLH_RASTER_OPACITY || CLH_RASTER_STATS)
#error "the motion pass exists on the device only, without opacity or statistics"
#endif

/* One end of a segment: view-space position, world tangent (any length), AO, styling w,
 * and its projection (clh_raster_project, once per vertex: a vertex ends one segment and
 * starts the next). */
typedef struct {
  float x, y, z;
  float tx, ty, tz;
  float ao, w;
  float iz, sx, sy; /* 1 / z and the screen position, when z >= near */
  float u;          /* position along the strand in [0, 1] (the identity word) */
#if CLH_POINT_ID
  float k; /* index of the point among the strand's drawn points (fractional where clipped) */
#endif
#if CLH_RASTER_MOTION
  float mx, my; /* screen motion to the previous frame, pixels (y down) */
#endif
} ClhRasterVertex;

/* Per-view (and per-strand: coverage, u6, v6) raster constants. */
typedef struct {
  float fx, fy, cx, cy;
  clh_i32 width, height;
  float near_z;
  float depth_near, depth_far;
  /* CLH_DEPTH_MAX_CODE / (depth_far - depth_near): one division less per column */
  float depth_scale;
  float width_px1;    /* strand diameter in pixels at view depth 1 */
  float min_diameter; /* smallest hit diameter, pixels */
  float coverage;     /* LOD compensation N / N_LOD */
  clh_u32 u6, v6;
  clh_u64 plane;         /* words per G-buffer layer */
  clh_u64 id_strand;     /* the strand's identity bits (strand << 16), CLH_STRAND_ID */
  float u_base, u_scale; /* vertex k of a lane's run lies at u = (u_base + k) * u_scale */
#if CLH_POINT_ID || CLH_RASTER_POINTS
  clh_u32 point_base; /* the strand's first point in the groom's point space */
#endif
#if CLH_RASTER_POINTS
  __global const clh_u32* point_bits_g;    /* marked points, one bit each */
  __global const clh_u32* point_offsets_g; /* marked points before each bitmap word */
  __global ClhPointGpu* points_g;          /* the marked points' shading inputs, by slot */
  clh_u32 point_words;                     /* words of the bitmap */
  clh_u32 point_capacity;                  /* records points_g holds */
#endif
#if CLH_RASTER_CURVE
  __global const clh_u32* link_flags_g; /* source strands of hair linking, one bit each */
  clh_u32 link_words;
#endif
#if CLH_RASTER_OPACITY
  __global const float* hair_depth_g; /* z0 per texel, at dom_offset */
  clh_u64 dom_offset;
  float bound[CLH_DOM_LAYERS];
#endif
#if CLH_RASTER_MOTION
  __global clh_u64* motion_g; /* per pixel: the winning word's motion, packed */
  clh_u32 motion_layers;      /* the layers the pixel's depth comes from (ClhMotionGpu) */
#endif
} clh_raster_ctx;

/* The raster constants of one view and groom (coverage 1, u and v 0 until a strand sets
 * them). */
CLH_FN void clh_raster_init(clh_raster_ctx* rc, float fx, float fy, float cx, float cy,
                            clh_u32 width, clh_u32 height, float depth_near, float depth_far,
                            float strand_width, float hit_diameter_px) {
  rc->fx = fx;
  rc->fy = fy;
  rc->cx = cx;
  rc->cy = cy;
  rc->width = (clh_i32)width;
  rc->height = (clh_i32)height;
  rc->plane = (clh_u64)width * (clh_u64)height;
  rc->near_z = 1e-4f;
  rc->depth_near = depth_near;
  rc->depth_far = depth_far;
  rc->depth_scale = (float)CLH_DEPTH_MAX_CODE / (depth_far - depth_near);
  rc->width_px1 = fy * strand_width;
  rc->min_diameter = hit_diameter_px;
  rc->coverage = 1.0f;
  rc->u6 = 0u;
  rc->v6 = 0u;
  rc->id_strand = 0u;
  rc->u_base = 0.0f;
  rc->u_scale = 0.0f;
}

/* Sets the strand's identity (gpu_types.h) and how its vertices map to u. */
CLH_FN void clh_raster_identity(clh_raster_ctx* rc, clh_u32 strand, float u_base, float u_scale) {
  rc->id_strand = (clh_u64)(strand < CLH_ID_MAX_STRAND ? strand : CLH_ID_MAX_STRAND) << 16;
  rc->u_base = u_base;
  rc->u_scale = u_scale;
}

/* Sample positions within the pixel (Direct3D 2x/4x/8x patterns, y down). */
#if CLH_MSAA == 1
#define CLH_SAMPLE_X(s) 0.5f
#define CLH_SAMPLE_Y(s) 0.5f
#elif defined(CLH_DEVICE_CODE)
#if CLH_MSAA == 2
__constant float clh_samples_xy[4] = {0.75f, 0.75f, 0.25f, 0.25f};
#elif CLH_MSAA == 4
__constant float clh_samples_xy[8] = {0.375f, 0.125f, 0.875f, 0.375f,
                                      0.125f, 0.625f, 0.625f, 0.875f};
#elif CLH_MSAA == 8
__constant float clh_samples_xy[16] = {0.5625f, 0.3125f, 0.4375f, 0.6875f, 0.8125f, 0.5625f,
                                       0.3125f, 0.1875f, 0.1875f, 0.8125f, 0.0625f, 0.4375f,
                                       0.6875f, 0.9375f, 0.9375f, 0.0625f};
#else
#error "CLH_MSAA must be 1, 2, 4 or 8"
#endif
#define CLH_SAMPLE_X(s) clh_samples_xy[2 * (s)]
#define CLH_SAMPLE_Y(s) clh_samples_xy[2 * (s) + 1]
#else
#error "the CPU raster supports CLH_MSAA 1 only"
#endif

/* ---- the atomic write ----------------------------------------------------------------- */

/* counts (CLH_RASTER_STATS): writes, atomics, skipped by the load, segments drawn */
CLH_FN void clh_gbuf_write(CLH_GLOBAL clh_u64* gbuf, clh_u32* counts, clh_u64 at, clh_u64 word) {
#if CLH_RASTER_STATS
  counts[0] += 1u;
#else
  (void)counts;
#endif
#if CLH_ATOMIC_LOAD_SKIP
#ifdef CLH_DEVICE_CODE
  const clh_u64 seen = gbuf[at];
#else
  const clh_u64 seen = __atomic_load_n(gbuf + at, __ATOMIC_RELAXED);
#endif
  if (word >= seen) {
#if CLH_RASTER_STATS
    counts[2] += 1u;
#endif
    return;
  }
#endif
#if CLH_RASTER_STATS
  counts[1] += 1u;
#endif
#ifdef CLH_DEVICE_CODE
  atom_min(gbuf + at, word);
#else
  clh_u64 cur = __atomic_load_n(gbuf + at, __ATOMIC_RELAXED);
  while (word < cur && !__atomic_compare_exchange_n(gbuf + at, &cur, word, true, __ATOMIC_RELAXED,
                                                    __ATOMIC_RELAXED)) {
  }
#endif
}

/* The pixel step of the walk: the segment's word at this column is `word` once computed
 * (*have set), with depth code `dcode` and view depth z known before it. Loads the current
 * word first: when it holds a strictly nearer depth the candidate cannot lower it, so
 * neither the scene depth nor the candidate's full word is needed (in dense hair most
 * pixels end here). Otherwise the scene depth test, the word (computed once per column)
 * and the atomic. The final word per pixel is the minimum over the candidates that pass
 * the scene depth test, whatever the order, as without the early test. */
typedef struct {
  float t;       /* screen parameter of the column's word */
  float u;       /* position along the strand there (CLH_STRAND_ID) */
  float z;       /* its view depth */
  clh_u32 dcode; /* its depth code */
  int have;      /* word computed */
  clh_u64 word;
} clh_col_word;

#if CLH_RASTER_OPACITY
/* Adds a strand's coverage of texel idx to the opacity layer its depth past z0 falls in
 * (Yuksel & Keyser 2008); hair beyond the last layer adds to the last one. */
static inline void clh_opacity_add(const clh_raster_ctx* rc, __global uint* opacity_g, clh_u64 idx,
                                   float z, float weight) {
  const float z0 = rc->hair_depth_g[rc->dom_offset + idx];
  const float d = z - z0;
  int k = CLH_DOM_LAYERS - 1;
  for (int j = CLH_DOM_LAYERS - 1; j >= 0; --j)
    if (d < rc->bound[j]) k = j;
  const uint add = (uint)(weight * CLH_DOM_FIXED + 0.5f);
  if (add > 0u)
    atomic_add(opacity_g + rc->dom_offset * CLH_DOM_LAYERS + (clh_u64)k * rc->plane + idx, add);
}
#endif

/* ---- the segment ---------------------------------------------------------------------- */

/* A segment ready to walk: major/minor screen coordinates of its ends (ma <= mb), 1/z and
 * the attributes divided by z at both ends. */
typedef struct {
  float ma, na, iza, izb;
  float ta[3], tb[3]; /* tangents / z */
  float aoa, aob, wa, wb;
  float ua, ub; /* position along the strand at the ends */
#if CLH_POINT_ID
  float ka, kb; /* point index at the ends */
#endif
  float inv_span; /* 1 / (mb - ma) */
  float span;
#if CLH_RASTER_MOTION
  float mxa, mya, mxb, myb; /* screen motion at both ends */
#endif
} clh_seg;

CLH_FN float clh_lerpf(float a, float b, float t) { return a + (b - a) * t; }

/* floor and ceiling to int for |x| < 2^30, without a library call */
CLH_FN clh_i32 clh_floor_i(float x) {
  const clh_i32 i = (clh_i32)x;
  return i - ((float)i > x ? 1 : 0);
}
CLH_FN clh_i32 clh_ceil_i(float x) { return -clh_floor_i(-x); }

/* Projects v (view space) to the screen; vertices behind the near plane are clipped by
 * the segment that uses them. */
CLH_FN void clh_raster_project(const clh_raster_ctx* rc, ClhRasterVertex* v) {
  v->iz = v->z >= rc->near_z ? 1.0f / v->z : 0.0f;
  v->sx = rc->cx + rc->fx * v->x * v->iz;
  v->sy = rc->cy - rc->fy * v->y * v->iz;
}

/* The depth code of view depth z (the mapping of clh_depth_encode with its division by
 * the range folded into depth_scale). */
CLH_FN clh_u32 clh_raster_depth_code(const clh_raster_ctx* rc, float z) {
  const float c = (z - rc->depth_near) * rc->depth_scale + 0.5f;
  return c >= (float)CLH_DEPTH_MAX_CODE ? CLH_DEPTH_MAX_CODE : (c > 0.0f ? (clh_u32)c : 0u);
}

/* The G-buffer word at screen parameter t of the segment (perspective-correct attributes);
 * its view depth through *z. */
CLH_FN clh_u64 clh_segment_word(const clh_raster_ctx* rc, const clh_seg* s, float t, float* z) {
  const float iz = clh_lerpf(s->iza, s->izb, t);
  const float zz = 1.0f / iz;
  *z = zz;
  /* the tangent's length does not matter to the octahedral code: no division by iz */
  const float tx = clh_lerpf(s->ta[0], s->tb[0], t);
  const float ty = clh_lerpf(s->ta[1], s->tb[1], t);
  const float tz = clh_lerpf(s->ta[2], s->tb[2], t);
  const float l1 = fabs(tx) + fabs(ty) + fabs(tz);
  const clh_u32 oct =
      (l1 > 1e-30f && l1 < 1e30f) ? clh_oct_encode(tx, ty, tz) : clh_oct_encode(0.0f, 1.0f, 0.0f);
  const float w = clh_lerpf(s->wa, s->wb, t) * zz;
  const float ao = clh_lerpf(s->aoa, s->aob, t) * zz;
  return clh_gbuf_pack(clh_raster_depth_code(rc, zz), oct, rc->u6, rc->v6, clh_unorm_bits(w, 6u),
                       clh_unorm_bits(ao, 6u));
}

CLH_FN void clh_col_init(const clh_raster_ctx* rc, const clh_seg* s, float t, clh_col_word* c) {
  c->t = t;
  c->z = 1.0f / clh_lerpf(s->iza, s->izb, t);
  c->dcode = clh_raster_depth_code(rc, c->z);
  c->have = 0;
  c->word = 0;
#if CLH_STRAND_ID || CLH_RASTER_CURVE
  c->u = clh_lerpf(s->ua, s->ub, t);
#else
  c->u = 0.0f;
#endif
}

/* The identity word of the column's strand (gpu_types.h). */
CLH_FN clh_u64 clh_col_id(const clh_raster_ctx* rc, const clh_col_word* c) {
  return ((clh_u64)c->dcode << 40) | rc->id_strand | ((clh_u64)clh_id_pos_code(c->u) << 1);
}

#if CLH_POINT_ID
/* The sample identity word of a fragment at screen parameter c->t of segment s
 * (gpu_types.h): the segment's first point and the fraction of the way to the second, the
 * point index interpolated perspective-correctly (like the word's attributes). */
CLH_FN clh_u64 clh_col_point_id(const clh_raster_ctx* rc, const clh_seg* s, const clh_col_word* c) {
  const float k = clh_lerpf(s->ka * s->iza, s->kb * s->izb, c->t) * c->z;
  const float k0 = floor(s->ka < s->kb ? s->ka : s->kb);
  float f = k - k0;
  f = f < 0.0f ? 0.0f : (f > 1.0f ? 1.0f : f);
  return clh_pt_pack(c->dcode, rc->point_base + (clh_u32)k0,
                     (clh_u32)(f * (float)CLH_PT_T_MAX + 0.5f));
}
#endif

CLH_FN void clh_col_write(const clh_raster_ctx* rc, const clh_seg* s,
                          CLH_GLOBAL const float* scene_depth, CLH_GLOBAL clh_u64* gbuf,
                          clh_u32* counts, clh_u64 layer_at, clh_u64 idx, clh_col_word* c) {
#if CLH_RASTER_MOTION
  /* The motion pass draws the same fragments again over the finished G-buffer. The pixel's
   * depth is the nearest word of its first motion_layers layers (composite.cl: the centre
   * sample with Huang's filter, where hair linking has put the linked strand's curve word
   * into it, or without a filter; the centre and conservative layers with Lipp's). The
   * fragment whose word is that word, in whichever layer it is drawn (a linked pixel's word
   * is the one its strand draws there into the conservative layer), gives the pixel its
   * motion, so motion and depth describe one fragment. Equal words from different
   * fragments resolve by atom_min over the packed motion, so the result does not depend on
   * the order either. */
  (void)counts;
  (void)layer_at;
  clh_u64 target = CLH_GBUF_EMPTY;
  for (clh_u32 k = 0u; k < rc->motion_layers; ++k) {
    const clh_u64 w = gbuf[(clh_u64)k * rc->plane + idx];
    target = w < target ? w : target;
  }
  if ((clh_u32)(target >> 40) < c->dcode || !(c->z < scene_depth[idx])) return;
  if (!c->have) {
    float z;
    c->word = clh_segment_word(rc, s, c->t, &z);
    c->have = 1;
  }
  if (c->word != target) return;
  const float mx = clh_lerpf(s->mxa, s->mxb, c->t), my = clh_lerpf(s->mya, s->myb, c->t);
  atom_min(rc->motion_g + idx, ((clh_u64)as_uint(mx) << 32) | (clh_u64)as_uint(my));
#else
#if CLH_ATOMIC_LOAD_SKIP
#ifdef CLH_DEVICE_CODE
  const clh_u64 seen = gbuf[layer_at + idx];
#else
  const clh_u64 seen = __atomic_load_n(gbuf + layer_at + idx, __ATOMIC_RELAXED);
#endif
  if ((clh_u32)(seen >> 40) < c->dcode) { /* something strictly nearer is there already */
#if CLH_RASTER_STATS
    if (c->z < scene_depth[idx]) {
      counts[0] += 1u;
      counts[2] += 1u;
    }
#endif
    return;
  }
#endif
  if (!(c->z < scene_depth[idx])) return;
  if (!c->have) {
    float z;
    c->word = clh_segment_word(rc, s, c->t, &z);
    c->have = 1;
  }
  clh_gbuf_write(gbuf, counts, layer_at + idx, c->word);
#if CLH_POINT_ID
  /* a sample write's identity, by the same depth test (counters untouched) */
  if (layer_at < (clh_u64)CLH_MSAA * rc->plane) {
    clh_u32 none[4] = {0u, 0u, 0u, 0u};
    clh_gbuf_write(gbuf, none, (clh_u64)(CLH_MSAA + 1) * rc->plane + layer_at + idx,
                   clh_col_point_id(rc, s, c));
  }
#endif
#if CLH_STRAND_ID && CLH_MSAA == 1
  /* the identity of a centre-sample write, by the same depth test (counters untouched) */
  if (layer_at == 0u) {
    clh_u32 none[4] = {0u, 0u, 0u, 0u};
    clh_gbuf_write(gbuf, none, (clh_u64)(CLH_MSAA + 1) * rc->plane + idx, clh_col_id(rc, c));
  }
#endif
#endif /* CLH_RASTER_MOTION */
}

#if CLH_RASTER_COVER
/* Inserts `word` into the three depth-ordered layers of pixel idx: an atom_min per layer,
 * the larger of the word and the one it met moving on to the next layer, until a layer was
 * empty. Whatever the order of the insertions, each layer ends with the k-th smallest of
 * the words inserted (the words passed from layer k to k + 1 are all its words but the
 * smallest). With the load skip, a word not below the third layer's is not inserted (words
 * only decrease, so it could never enter). */
CLH_FN void clh_cover_insert(__global clh_u64* gbuf, clh_u64 plane, clh_u64 idx, clh_u64 word) {
  __global clh_u64* pixel = gbuf + idx; /* layer k of the pixel at pixel[k * plane] */
#if CLH_ATOMIC_LOAD_SKIP
  if (word >= pixel[(clh_u64)(CLH_COVER_LAYERS - 1) * plane]) return;
#endif
  for (int k = 0; k < CLH_COVER_LAYERS; ++k) {
    const clh_u64 old = atom_min(pixel + (clh_u64)k * plane, word);
    if (old == CLH_GBUF_EMPTY) return;
    word = old > word ? old : word;
  }
}

/* Adds a fragment's coverage (share of the pixel, 0..1) to the coverage plane. */
CLH_FN void clh_cover_add(__global clh_u64* gbuf, clh_u64 plane, clh_u64 idx, float coverage) {
  const clh_u32 add = (clh_u32)(coverage * CLH_COVER_FIXED + 0.5f);
  if (add > 0u)
    atomic_add((__global clh_u32*)(gbuf + (clh_u64)CLH_LAYER_COVERAGE * plane) + idx, add);
}

/* The strand's projected width at an end of 1 / z = iz, pixels (LOD widening, capped). */
CLH_FN float clh_cover_width(const clh_raster_ctx* rc, float iz) {
  const float d = rc->width_px1 * iz * rc->coverage;
  return d < CLH_MAX_HIT_DIAMETER ? d : CLH_MAX_HIT_DIAMETER;
}

/* Draws segment a-b (in front of the near plane) as a trapezoid: column by column over its
 * screen box (the trapezoid's slice of each column, then each row the slice reaches), the
 * exact overlap area per pixel. */
CLH_FN void clh_cover_segment(const clh_raster_ctx* rc, __global const float* scene_depth,
                              __global clh_u64* gbuf, clh_u32* counts, const ClhRasterVertex* a,
                              const ClhRasterVertex* b) {
  clh_poly8 q;
  if (!clh_trapezoid(a->sx, a->sy, b->sx, b->sy, clh_cover_width(rc, a->iz),
                     clh_cover_width(rc, b->iz), &q))
    return;
#if CLH_RASTER_STATS
  counts[3] += 1u;
#else
  (void)counts;
#endif
  clh_seg s; /* the attributes over z at both ends, a to b (t = 0 at a) */
  s.iza = a->iz;
  s.izb = b->iz;
  s.ta[0] = a->tx * a->iz;
  s.ta[1] = a->ty * a->iz;
  s.ta[2] = a->tz * a->iz;
  s.tb[0] = b->tx * b->iz;
  s.tb[1] = b->ty * b->iz;
  s.tb[2] = b->tz * b->iz;
  s.aoa = a->ao * a->iz;
  s.aob = b->ao * b->iz;
  s.wa = a->w * a->iz;
  s.wb = b->w * b->iz;
  const float dx = b->sx - a->sx, dy = b->sy - a->sy;
  const float inv_len2 = 1.0f / (dx * dx + dy * dy);
  float xlo = q.x[0], xhi = q.x[0], ylo = q.y[0], yhi = q.y[0];
  for (int k = 1; k < 4; ++k) {
    xlo = fmin(xlo, q.x[k]);
    xhi = fmax(xhi, q.x[k]);
    ylo = fmin(ylo, q.y[k]);
    yhi = fmax(yhi, q.y[k]);
  }
  if (!(xhi > 0.0f) || !(yhi > 0.0f) || !(xlo < (float)rc->width) || !(ylo < (float)rc->height))
    return;
  const clh_i32 i0 = xlo > 0.0f ? clh_floor_i(xlo) : 0;
  const clh_i32 i1 = xhi < (float)rc->width ? clh_ceil_i(xhi) : rc->width; /* exclusive */
  const clh_u64 width = (clh_u64)rc->width;
  for (clh_i32 i = i0; i < i1; ++i) {
    clh_poly8 col;
    clh_poly_column(&q, (float)i, &col);
    if (col.n < 3) continue;
    float clo = col.y[0], chi = col.y[0];
    for (int k = 1; k < col.n; ++k) {
      clo = fmin(clo, col.y[k]);
      chi = fmax(chi, col.y[k]);
    }
    const clh_i32 j0 = clo > 0.0f ? clh_floor_i(clo) : 0;
    const clh_i32 j1 = chi < (float)rc->height ? clh_ceil_i(chi) : rc->height;
    for (clh_i32 j = j0; j < j1; ++j) {
      const float area = clh_poly_row_area(&col, (float)j);
      if (!(area > 0.0f)) continue;
      const clh_u64 idx = (clh_u64)j * width + (clh_u64)i;
      /* the fragment: the segment's point nearest the pixel centre */
      float t = (((float)i + 0.5f - a->sx) * dx + ((float)j + 0.5f - a->sy) * dy) * inv_len2;
      t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
      const float z = 1.0f / clh_lerpf(s.iza, s.izb, t);
      if (!(z < scene_depth[idx])) continue;
#if CLH_RASTER_STATS
      counts[0] += 1u;
#endif
      float zw;
      clh_cover_insert(gbuf, rc->plane, idx, clh_segment_word(rc, &s, t, &zw));
      clh_cover_add(gbuf, rc->plane, idx, area > 1.0f ? 1.0f : area);
    }
  }
}
#endif

/* Draws the segment a-b. */
CLH_FN void clh_raster_segment(const clh_raster_ctx* rc, CLH_GLOBAL const float* scene_depth,
                               CLH_GLOBAL clh_u64* gbuf, clh_u32* counts, ClhRasterVertex a,
                               ClhRasterVertex b) {
  const float near_z = rc->near_z;
  if (a.z < near_z && b.z < near_z) return;
  if (a.z < near_z || b.z < near_z) { /* clip at the near plane */
    const float t = (near_z - a.z) / (b.z - a.z);
    ClhRasterVertex c;
    c.x = clh_lerpf(a.x, b.x, t);
    c.y = clh_lerpf(a.y, b.y, t);
    c.z = clh_lerpf(a.z, b.z, t);
    c.tx = clh_lerpf(a.tx, b.tx, t);
    c.ty = clh_lerpf(a.ty, b.ty, t);
    c.tz = clh_lerpf(a.tz, b.tz, t);
    c.ao = clh_lerpf(a.ao, b.ao, t);
    c.w = clh_lerpf(a.w, b.w, t);
    c.u = clh_lerpf(a.u, b.u, t);
#if CLH_POINT_ID
    c.k = clh_lerpf(a.k, b.k, t);
#endif
#if CLH_RASTER_MOTION
    c.mx = clh_lerpf(a.mx, b.mx, t);
    c.my = clh_lerpf(a.my, b.my, t);
#endif
    clh_raster_project(rc, &c);
    if (a.z < near_z) {
      a = c;
    } else {
      b = c;
    }
  }
#if CLH_RASTER_COVER
  clh_cover_segment(rc, scene_depth, gbuf, counts, &a, &b);
  return;
#endif
  const float iza = a.iz, izb = b.iz;
  const float xa = a.sx, ya = a.sy;
  const float xb = b.sx, yb = b.sy;
  const float dx = xb - xa, dy = yb - ya;
  const float len = sqrt(dx * dx + dy * dy);
  if (!(len > 1e-6f) || !(len < 1e7f)) return;
#if CLH_RASTER_STATS
  counts[3] += 1u;
#endif

  const bool xmajor = fabs(dx) >= fabs(dy);
  /* order the ends along the major axis */
  const float m0 = xmajor ? xa : ya, m1 = xmajor ? xb : yb;
  const bool flip = m0 > m1;
  const ClhRasterVertex lo_v = flip ? b : a, hi_v = flip ? a : b;
  clh_seg s;
  s.ma = flip ? m1 : m0;
  const float mb = flip ? m0 : m1;
  s.na = xmajor ? (flip ? yb : ya) : (flip ? xb : xa);
  const float nb = xmajor ? (flip ? ya : yb) : (flip ? xa : xb);
  s.iza = flip ? izb : iza;
  s.izb = flip ? iza : izb;
  s.ta[0] = lo_v.tx * s.iza;
  s.ta[1] = lo_v.ty * s.iza;
  s.ta[2] = lo_v.tz * s.iza;
  s.tb[0] = hi_v.tx * s.izb;
  s.tb[1] = hi_v.ty * s.izb;
  s.tb[2] = hi_v.tz * s.izb;
  s.aoa = lo_v.ao * s.iza;
  s.aob = hi_v.ao * s.izb;
  s.wa = lo_v.w * s.iza;
  s.wb = hi_v.w * s.izb;
  s.ua = lo_v.u;
  s.ub = hi_v.u;
#if CLH_POINT_ID
  s.ka = lo_v.k;
  s.kb = hi_v.k;
#endif
  s.span = mb - s.ma;
  s.inv_span = 1.0f / s.span;
#if CLH_RASTER_MOTION
  s.mxa = lo_v.mx;
  s.mya = lo_v.my;
  s.mxb = hi_v.mx;
  s.myb = hi_v.my;
#endif

  const clh_i32 major_max = xmajor ? rc->width : rc->height;
  const clh_i32 minor_max = xmajor ? rc->height : rc->width;
  const float slope = (nb - s.na) * s.inv_span;
  const float cosv = s.span / len; /* minor-axis offsets times cosv = perpendicular distance */
#if CLH_RASTER_OPACITY || CLH_RASTER_CURVE
  (void)cosv;
#endif

  /* hit radius: projected width at the segment's middle (1 / z_mid is the mean of the ends'
   * 1 / z), widened for LOD, at least the minimum */
  const float izmid = 0.5f * (iza + izb);
  float diameter = rc->width_px1 * izmid;
  diameter = diameter > rc->min_diameter ? diameter : rc->min_diameter;
  diameter *= rc->coverage;
  diameter = diameter < CLH_MAX_HIT_DIAMETER ? diameter : CLH_MAX_HIT_DIAMETER;
  const float r = 0.5f * diameter;
  const float reach = r * len * s.inv_span; /* r / cosv */
#if CLH_RASTER_OPACITY
  /* the share of a texel the strand covers, scaled for strands removed by LOD */
  const float opacity_w = fmin(rc->width_px1 * izmid, 1.0f) * rc->coverage;
#endif

  /* columns whose extent meets [ma, mb), restricted to where the band stays on screen
   * (only segments that leave the screen's band need the intersections) */
  float lo = floor(s.ma), hi = ceil(mb);
  const float band_lo = -2.0f - reach, band_hi = (float)minor_max + 2.0f + reach;
  const bool inside = s.na >= band_lo && s.na <= band_hi && nb >= band_lo && nb <= band_hi;
  if (!inside && fabs(slope) > 1e-12f) {
    const float inv_slope = 1.0f / slope;
    const float c0 = s.ma + (band_lo - s.na) * inv_slope;
    const float c1 = s.ma + (band_hi - s.na) * inv_slope;
    const float cmin = c0 < c1 ? c0 : c1, cmax = c0 < c1 ? c1 : c0;
    lo = fmax(lo, floor(cmin));
    hi = fmin(hi, ceil(cmax));
  } else if (!inside) {
    return;
  }
  const clh_i32 i0 = lo > 0.0f ? (clh_i32)lo : 0;
  const clh_i32 i1 = hi < (float)major_max ? (clh_i32)hi : major_max; /* exclusive */
  const clh_u64 width = (clh_u64)rc->width;
  for (clh_i32 i = i0; i < i1; ++i) {
    /* conservative: the rows the segment crosses within this column */
    const float e0 = (float)i > s.ma ? (float)i : s.ma;
    const float e1 = (float)i + 1.0f < mb ? (float)i + 1.0f : mb;
    if (!(e1 >= e0)) continue;
    const float n0 = s.na + (e0 - s.ma) * slope, n1 = s.na + (e1 - s.ma) * slope;
    const clh_i32 j0 = clh_floor_i(n0 < n1 ? n0 : n1), j1 = clh_floor_i(n0 < n1 ? n1 : n0);
    /* one word per column: at the column's centre, clamped to the segment */
    const float mc = (float)i + 0.5f;
    float tc = (mc - s.ma) * s.inv_span;
    tc = tc < 0.0f ? 0.0f : (tc > 1.0f ? 1.0f : tc);
    clh_col_word col;
    clh_col_init(rc, &s, tc, &col);
#if CLH_RASTER_CURVE
    /* the centre line: the pixel holding the line at the column's centre, when the centre
     * belongs to this segment (consecutive segments never share a column's centre) */
    (void)j0;
    (void)j1;
    {
      const float ms = (float)i + 0.5f;
      const float nl = s.na + (ms - s.ma) * slope;
      const clh_i32 j = clh_floor_i(nl);
      if (ms >= s.ma && ms < mb && j >= 0 && j < minor_max) {
        const clh_u64 idx =
            xmajor ? (clh_u64)j * width + (clh_u64)i : (clh_u64)i * width + (clh_u64)j;
        if (col.z < scene_depth[idx]) {
          float z;
          clh_gbuf_write(gbuf, counts, (clh_u64)CLH_LAYER_CURVE * rc->plane + idx,
                         clh_segment_word(rc, &s, col.t, &z));
          clh_gbuf_write(gbuf, counts, (clh_u64)CLH_LAYER_CURVE_ID * rc->plane + idx,
                         clh_col_id(rc, &col));
        }
      }
    }
#elif CLH_RASTER_OPACITY
    /* each texel gets the strand's area in it: its width times the length of the segment's
     * path through the texel (this column's share of the segment, split between the rows it
     * crosses), so a texel two segments share, or a segment shorter than a texel, counts the
     * strand once whatever the tessellation */
    const float nlo = n0 < n1 ? n0 : n1, nhi = n0 < n1 ? n1 : n0;
    const float path = (e1 - e0) * len * s.inv_span; /* length in this column, pixels */
    const float rise = nhi - nlo;
    const clh_i32 jc0 = j0 > 0 ? j0 : 0, jc1 = j1 < minor_max - 1 ? j1 : minor_max - 1;
    for (clh_i32 j = jc0; j <= jc1; ++j) {
      const clh_u64 idx =
          xmajor ? (clh_u64)j * width + (clh_u64)i : (clh_u64)i * width + (clh_u64)j;
      const float lo_j = fmax(nlo, (float)j), hi_j = fmin(nhi, (float)j + 1.0f);
      const float share = rise > 1e-6f ? fmax(hi_j - lo_j, 0.0f) / rise : (j == j0 ? 1.0f : 0.0f);
      if (col.z < scene_depth[idx])
        clh_opacity_add(rc, (__global uint*)gbuf, idx, col.z, fmin(opacity_w * path * share, 1.0f));
    }
#else
    const clh_u64 cons_at = (clh_u64)CLH_MSAA * rc->plane;
    if (CLH_MSAA == 1 && reach <= 1.0f && j1 - j0 <= 1) {
      /* Thin strands, MSAA 1 (the common case): a fixed-trip path without data-dependent
       * loop counts. The conservative rows are j0 and j1 (equal or adjacent: |slope| <= 1);
       * visiting j1 == j0 twice is harmless, the loaded word rejects the repeat. A pixel
       * centre within reach <= 1 of the line lies in row jA = floor(nl - 1/2) or jA + 1. */
      if (j0 >= 0 && j0 < minor_max) {
        const clh_u64 idx =
            xmajor ? (clh_u64)j0 * width + (clh_u64)i : (clh_u64)i * width + (clh_u64)j0;
        clh_col_write(rc, &s, scene_depth, gbuf, counts, cons_at, idx, &col);
      }
#if CLH_RASTER_STATS
      if (j1 != j0) /* counted once */
#endif
        if (j1 >= 0 && j1 < minor_max) {
          const clh_u64 idx =
              xmajor ? (clh_u64)j1 * width + (clh_u64)i : (clh_u64)i * width + (clh_u64)j1;
          clh_col_write(rc, &s, scene_depth, gbuf, counts, cons_at, idx, &col);
        }
      const float ms = (float)i + 0.5f;
      if (ms >= s.ma && ms < mb) {
        const float nl = s.na + (ms - s.ma) * slope;
        const clh_i32 ja = clh_floor_i(nl - 0.5f);
        for (clh_i32 j = ja; j <= ja + 1; ++j) {
          if (!(fabs((float)j + 0.5f - nl) * cosv < r) || j < 0 || j >= minor_max) continue;
          const clh_u64 idx =
              xmajor ? (clh_u64)j * width + (clh_u64)i : (clh_u64)i * width + (clh_u64)j;
          clh_col_write(rc, &s, scene_depth, gbuf, counts, 0u, idx, &col);
          if (j < j0 || j > j1)
            clh_col_write(rc, &s, scene_depth, gbuf, counts, cons_at, idx, &col);
        }
      }
      continue;
    }
    /* the general walk: wide strands (LOD compensation), MSAA samples */
    const clh_i32 jc0 = j0 > 0 ? j0 : 0, jc1 = j1 < minor_max - 1 ? j1 : minor_max - 1;
    for (clh_i32 j = jc0; j <= jc1; ++j) {
      const clh_u64 idx =
          xmajor ? (clh_u64)j * width + (clh_u64)i : (clh_u64)i * width + (clh_u64)j;
      clh_col_write(rc, &s, scene_depth, gbuf, counts, cons_at, idx, &col);
    }
    /* samples within the hit radius */
    for (int sidx = 0; sidx < CLH_MSAA; ++sidx) {
      const float om = xmajor ? CLH_SAMPLE_X(sidx) : CLH_SAMPLE_Y(sidx);
      const float on = xmajor ? CLH_SAMPLE_Y(sidx) : CLH_SAMPLE_X(sidx);
      const float ms = (float)i + om;
      if (ms < s.ma || ms >= mb) continue;
      const float nl = s.na + (ms - s.ma) * slope;
      const clh_i32 flo = clh_ceil_i(nl - reach - on), fhi = clh_floor_i(nl + reach - on);
      const clh_i32 jlo = flo > 0 ? flo : 0;
      const clh_i32 jhi = fhi < minor_max - 1 ? fhi : minor_max - 1;
      if (jlo > jhi) continue;
      clh_col_word sw = col; /* MSAA 1: the sample is the column's centre */
      if (CLH_MSAA > 1) clh_col_init(rc, &s, (ms - s.ma) * s.inv_span, &sw);
      for (clh_i32 j = jlo; j <= jhi; ++j) {
        if (!(fabs((float)j + on - nl) * cosv < r)) continue;
        const clh_u64 idx =
            xmajor ? (clh_u64)j * width + (clh_u64)i : (clh_u64)i * width + (clh_u64)j;
        clh_col_write(rc, &s, scene_depth, gbuf, counts, (clh_u64)sidx * rc->plane, idx, &sw);
        if (j < j0 || j > j1) clh_col_write(rc, &s, scene_depth, gbuf, counts, cons_at, idx, &sw);
      }
    }
#endif
  }
}

/* ---- strand geometry shared by the stored-strand kernel and the CPU floor -------------- */

/* A 3x4 row-major affine transform applied to a point / a direction. */
CLH_FN void clh_xform3(const float* m, float x, float y, float z, float w, float* out) {
  out[0] = m[0] * x + m[1] * y + m[2] * z + m[3] * w;
  out[1] = m[4] * x + m[5] * y + m[6] * z + m[7] * w;
  out[2] = m[8] * x + m[9] * y + m[10] * z + m[11] * w;
}

/* v / |v|, or the fallback when v is (nearly) zero or not finite. */
CLH_FN void clh_normalize3(float* v, const float* fallback) {
  const float l2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  if (l2 > 1e-30f && l2 < 1e30f) {
    const float inv = 1.0f / sqrt(l2);
    v[0] *= inv;
    v[1] *= inv;
    v[2] *= inv;
  } else {
    v[0] = fallback[0];
    v[1] = fallback[1];
    v[2] = fallback[2];
  }
}

/* The end tangent: the neighbour's tangent t reflected about the end segment's unit
 * direction q (Bhokare Eq. 5-6), normalised (q when degenerate); written to t. */
CLH_FN void clh_end_tangent3(const float* q, float* t) {
  const float d = t[0] * q[0] + t[1] * q[1] + t[2] * q[2];
  t[0] = 2.0f * q[0] * d - t[0];
  t[1] = 2.0f * q[1] * d - t[1];
  t[2] = 2.0f * q[2] * d - t[2];
  clh_normalize3(t, q);
}

#ifndef CLH_DEVICE_CODE
}  // namespace gpu
}  // namespace clhair
#endif

#endif /* CLHAIR_RASTER_CORE_H */
