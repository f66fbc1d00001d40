/* raster.h — drawing strand segments into the visibility layers, shared by the strand
 * kernels that generate strands (strands.cl) and those that read stored ones.
 *
 * A segment (view-space endpoints with world tangents, styling w and AO) is walked along
 * its major axis one column (x-major) or row (y-major) at a time:
 *   - the conservative layer (index CLH_MSAA) receives every pixel the segment touches;
 *   - sample layer s receives the pixel when sample position s lies within half the hit
 *     diameter of the segment (CLH_MSAA = 1: the pixel center; 2/4/8: the Direct3D
 *     standard patterns), and a sample belongs to the segment when its major coordinate
 *     lies in [start, end), so consecutive segments never hit a sample twice. Every
 *     sample hit also marks the conservative layer, which therefore contains all samples.
 * The hit diameter is the strand's projected width at the segment's middle, at least
 * the groom's minimum, widened by the LOD compensation and capped at
 * CLH_MAX_HIT_DIAMETER. Writes are 64-bit atom_min of the G-buffer word after a depth
 * test against the scene depth, skipped when a plain load shows they cannot lower the
 * word. With CLH_RASTER_OPACITY the conservative pixels add the strand's coverage to the
 * deep-opacity layer of their depth instead (Yuksel & Keyser 2008).
 */
#ifndef CLHAIR_RASTER_H
#define CLHAIR_RASTER_H

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

#define CLH_UP ((float3)(0.0f, 1.0f, 0.0f))

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

/* counts (CLH_RASTER_STATS): the lane's private tallies, summed into the global counters
 * once per lane run (clh_raster_lane), so counting adds no contention per write */
static inline void clh_gbuf_write(__global ulong* gbuf_g, uint* counts, size_t at,
                                  ulong word) {
#if CLH_RASTER_STATS
  counts[0] += 1u;
#endif
#if CLH_ATOMIC_LOAD_SKIP
  if (word >= gbuf_g[at]) {
#if CLH_RASTER_STATS
    counts[2] += 1u;
#endif
    return;
  }
#endif
#if CLH_RASTER_STATS
  counts[1] += 1u;
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
                                      __global ulong* gbuf_g, uint* counts, float3 pa,
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
  counts[3] += 1u;
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
      if (zc < scene_depth_g[idx]) clh_gbuf_write(gbuf_g, counts, (size_t)CLH_MSAA * rc->plane + idx, cword);
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
        clh_gbuf_write(gbuf_g, counts, (size_t)sidx * rc->plane + idx, word);
        if (j < j0 || j > j1) clh_gbuf_write(gbuf_g, counts, (size_t)CLH_MSAA * rc->plane + idx, word);
      }
    }
  }
}

/* Fills the per-view raster constants (written through a pointer: Oclgrind's LLVM lacks
 * the noalias-scope intrinsic clang emits when a returned struct is inlined). */
static inline void clh_raster_setup(clh_raster_ctx* rcp, __global const ClhGroomGpu* g, __global const ClhViewGpu* view_g) {
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
  *rcp = rc;
}

/* Draws a lane's run of a strand: segments (k, k + 1) for its `count` points from
 * `first` on (positions with styling w in P[i].w, tangents with AO in T[i].w, object
 * space), the last one closed by the next lane's first point next_p/next_t; no segment
 * reaches past point total - 1. */
static inline void clh_raster_lane(clh_raster_ctx* rc, __global const float* scene_depth_g, __global ulong* gbuf_g,
                                   __global uint* stats_g, clh_mat34 to_view, clh_mat34 to_world, const float4* P,
                                   const float4* T, uint first, uint count, uint total, float4 next_p,
                                   float4 next_t) {
  float3 prev_view = (float3)(0.0f);
  float4 prev_t = (float4)(0.0f);
  float prev_w = 0.0f;
  uint counts[4] = {0u, 0u, 0u, 0u};
  for (uint i = 0; i <= count; ++i) {
    if (first + i >= total) break;
    const float4 p = (i < count) ? P[i] : next_p;
    const float4 t = (i < count) ? T[i] : next_t;
    const float3 pv = clh_xform_point(to_view, p.xyz);
    const float4 tw = (float4)(clh_xform_dir(to_world, t.xyz), t.w);
    if (i > 0u) clh_raster_segment(rc, scene_depth_g, gbuf_g, counts, prev_view, pv, prev_t, tw, prev_w, p.w);
    prev_view = pv;
    prev_t = tw;
    prev_w = p.w;
  }
#if CLH_RASTER_STATS
  for (int c = 0; c < 4; ++c)
    if (counts[c] > 0u) atomic_add(stats_g + c, counts[c]);
#else
  (void)stats_g;
  (void)counts;
#endif
}

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

#endif /* CLHAIR_RASTER_H */
