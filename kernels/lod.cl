/* lod.cl — the per-bundle LOD pre-pass and the scan that sizes the strand dispatch.
 *
 * lod_bundles (one work-item per bundle, Lipp §3.2): projects the four corners of every
 * layer quad, accumulates one screen AABB (Eq. 3) widened by the groom's styling reach,
 * culls bundles entirely off screen, and computes L (Eq. 2), N_LOD (Eq. 1 with the
 * bundle's delta) and C (Eq. 4-5); where the groom gives strands per pixel (the default),
 * N_LOD is that many per pixel of the bundle's projected width instead (its widest layer quad,
 * lod_math.h clh_lod_strands_screen). With LOD off L = 1, N_LOD = N and C is the groom's
 * full-detail count; gamma is the vertex-LOD morph factor (lod_math.h). Output: one
 * ClhLodRecord per bundle (N_LOD, C, the widening N / N_LOD, gamma) and the counts for the scan:
 * N_LOD, the full count of bundles not culled and the segments (layout: gpu_types.h, "the LOD
 * counts and their scan").
 *
 * lod_chunks (one work-item per chunk of an explicit groom, strands_explicit.cl): the same
 * record from the chunk's object-space AABB (its 8 corners projected, no styling reach),
 * with 3 as the least control-point count; chunks play the role of bundles, so
 * scan_bundles and the strand dispatch sizing are shared.
 *
 * scan_bundles (one work-group of SCAN_WG items): exclusive scan of the counts into
 * offsets[0..n), then the drawn total (the host reads it back to size the strand pass),
 * the visible total, the full-detail strand count of the bundles not culled, so shading
 * knows the fraction beta of visible strands LOD kept, and the segment total.
 *
 * lod_cap (one work-group): the light passes' records of a groom capped by the camera's
 * (what the camera can resolve, per bundle), counted and scanned again.
 *
 * Each pre-pass also writes the record's screen box clipped to the image (gpu_types.h),
 * which the segment budget's screen rule reads (budget.cl). The work-group reductions and the scan
 * live in group_scan.h.
 */
#include "clhair/gpu_types.h"
#include "clhair/lod_math.h"
#include "clh_math.h"
#include "group_scan.h"

/* The LOD record of a bundle or chunk of n_full strands from its screen AABB [lo, hi]:
 * culled (N_LOD = 0) when every corner is behind the camera or the box is off screen;
 * full detail when LOD is off or some corner cannot be projected; otherwise Eq. 1-5 and
 * the morph factor (lod_math.h), C_max being the groom's full detail. */
static inline ClhLodRecord clh_lod_record_for_box(__global const ClhGroomGpu* g, float2 lo,
                                                  float2 hi, float across, bool all_behind,
                                                  bool unprojectable, float width, float height,
                                                  uint n_full, float delta, uint min_points) {
  const uint C_full = clamp(g->control_points, 3u, (uint)CLH_MAX_CONTROL_POINTS);
  bool off_screen = hi.x < 0.0f || hi.y < 0.0f || lo.x > width || lo.y > height;
  if (all_behind || (!unprojectable && off_screen))
    return clh_lod_record_make(0u, C_full, 1.0f, 0.0f);
  if (g->lod_enabled == 0u || unprojectable)
    return clh_lod_record_make(n_full, C_full, clh_lod_widening(n_full, n_full), 0.0f);
  float2 ext = hi - lo;
  float L = clh_lod_value(ext.x, ext.y, height, g->lod_lambda); /* Eq. 2 */
  if (g->lod_strands_px > 0.0f) /* the strands from the screen, C from L */
    return clh_lod_record_screen(L, across, g->lod_strands_px, n_full, delta, min_points, C_full,
                                 g->lod_morph_window);
  return clh_lod_record_at(L, n_full, delta, min_points, C_full, g->lod_morph_window);
}

/* The record's screen box clipped to the image, for the segment budget's screen rule
 * (gpu_types.h: clh_lod_box_at); zeros when the record draws nothing. */
static inline void clh_lod_write_box(__global uint* counts_g, uint n, uint b, bool drawn, float2 lo,
                                     float2 hi, float width, float height) {
  const float2 size = (float2)(width, height);
  const float2 clo = drawn ? clamp(lo, (float2)(0.0f), size) : (float2)(0.0f);
  const float2 chi = drawn ? clamp(hi, clo, size) : (float2)(0.0f);
  counts_g[clh_lod_box_at(n, b, 0u)] = as_uint(clo.x);
  counts_g[clh_lod_box_at(n, b, 1u)] = as_uint(clo.y);
  counts_g[clh_lod_box_at(n, b, 2u)] = as_uint(chi.x);
  counts_g[clh_lod_box_at(n, b, 3u)] = as_uint(chi.y);
}

__kernel void lod_bundles(__global const ClhGroomGpu* groom_g, __global const ClhViewGpu* view_g,
                          __global const ClhBundle* bundles_g,
                          __global const ClhMeshVertex* verts_g, float reach,
                          __global ClhLodRecord* lod_g, __global uint* counts_g) {
  uint b = (uint)get_global_id(0);
  __global const ClhGroomGpu* g = groom_g;
  if (b >= g->bundle_count) return;
  __global const ClhBundle* bundle = bundles_g + b;
  uint n_full = bundle->strand_count;
  uint layers = clamp(g->layer_count, 2u, (uint)CLH_MAX_LAYERS);
  uint nv = g->vertex_count;
  clh_mat34 to_view = clh_load_mat34(g->obj_to_view);
  float fx = view_g->fx, fy = view_g->fy, cx = view_g->cx, cy = view_g->cy;
  float width = (float)view_g->width, height = (float)view_g->height;

  /* Corners at or behind the camera plane cannot be projected: such a bundle is kept at
   * full detail, unless every corner lies behind the camera by more than the reach. */
  float2 lo = (float2)(INFINITY), hi = (float2)(-INFINITY);
  bool all_behind = true, unprojectable = false;
  float across = 0.0f; /* the bundle's width on screen: its widest layer quad, in pixels */
  for (uint l = 0; l < layers; ++l) {
    float2 q[4];
    for (uint c = 0; c < 4u; ++c) {
      int vi = clamp(bundle->vtx[c], 0, (int)nv - 1);
      float3 p = clh_xform_point(to_view, vload3(0, verts_g[(size_t)l * nv + (uint)vi].pos));
      if (p.z >= -reach) all_behind = false;
      q[c] = (float2)(0.0f);
      if (p.z <= 1e-4f) {
        unprojectable = true;
        continue;
      }
      float2 s = (float2)(cx + fx * p.x / p.z, cy - fy * p.y / p.z);
      q[c] = s;
      float r = fx * reach / p.z; /* styling can move strands this far off the mesh */
      lo = fmin(lo, s - r);
      hi = fmax(hi, s + r);
    }
    /* the quad's diameter (a triangle repeats its third corner) */
    across = fmax(across, fmax(fmax(distance(q[0], q[1]), distance(q[1], q[2])),
                               fmax(distance(q[2], q[3]), distance(q[3], q[0]))));
    across = fmax(across, fmax(distance(q[0], q[2]), distance(q[1], q[3])));
  }

  const ClhLodRecord rec = clh_lod_record_for_box(g, lo, hi, across, all_behind, unprojectable,
                                                  width, height, n_full, bundle->lod_delta, layers);
  lod_g[b] = rec;
  const uint n = g->bundle_count;
  counts_g[b] = rec.strands;
  /* the full-detail count of every bundle not culled, for beta = drawn / visible */
  counts_g[clh_lod_full_count_at(n, b)] = rec.strands > 0u ? n_full : 0u;
  counts_g[clh_lod_segment_count_at(n, b)] = rec.strands * (max(rec.control_points, 2u) - 1u);
  clh_lod_write_box(counts_g, n, b, rec.strands > 0u, lo, hi, width, height);
}

/* bounds_g: 2 float4 per chunk (AABB min, max); chunks_g: uint4 (first strand, strands
 * drawn at full detail, LOD delta bits, stored strands: host/groom/explicit_data.h);
 * strand_offsets_g: the first stored point of each of the strand_count strands and the point count
 * after the last (strands_explicit.cl). */
__kernel void lod_chunks(__global const ClhGroomGpu* groom_g, __global const ClhViewGpu* view_g,
                         __global const float4* bounds_g, __global const uint4* chunks_g,
                         __global const uint* strand_offsets_g, uint strand_count, uint point_count,
                         __global ClhLodRecord* lod_g, __global uint* counts_g) {
  uint c = (uint)get_global_id(0);
  __global const ClhGroomGpu* g = groom_g;
  if (c >= g->bundle_count) return;
  const uint4 chunk = chunks_g[c];
  const uint n_full = chunk.y;
  const float3 blo = bounds_g[2u * c].xyz, bhi = bounds_g[2u * c + 1u].xyz;
  clh_mat34 to_view = clh_load_mat34(g->obj_to_view);
  float fx = view_g->fx, fy = view_g->fy, cx = view_g->cx, cy = view_g->cy;
  float width = (float)view_g->width, height = (float)view_g->height;

  /* as in lod_bundles: corners at or behind the camera plane keep the chunk at full detail
   * unless all of them are behind the camera */
  float2 lo = (float2)(INFINITY), hi = (float2)(-INFINITY);
  bool all_behind = true, unprojectable = false;
  float nearest = INFINITY;
  for (uint k = 0; k < 8u; ++k) {
    float3 corner =
        (float3)((k & 1u) ? bhi.x : blo.x, (k & 2u) ? bhi.y : blo.y, (k & 4u) ? bhi.z : blo.z);
    float3 p = clh_xform_point(to_view, corner);
    if (p.z >= 0.0f) all_behind = false;
    if (p.z <= 1e-4f) {
      unprojectable = true;
      continue;
    }
    float2 s = (float2)(cx + fx * p.x / p.z, cy - fy * p.y / p.z);
    lo = fmin(lo, s);
    hi = fmax(hi, s);
    nearest = fmin(nearest, p.z);
  }
  /* the chunk's width on screen: its widest cross-section (bounds_g[2c].w, object units,
   * host/groom/explicit_data.h) at its nearest corner's depth, times the largest axis scale */
  const float axis = fmax(fmax(length((float3)(to_view.r0.x, to_view.r1.x, to_view.r2.x)),
                               length((float3)(to_view.r0.y, to_view.r1.y, to_view.r2.y))),
                          length((float3)(to_view.r0.z, to_view.r1.z, to_view.r2.z)));
  const float across = isfinite(nearest) ? fx * bounds_g[2u * c].w * axis / nearest : 0.0f;

  const ClhLodRecord rec = clh_lod_record_for_box(g, lo, hi, across, all_behind, unprojectable,
                                                  width, height, n_full, as_float(chunk.z), 3u);
  lod_g[c] = rec;
  counts_g[c] = rec.strands;
  counts_g[clh_lod_full_count_at(g->bundle_count, c)] = rec.strands > 0u ? n_full : 0u;
  /* the segments of the strands drawn: the first N_LOD of the chunk, each at its own step;
   * slot k is a child of guide k % guides (chunks_g.w guides; a child draws as its guide) */
  const uint c_full = clamp(g->control_points, 3u, (uint)CLH_MAX_CONTROL_POINTS);
  const uint C = clamp(rec.control_points, 3u, c_full);
  const uint guides = max(min(chunk.w, n_full), 1u);
  const uint drawn = min(rec.strands, n_full);
  uint all = 0u, head = 0u; /* every guide's segments; the first drawn % guides guides' */
  for (uint k = 0u; k < guides; ++k) {
    const uint st = chunk.x + k;
    if (st >= strand_count) break;
    const uint first = min(strand_offsets_g[st], point_count);
    const uint last = clamp(strand_offsets_g[st + 1u], first, point_count);
    const uint seg = clh_explicit_segments(last - first, C, c_full);
    all += seg;
    if (k < drawn % guides) head += seg;
  }
  const uint segments = (drawn / guides) * all + head;
  counts_g[clh_lod_segment_count_at(g->bundle_count, c)] = segments;
  clh_lod_write_box(counts_g, g->bundle_count, c, rec.strands > 0u, lo, hi, width, height);
}

__kernel __attribute__((reqd_work_group_size(SCAN_WG, 1, 1))) void scan_bundles(
    __global const uint* counts_g, __global uint* offsets_g, uint n) {
  __local uint sums_l[SCAN_WG];
  clh_scan_counts(counts_g, offsets_g, n, sums_l);
}

/* ---- the light passes' LOD from what the camera needs --------------------------------- */

/* One work-group (one groom instance; DESIGN.md, "Light-pass LOD from the camera"): the
 * light's records of the groom, just written by lod_bundles / lod_chunks in the light's
 * view, keep no more strands and control points per bundle than the camera's records
 * camera_g (the same bundles in the camera's view) do: a strand the camera cannot resolve
 * adds nothing to the shadow it sees. A bundle the camera culls (no strands) keeps the
 * light's record: its shadow may still fall in view. The strands kept are widened by the
 * strand kernels as for any LOD (N / N_LOD), so a texel's opacity stays. Counts
 * rewritten (segments: exact for hair meshes, stored == 0; the chunk's mean per strand
 * for strand files) and scanned again. */
__kernel __attribute__((reqd_work_group_size(SCAN_WG, 1, 1))) void lod_cap(
    __global ClhLodRecord* rec_g, __global uint* counts_g, __global uint* offsets_g,
    __global const ClhLodRecord* camera_g, uint camera_at, uint n, uint stored) {
  __local uint sums_l[SCAN_WG];
  const uint lid = (uint)get_local_id(0);
  for (uint b = lid; b < n; b += SCAN_WG) {
    ClhLodRecord r = rec_g[b];
    const ClhLodRecord c = camera_g[camera_at + b];
    if (c.strands == 0u || r.strands == 0u) continue;
    const uint kept = min(r.strands, c.strands);
    const uint C = min(r.control_points, c.control_points);
    const uint segs = counts_g[clh_lod_segment_count_at(n, b)];
    ulong s2;
    if (stored == 0u) {
      s2 = (ulong)kept * (ulong)(max(C, 2u) - 1u);
    } else {
      /* the chunk's mean segments per strand, scaled by the points kept */
      const ulong per = ((ulong)segs + r.strands - 1u) / r.strands;
      s2 = (ulong)kept *
           max((per * (ulong)(max(C, 2u) - 1u)) / (ulong)(max(r.control_points, 2u) - 1u),
               (ulong)1u);
    }
    if (C < r.control_points) {
      r.control_points = C;
      r.gamma = c.control_points == C ? c.gamma : 0.0f;
    }
    /* the strands left out widen those kept: N / kept, with N = coverage x strands */
    r.coverage = r.coverage * (float)r.strands / (float)kept;
    r.strands = kept;
    rec_g[b] = r;
    counts_g[b] = kept;
    counts_g[clh_lod_segment_count_at(n, b)] = (uint)min(s2, (ulong)0xFFFFFFFFu);
  }
  barrier(CLK_GLOBAL_MEM_FENCE | CLK_LOCAL_MEM_FENCE);
  clh_scan_counts(counts_g, offsets_g, n, sums_l);
}
