/* strands.cl — strand assembly and rasterisation: one work-group (one logical sub-group of
 * SG_SIZE lanes) per strand.
 *
 * Inputs: the groom (ClhGroomGpu), its bundles and hair-mesh vertices, the per-bundle LOD
 * records (uint4: N_LOD, C, L bits, morph gamma bits) and their exclusive scan
 * (bundle_count + 1 entries, the last being the total), and the progressive blue-noise
 * root sets.
 *
 * Assembly (Lipp §3.1.1, Bhokare §3.3-3.6): the lanes interpolate the bundle's layers at
 * the strand's root sample into local memory (finite-difference tangents, neighbours
 * exchanged by shuffles); then each lane evaluates its own run of the C control points on
 * the Hermite base spline, styles them, and swaps its first/last points and tangents with
 * its neighbours, so every point and tangent is computed exactly once. Lane i owns points
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
 * writes points and tangents instead of drawing.
 */
#include "clhair/gpu_types.h"
#include "subgroup.h"
#include "clh_math.h"
#include "hair_style.h"

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_int64_extended_atomics : enable

#ifndef CLH_ATOMIC_LOAD_SKIP
#define CLH_ATOMIC_LOAD_SKIP 1 /* plain load before atom_min (DESIGN.md, Atomics) */
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

#define CLH_PTS_PER_LANE ((CLH_MAX_CONTROL_POINTS - 1 + SG_SIZE - 1) / SG_SIZE)
#define CLH_PTS_CAP (CLH_PTS_PER_LANE + 1)
#define CLH_LAYERS_PER_LANE ((CLH_MAX_LAYERS + SG_SIZE - 1) / SG_SIZE)

/* Standard sample positions within the pixel (Direct3D 2x/4x/8x patterns, y down). */
#if CLH_MSAA == 1
__constant float2 clh_samples[1] = {(float2)(0.5f, 0.5f)};
#elif CLH_MSAA == 2
__constant float2 clh_samples[2] = {(float2)(0.75f, 0.75f), (float2)(0.25f, 0.25f)};
#elif CLH_MSAA == 4
__constant float2 clh_samples[4] = {(float2)(0.375f, 0.125f), (float2)(0.875f, 0.375f),
                                    (float2)(0.125f, 0.625f), (float2)(0.625f, 0.875f)};
#elif CLH_MSAA == 8
__constant float2 clh_samples[8] = {(float2)(0.5625f, 0.3125f), (float2)(0.4375f, 0.6875f),
                                    (float2)(0.8125f, 0.5625f), (float2)(0.3125f, 0.1875f),
                                    (float2)(0.1875f, 0.8125f), (float2)(0.0625f, 0.4375f),
                                    (float2)(0.6875f, 0.9375f), (float2)(0.9375f, 0.0625f)};
#else
#error "CLH_MSAA must be 1, 2, 4 or 8"
#endif

/* The lane's share of the strand after assembly. */
typedef struct {
  uint C;        /* control points of the strand */
  uint first;    /* index of the lane's first point */
  uint count;    /* points the lane owns */
  float4 next_p; /* point first+count (position, styling w), from the next lane */
  float4 next_t; /* its final tangent (xyz, ambient occlusion in w) */
  float2 uv;     /* the strand's root styling coordinates */
} clh_lane_span;

/* Largest b with offsets[b] <= strand: the bundle that holds the strand. */
static inline uint clh_find_bundle(__global const uint* offsets_g, uint bundle_count, uint strand) {
  uint lo = 0u, hi = bundle_count;
  while (hi - lo > 1u) {
    uint mid = (lo + hi) >> 1;
    if (offsets_g[mid] <= strand) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return lo;
}

/* Reflects the neighbour tangent t about the end segment direction q (Bhokare Eq. 5-6). */
static inline float3 clh_end_tangent(float3 q, float3 t_neighbour) {
  return 2.0f * q * dot(t_neighbour, q) - t_neighbour;
}

#define CLH_UP ((float3)(0.0f, 1.0f, 0.0f))

/* Tangent k of the fine level from raw points in local memory (central differences, the
 * reflection rule at the ends). */
static inline float3 clh_fine_tangent(__local const float4* pts_l, uint k, uint C) {
  if (k > 0u && k + 1u < C) return clh_normalize_or(pts_l[k + 1u].xyz - pts_l[k - 1u].xyz, CLH_UP);
  if (k == 0u) {
    float3 q = clh_normalize_or(pts_l[1].xyz - pts_l[0].xyz, CLH_UP);
    float3 t1 = C > 2u ? clh_normalize_or(pts_l[2].xyz - pts_l[0].xyz, q) : q;
    return clh_normalize_or(clh_end_tangent(q, t1), q);
  }
  float3 q = clh_normalize_or(pts_l[C - 1u].xyz - pts_l[C - 2u].xyz, CLH_UP);
  float3 tm = C > 2u ? clh_normalize_or(pts_l[C - 1u].xyz - pts_l[C - 3u].xyz, q) : q;
  return clh_normalize_or(clh_end_tangent(q, tm), q);
}

/* Tangent of the coarse level (the even points) at even index e. */
static inline float3 clh_coarse_tangent(__local const float4* pts_l, uint e, uint C) {
  if (e > 0u && e + 1u < C) return clh_normalize_or(pts_l[e + 2u].xyz - pts_l[e - 2u].xyz, CLH_UP);
  if (e == 0u) {
    float3 q = clh_normalize_or(pts_l[2].xyz - pts_l[0].xyz, CLH_UP);
    float3 t1 = C > 3u ? clh_normalize_or(pts_l[4].xyz - pts_l[0].xyz, q) : q;
    return clh_normalize_or(clh_end_tangent(q, t1), q);
  }
  float3 q = clh_normalize_or(pts_l[C - 1u].xyz - pts_l[C - 3u].xyz, CLH_UP);
  float3 tm = C > 3u ? clh_normalize_or(pts_l[C - 1u].xyz - pts_l[C - 5u].xyz, q) : q;
  return clh_normalize_or(clh_end_tangent(q, tm), q);
}

/* Cooperative assembly of one strand. Every lane must call it. */
static inline void clh_assemble_strand(sg_ctx* sg, __local clh_layer_pt* layers_l,
                                       __local clh_strand* strand_l, __local float4* pts_l,
                                       __global const ClhGroomGpu* g,
                                       __global const ClhBundle* b,
                                       __global const ClhMeshVertex* verts_g,
                                       __global const float2* roots_quad_g,
                                       __global const float2* roots_tri_g, uint bundle,
                                       uint local_index, uint C, float gamma, float4* P,
                                       float4* T, clh_lane_span* span) {
  const uint lane = sg_lane();
  const uint layer_count = clamp(g->layer_count, 2u, (uint)CLH_MAX_LAYERS);
  const int4 vtx = vload4(0, b->vtx);
  const uint root = min(local_index, g->root_set_size - 1u);
  const float2 st = b->triangle ? roots_tri_g[root] : roots_quad_g[root];
  /* the strand's constants are the same for every lane: lane 0 computes them once */
  if (lane == 0u) *strand_l = clh_strand_setup(g, b, bundle, local_index, st);

  /* ---- pass 1: the strand's sample on every layer -------------------------------- */
  const uint SL = (layer_count + SG_SIZE - 1u) / SG_SIZE;
  const uint lfirst = lane * SL;
  const uint lcount = lfirst < layer_count ? min(SL, layer_count - lfirst) : 0u;
  clh_layer_pt lay[CLH_LAYERS_PER_LANE];
  for (uint i = 0; i < CLH_LAYERS_PER_LANE; ++i) {
    if (i < lcount) {
      lay[i] = clh_bundle_layer(verts_g, vtx, lfirst + i, g->vertex_count, st);
    } else {
      lay[i].pos = lay[i].tan = lay[i].du = lay[i].dv = (float4)(0.0f);
    }
  }
  const float4 lay_last = lay[lcount > 0u ? lcount - 1u : 0u].pos;
  const float4 lay_prev = sg_shuffle_up1_f4(sg, lay_last, (float4)(0.0f));
  const float4 lay_next = sg_shuffle_down1_f4(sg, lay[0].pos, (float4)(0.0f));
  for (uint i = 0; i < CLH_LAYERS_PER_LANE; ++i) {
    if (i < lcount) {
      uint l = lfirst + i;
      if (g->has_tangents == 0u) {
        float3 prev = (i > 0u ? lay[i - 1u].pos : lay_prev).xyz;
        float3 next = (i + 1u < lcount ? lay[i + 1u].pos : lay_next).xyz;
        float3 cur = lay[i].pos.xyz;
        float3 m = (l == 0u) ? next - cur : (l == layer_count - 1u) ? cur - prev
                                                                    : 0.5f * (next - prev);
        lay[i].tan.xyz = m;
      }
      layers_l[l] = lay[i];
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  const clh_strand s = *strand_l;

  /* ---- pass 2: styled control points ---------------------------------------------- */
  const uint S = (C - 1u + SG_SIZE - 1u) / SG_SIZE;
  const uint first = lane * S;
  const uint end = (lane == (uint)(SG_SIZE - 1)) ? C : min(first + S, C);
  const uint count = end > first ? min(end - first, (uint)CLH_PTS_CAP) : 0u;
  float ao[CLH_PTS_CAP];
  for (uint i = 0; i < CLH_PTS_CAP; ++i) {
    P[i] = (float4)(0.0f);
    T[i] = (float4)(0.0f);
    ao[i] = 1.0f;
    if (i < count) {
      float3 deriv, du, dv;
      float4 base = clh_base_point(layers_l, layer_count, first + i, C, s.length, &deriv, &du,
                                   &dv, &ao[i]);
      P[i] = (float4)(base.xyz + clh_style_offset(g, &s, base.w, deriv, du, dv), base.w);
    }
  }

  float4 next_p;
  if (gamma > 0.0f) {
    /* vertex-LOD transition: raw points through local memory, then the morphed positions
     * (Eq. 11-12) and tangents blended between this level and the coarser one */
    for (uint i = 0; i < CLH_PTS_CAP; ++i)
      if (i < count) pts_l[first + i] = P[i];
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint i = 0; i < CLH_PTS_CAP; ++i) {
      uint k = first + i;
      if (i < count) {
        float3 fine = clh_fine_tangent(pts_l, k, C);
        float3 coarse;
        if ((k & 1u) == 0u) {
          coarse = clh_coarse_tangent(pts_l, k, C);
        } else {
          coarse = clh_normalize_or(clh_coarse_tangent(pts_l, k - 1u, C) +
                                        clh_coarse_tangent(pts_l, k + 1u, C),
                                    fine);
          float3 mid = 0.5f * (pts_l[k - 1u].xyz + pts_l[k + 1u].xyz);
          P[i].xyz = mix(P[i].xyz, mid, gamma);
        }
        T[i] = (float4)(clh_normalize_or(mix(fine, coarse, gamma), fine), ao[i]);
      }
    }
    next_p = sg_shuffle_down1_f4(sg, P[0], (float4)(0.0f));
  } else {
    /* exchange 1: neighbour points for the finite-difference tangents */
    const float4 prev_p = sg_shuffle_up1_f4(sg, P[count > 0u ? count - 1u : 0u], (float4)(0.0f));
    next_p = sg_shuffle_down1_f4(sg, P[0], (float4)(0.0f));
    for (uint i = 0; i < CLH_PTS_CAP; ++i) {
      uint k = first + i;
      if (i < count && k > 0u && k + 1u < C) {
        float3 a = (i > 0u ? P[i - 1u] : prev_p).xyz;
        float3 c = (i + 1u < count ? P[i + 1u] : next_p).xyz;
        T[i].xyz = clh_normalize_or(c - a, CLH_UP);
      }
      T[i].w = ao[i];
    }
    /* exchange 2: interior tangents next to the end points */
    const float4 prev_t = sg_shuffle_up1_f4(sg, T[count > 0u ? count - 1u : 0u], (float4)(0.0f));
    const float4 next_t0 = sg_shuffle_down1_f4(sg, T[0], (float4)(0.0f));
    if (count > 0u && first == 0u) { /* root, Bhokare Eq. 6 */
      float3 p1 = (count > 1u ? P[1] : next_p).xyz;
      float3 q = clh_normalize_or(p1 - P[0].xyz, CLH_UP);
      float3 t1 = (C == 2u) ? q : (count > 1u ? T[1] : next_t0).xyz;
      T[0].xyz = clh_normalize_or(clh_end_tangent(q, t1), q);
    }
    if (count > 0u && C - 1u >= first && C - 1u < first + count) { /* tip, Bhokare Eq. 5 */
      uint i = C - 1u - first;
      float3 pm = (i > 0u ? P[i - 1u] : prev_p).xyz;
      float3 q = clh_normalize_or(P[i].xyz - pm, CLH_UP);
      float3 tm = (C == 2u) ? q : (i > 0u ? T[i - 1u] : prev_t).xyz;
      T[i].xyz = clh_normalize_or(clh_end_tangent(q, tm), q);
    }
  }

  /* last exchange: the next lane's first tangent, now final */
  span->next_t = sg_shuffle_down1_f4(sg, T[0], (float4)(0.0f));
  span->next_p = next_p;
  span->uv = s.uv;
  span->C = C;
  span->first = first;
  span->count = count;
}

/* ---- rasterisation ---------------------------------------------------------------- */

typedef struct {
  float fx, fy, cx, cy;
  int width, height;
  float near_z;
  float depth_near, depth_far;
  float width_px1;    /* strand diameter in pixels at view depth 1 */
  float min_diameter; /* smallest hit diameter, pixels */
  float coverage;     /* LOD compensation N / N_LOD */
  uint u6, v6;
  size_t plane;       /* words per G-buffer layer */
#if CLH_RASTER_OPACITY
  __global const float* hair_depth_g; /* z0 per texel, at dom_offset */
  size_t dom_offset;
  float bound[CLH_DOM_LAYERS];
#endif
} clh_raster_ctx;

#if CLH_RASTER_OPACITY
/* Adds a strand's coverage of texel idx to the opacity layer its depth past z0 falls in
 * (Yuksel & Keyser 2008); hair beyond the last layer adds to the last one. */
static inline void clh_opacity_add(const clh_raster_ctx* rc, __global uint* opacity_g, size_t idx, float z,
                                   float weight) {
  const float z0 = rc->hair_depth_g[rc->dom_offset + idx];
  const float d = z - z0;
  int k = CLH_DOM_LAYERS - 1;
  for (int j = CLH_DOM_LAYERS - 1; j >= 0; --j)
    if (d < rc->bound[j]) k = j;
  const uint add = (uint)(weight * CLH_DOM_FIXED + 0.5f);
  if (add > 0u) atomic_add(opacity_g + rc->dom_offset * CLH_DOM_LAYERS + (size_t)k * rc->plane + idx, add);
}
#endif

static inline void clh_gbuf_write(__global ulong* gbuf_g, __global uint* stats_g, size_t at,
                                  ulong word) {
#if CLH_RASTER_STATS
  atomic_inc(stats_g + 0);
#endif
#if CLH_ATOMIC_LOAD_SKIP
  if (word >= gbuf_g[at]) {
#if CLH_RASTER_STATS
    atomic_inc(stats_g + 2);
#endif
    return;
  }
#endif
#if CLH_RASTER_STATS
  atomic_inc(stats_g + 1);
#endif
  atom_min(gbuf_g + at, word);
}

/* The G-buffer word of a point on the segment at screen parameter t (perspective-correct
 * attributes: aa/ab and ea/eb are attributes divided by z). Returns z through *z. */
static inline ulong clh_segment_word(const clh_raster_ctx* rc, float t, float iza, float izb,
                                     float4 aa, float4 ab, float ea, float eb, float* z) {
  float iz = mix(iza, izb, t);
  *z = 1.0f / iz;
  float4 tw = mix(aa, ab, t) * *z;
  float w = mix(ea, eb, t) * *z;
  float3 tn = clh_normalize_or(tw.xyz, CLH_UP);
  return clh_gbuf_pack(clh_depth_encode(*z, rc->depth_near, rc->depth_far),
                       clh_oct_encode(tn.x, tn.y, tn.z), rc->u6, rc->v6, clh_unorm_bits(w, 6u),
                       clh_unorm_bits(tw.w, 6u));
}

/* Draws one segment (view-space endpoints with world tangents, styling w and AO in the
 * tangent's w). Walks the columns (x-major) or rows (y-major) the segment spans; a sample
 * belongs to the segment when its major coordinate lies in [start, end), so consecutive
 * segments of a strand never hit a sample twice. */
static inline void clh_raster_segment(const clh_raster_ctx* rc, __global const float* scene_depth_g,
                                      __global ulong* gbuf_g, __global uint* stats_g, float3 pa,
                                      float3 pb, float4 ta, float4 tb, float wa, float wb) {
  if (pa.z < rc->near_z && pb.z < rc->near_z) return;
  if (pa.z < rc->near_z || pb.z < rc->near_z) {
    float t = (rc->near_z - pa.z) / (pb.z - pa.z);
    float3 pc = mix(pa, pb, t);
    float4 tc = mix(ta, tb, t);
    float wc = mix(wa, wb, t);
    if (pa.z < rc->near_z) {
      pa = pc;
      ta = tc;
      wa = wc;
    } else {
      pb = pc;
      tb = tc;
      wb = wc;
    }
  }
  float iza = 1.0f / pa.z, izb = 1.0f / pb.z;
  float xa = rc->cx + rc->fx * pa.x * iza, ya = rc->cy - rc->fy * pa.y * iza;
  float xb = rc->cx + rc->fx * pb.x * izb, yb = rc->cy - rc->fy * pb.y * izb;
  float dx = xb - xa, dy = yb - ya;
  float len = sqrt(dx * dx + dy * dy);
  if (!(len > 1e-6f) || !(len < 1e7f)) return;
#if CLH_RASTER_STATS
  atomic_inc(stats_g + 3);
#endif

  bool xmajor = fabs(dx) >= fabs(dy);
  float ma = xmajor ? xa : ya, mb = xmajor ? xb : yb;
  float na = xmajor ? ya : xa, nb = xmajor ? yb : xb;
  float4 aa = ta * iza, ab = tb * izb;
  float ea = wa * iza, eb = wb * izb;
  if (ma > mb) {
    float tmp = ma; ma = mb; mb = tmp;
    tmp = na; na = nb; nb = tmp;
    tmp = iza; iza = izb; izb = tmp;
    float4 t4 = aa; aa = ab; ab = t4;
    tmp = ea; ea = eb; eb = tmp;
  }
  const int major_max = xmajor ? rc->width : rc->height;
  const int minor_max = xmajor ? rc->height : rc->width;
  const float span_m = mb - ma;
  const float slope = (nb - na) / span_m;
  const float cosv = span_m / len; /* minor-axis offsets times cosv = perpendicular distance */

  /* hit radius: projected width at the segment's middle, widened for LOD, at least the minimum */
  const float zmid = 2.0f / (iza + izb);
  const float diameter = fmin(fmax(rc->width_px1 / zmid, rc->min_diameter) * rc->coverage,
                              CLH_MAX_HIT_DIAMETER);
  const float r = 0.5f * diameter;
  const float reach = r / cosv;
#if CLH_RASTER_OPACITY
  /* the share of a texel the strand covers, scaled for strands removed by LOD */
  const float opacity_w = fmin(rc->width_px1 / zmid, 1.0f) * rc->coverage;
#endif

  /* columns whose extent meets [ma, mb), restricted to where the band stays on screen */
  float lo = floor(ma), hi = ceil(mb);
  if (fabs(slope) > 1e-12f) {
    float m0 = ma + (-2.0f - reach - na) / slope;
    float m1 = ma + ((float)minor_max + 2.0f + reach - na) / slope;
    lo = fmax(lo, floor(fmin(m0, m1)));
    hi = fmin(hi, ceil(fmax(m0, m1)));
  } else if (na < -2.0f - reach || na > (float)minor_max + 2.0f + reach) {
    return;
  }
  const int i0 = max((int)fmax(lo, -1.0f), 0);
  const int i1 = min((int)fmin(hi, (float)major_max), major_max); /* exclusive */
  for (int i = i0; i < i1; ++i) {
    /* conservative: the rows the segment crosses within this column */
    float m0 = fmax((float)i, ma), m1 = fmin((float)i + 1.0f, mb);
    if (!(m1 >= m0)) continue;
    float n0 = na + (m0 - ma) * slope, n1 = na + (m1 - ma) * slope;
    int j0 = (int)floor(fmin(n0, n1)), j1 = (int)floor(fmax(n0, n1));
    float zc;
    const ulong cword = clh_segment_word(rc, (0.5f * (m0 + m1) - ma) / span_m, iza, izb, aa, ab, ea, eb, &zc);
#if CLH_RASTER_OPACITY
    (void)cword;
#endif
    for (int j = max(j0, 0); j <= min(j1, minor_max - 1); ++j) {
      int px = xmajor ? i : j, py = xmajor ? j : i;
      size_t idx = (size_t)py * (size_t)rc->width + (size_t)px;
#if CLH_RASTER_OPACITY
      if (zc < scene_depth_g[idx]) clh_opacity_add(rc, (__global uint*)gbuf_g, idx, zc, opacity_w);
#else
      if (zc < scene_depth_g[idx]) clh_gbuf_write(gbuf_g, stats_g, (size_t)CLH_MSAA * rc->plane + idx, cword);
#endif
    }
#if CLH_RASTER_OPACITY
    continue; /* the opacity pass needs no samples */
#endif
    /* samples within the hit radius */
    for (int sidx = 0; sidx < CLH_MSAA; ++sidx) {
      float2 so = clh_samples[sidx];
      float om = xmajor ? so.x : so.y, on = xmajor ? so.y : so.x;
      float ms = (float)i + om;
      if (ms < ma || ms >= mb) continue;
      float nl = na + (ms - ma) * slope;
      int jlo = max((int)ceil(nl - reach - on), 0);
      int jhi = min((int)floor(nl + reach - on), minor_max - 1);
      for (int j = jlo; j <= jhi; ++j) {
        if (!(fabs((float)j + on - nl) * cosv < r)) continue;
        int px = xmajor ? i : j, py = xmajor ? j : i;
        size_t idx = (size_t)py * (size_t)rc->width + (size_t)px;
        float z;
        ulong word = clh_segment_word(rc, (ms - ma) / span_m, iza, izb, aa, ab, ea, eb, &z);
        if (!(z < scene_depth_g[idx])) continue;
        clh_gbuf_write(gbuf_g, stats_g, (size_t)sidx * rc->plane + idx, word);
        if (j < j0 || j > j1) clh_gbuf_write(gbuf_g, stats_g, (size_t)CLH_MSAA * rc->plane + idx, word);
      }
    }
  }
}

/* Which strand a work-group draws; false when there is none (uniform per group). */
static inline bool clh_strand_job(__global const ClhGroomGpu* g, __global const uint4* lod_g,
                                  __global const uint* offsets_g, __global const ClhBundle* bundles_g,
                                  uint strand, uint* bundle, uint* local_index, uint* C,
                                  float* gamma, float* coverage) {
  uint bundle_count = g->bundle_count;
  if (bundle_count == 0u || strand >= offsets_g[bundle_count]) return false;
  uint b = clh_find_bundle(offsets_g, bundle_count, strand);
  uint4 lod = lod_g[b];
  *bundle = b;
  *local_index = strand - offsets_g[b];
  *C = clamp(lod.y, 2u, (uint)CLH_MAX_CONTROL_POINTS);
  *gamma = clamp(as_float(lod.w), 0.0f, 1.0f);
  *coverage = lod.x > 0u ? fmax((float)bundles_g[b].strand_count / (float)lod.x, 1.0f) : 1.0f;
  return *local_index < lod.x;
}

typedef struct {
  __local clh_layer_pt* layers;
  __local clh_strand* strand;
  __local float4* pts;
} clh_strand_scratch;

/* Assembles strand `strand` (when it exists) and draws its segments. Uniform per group. */
static inline void clh_draw_strand(sg_ctx* sg, clh_strand_scratch scratch, clh_raster_ctx* rc,
                                   __global const ClhGroomGpu* g, __global const ClhBundle* bundles_g,
                                   __global const ClhMeshVertex* verts_g, __global const uint4* lod_g,
                                   __global const uint* offsets_g, __global const float2* roots_quad_g,
                                   __global const float2* roots_tri_g, __global const float* scene_depth_g,
                                   __global ulong* gbuf_g, __global uint* stats_g, uint strand) {
  uint bundle = 0u, local_index = 0u, C = 2u;
  float gamma = 0.0f, coverage = 1.0f;
  if (!clh_strand_job(g, lod_g, offsets_g, bundles_g, strand, &bundle, &local_index, &C, &gamma, &coverage))
    return;
  float4 P[CLH_PTS_CAP], T[CLH_PTS_CAP];
  clh_lane_span span;
  clh_assemble_strand(sg, scratch.layers, scratch.strand, scratch.pts, g, bundles_g + bundle, verts_g,
                      roots_quad_g, roots_tri_g, bundle, local_index, C, gamma, P, T, &span);
  rc->u6 = clh_unorm_bits(span.uv.x, 6u);
  rc->v6 = clh_unorm_bits(span.uv.y, 6u);
  rc->coverage = coverage;
  const clh_mat34 to_view = clh_load_mat34(g->obj_to_view);
  const clh_mat34 to_world = clh_load_mat34(g->obj_to_world);
  float3 prev_view = (float3)(0.0f);
  float4 prev_t = (float4)(0.0f);
  float prev_w = 0.0f;
  for (uint i = 0; i < CLH_PTS_CAP + 1u; ++i) {
    uint k = span.first + i;
    if (i > span.count || k >= span.C) break;
    float4 p = (i < span.count) ? P[i] : span.next_p;
    float4 t = (i < span.count) ? T[i] : span.next_t;
    float3 pv = clh_xform_point(to_view, p.xyz);
    float4 tw = (float4)(clh_xform_dir(to_world, t.xyz), t.w);
    if (i > 0u) clh_raster_segment(rc, scene_depth_g, gbuf_g, stats_g, prev_view, pv, prev_t, tw, prev_w, p.w);
    prev_view = pv;
    prev_t = tw;
    prev_w = p.w;
  }
}

static inline clh_raster_ctx clh_raster_setup(__global const ClhGroomGpu* g, __global const ClhViewGpu* view_g) {
  clh_raster_ctx rc;
  rc.fx = view_g->fx;
  rc.fy = view_g->fy;
  rc.cx = view_g->cx;
  rc.cy = view_g->cy;
  rc.width = (int)view_g->width;
  rc.height = (int)view_g->height;
  rc.plane = (size_t)view_g->width * (size_t)view_g->height;
  rc.near_z = 1e-4f;
  rc.depth_near = g->depth_near;
  rc.depth_far = g->depth_far;
  rc.width_px1 = view_g->fy * g->strand_width;
  rc.min_diameter = g->hit_diameter_px;
  rc.coverage = 1.0f;
  rc.u6 = rc.v6 = 0u;
  return rc;
}

#define CLH_RASTER_PARAMS                                                                          \
  __global const ClhGroomGpu *groom_g, __global const ClhViewGpu *view_g,                          \
      __global const ClhBundle *bundles_g, __global const ClhMeshVertex *verts_g,                  \
      __global const uint4 *lod_g, __global const uint *offsets_g,                                 \
      __global const float2 *roots_quad_g, __global const float2 *roots_tri_g,                     \
      __global const float *scene_depth_g, __global ulong *gbuf_g, __global uint *stats_g,         \
      uint strand_base, uint strand_stride

#define CLH_RASTER_PROLOGUE                                           \
  SG_DECLARE(sg);                                                     \
  __local clh_layer_pt layers_l[CLH_MAX_LAYERS];                      \
  __local clh_strand strand_l[1];                                     \
  __local float4 pts_l[CLH_MAX_CONTROL_POINTS];                       \
  clh_strand_scratch scratch;                                         \
  scratch.layers = layers_l;                                          \
  scratch.strand = strand_l;                                          \
  scratch.pts = pts_l;                                                \
  clh_raster_ctx rc = clh_raster_setup(groom_g, view_g)

#if !CLH_RASTER_OPACITY
/* One strand per work-group: strand_base + group (read-back and over-launch sizing). */
__kernel SG_KERNEL_ATTRS void strands_raster(CLH_RASTER_PARAMS) {
  CLH_RASTER_PROLOGUE;
  (void)strand_stride;
  clh_draw_strand(&sg, scratch, &rc, groom_g, bundles_g, verts_g, lod_g, offsets_g, roots_quad_g,
                  roots_tri_g, scene_depth_g, gbuf_g, stats_g, strand_base + (uint)get_group_id(0));
}

/* Persistent grid: group g draws strands g, g + stride, g + 2 stride, ... below the total. */
__kernel SG_KERNEL_ATTRS void strands_raster_persistent(CLH_RASTER_PARAMS) {
  CLH_RASTER_PROLOGUE;
  const uint total = groom_g->bundle_count > 0u ? offsets_g[groom_g->bundle_count] : 0u;
  for (uint strand = strand_base + (uint)get_group_id(0); strand < total; strand += max(strand_stride, 1u)) {
    clh_draw_strand(&sg, scratch, &rc, groom_g, bundles_g, verts_g, lod_g, offsets_g, roots_quad_g,
                    roots_tri_g, scene_depth_g, gbuf_g, stats_g, strand);
  }
}
#else
/* Deep-opacity layers of one light (built with -DCLH_RASTER_OPACITY=1): the strands seen
 * from the light, every texel they touch in front of the opaque scene adding coverage to
 * the layer of its depth past z0. One strand per work-group. */
__kernel SG_KERNEL_ATTRS void strands_opacity(
    __global const ClhGroomGpu* groom_g, __global const ClhViewGpu* view_g, __global const ClhBundle* bundles_g,
    __global const ClhMeshVertex* verts_g, __global const uint4* lod_g, __global const uint* offsets_g,
    __global const float2* roots_quad_g, __global const float2* roots_tri_g, __global const float* opaque_depth_g,
    __global const ClhShadowGpu* shadow_g, __global const float* hair_depth_g, __global uint* opacity_g,
    uint strand_base) {
  SG_DECLARE(sg);
  __local clh_layer_pt layers_l[CLH_MAX_LAYERS];
  __local clh_strand strand_l[1];
  __local float4 pts_l[CLH_MAX_CONTROL_POINTS];
  clh_strand_scratch scratch;
  scratch.layers = layers_l;
  scratch.strand = strand_l;
  scratch.pts = pts_l;
  clh_raster_ctx rc = clh_raster_setup(groom_g, view_g);
  rc.hair_depth_g = hair_depth_g;
  rc.dom_offset = shadow_g->offset;
  for (int k = 0; k < CLH_DOM_LAYERS; ++k) rc.bound[k] = shadow_g->bound[k];
  clh_draw_strand(&sg, scratch, &rc, groom_g, bundles_g, verts_g, lod_g, offsets_g, roots_quad_g, roots_tri_g,
                  opaque_depth_g + shadow_g->offset, (__global ulong*)opacity_g, 0, strand_base + (uint)get_group_id(0));
}
#endif

#if !CLH_RASTER_OPACITY
/* Writes the assembled strands: points_g/tangents_g hold CLH_MAX_CONTROL_POINTS float4 per
 * strand (object space; w = styling w / ambient occlusion), counts_g the point count. */
__kernel SG_KERNEL_ATTRS void strands_export(
    __global const ClhGroomGpu* groom_g, __global const ClhBundle* bundles_g,
    __global const ClhMeshVertex* verts_g, __global const uint4* lod_g,
    __global const uint* offsets_g, __global const float2* roots_quad_g,
    __global const float2* roots_tri_g, __global float4* points_g, __global float4* tangents_g,
    __global uint* counts_g, uint strand_base, uint strand_capacity) {
  SG_DECLARE(sg);
  __local clh_layer_pt layers_l[CLH_MAX_LAYERS];
  __local clh_strand strand_l[1];
  __local float4 pts_l[CLH_MAX_CONTROL_POINTS];
  uint strand = strand_base + (uint)get_group_id(0);
  uint bundle = 0u, local_index = 0u, C = 2u;
  float gamma = 0.0f, coverage = 1.0f;
  if (strand >= strand_capacity ||
      !clh_strand_job(groom_g, lod_g, offsets_g, bundles_g, strand, &bundle, &local_index, &C,
                      &gamma, &coverage))
    return;

  float4 P[CLH_PTS_CAP], T[CLH_PTS_CAP];
  clh_lane_span span;
  clh_assemble_strand(&sg, layers_l, strand_l, pts_l, groom_g, bundles_g + bundle, verts_g,
                      roots_quad_g, roots_tri_g, bundle, local_index, C, gamma, P, T, &span);
  size_t base = (size_t)strand * CLH_MAX_CONTROL_POINTS;
  for (uint i = 0; i < CLH_PTS_CAP; ++i) {
    if (i < span.count) {
      points_g[base + span.first + i] = P[i];
      tangents_g[base + span.first + i] = T[i];
    }
  }
  if (sg_lane() == 0u) counts_g[strand] = span.C;
}
#endif
