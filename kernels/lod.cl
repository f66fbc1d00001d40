/* lod.cl — the per-bundle LOD pre-pass and the scan that sizes the strand dispatch.
 *
 * lod_bundles (one work-item per bundle, Lipp §3.2): projects the four corners of every
 * layer quad, accumulates one screen AABB (Eq. 3) widened by the groom's styling reach,
 * culls bundles entirely off screen, and computes L (Eq. 2), N_LOD (Eq. 1 with the
 * bundle's delta) and C (Eq. 4-5). With LOD off L = 1, N_LOD = N and C is the groom's
 * full-detail count; gamma is the vertex-LOD morph factor (lod_math.h). Output: one
 * ClhLodRecord per bundle (N_LOD, C, L, gamma) and the counts for the scan: N_LOD, and the
 * full count of bundles not culled (layout: gpu_types.h, "the LOD counts and their scan").
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
 * budget_plan and budget_apply (the segment budget, Kulikov 2025 "LODs"): once every
 * groom's pre-pass has run, all grooms' LOD records lie in one buffer (the arena, see
 * ClhBudgetDraw in gpu_types.h). budget_plan (one work-group) sums the segments of the
 * grooms drawn with LOD (the budget is a stage of LOD; grooms drawn without it keep every
 * strand and do not count); over
 * the budget, far grooms (small on screen, marked by the host) draw every other control
 * point, and then every groom keeps N' = max(1, floor(f N)) of the N strands of each
 * drawn bundle, with the largest f <= budget / total that fits. budget_apply (one
 * work-group per groom) rewrites the records, counts and scan, and reports each groom's
 * strands and segments. The strand kernels widen the surviving strands by N / N' as for
 * LOD (clh_lod_record_coverage).
 */
#include "clhair/gpu_types.h"
#include "clhair/lod_math.h"
#include "clh_math.h"

#ifndef SCAN_WG
#define SCAN_WG 256
#endif

/* The LOD record of a bundle or chunk of n_full strands from its screen AABB [lo, hi]:
 * culled (N_LOD = 0) when every corner is behind the camera or the box is off screen;
 * full detail when LOD is off or some corner cannot be projected; otherwise Eq. 1-5 and
 * the morph factor (lod_math.h), C_max being the groom's full detail. */
static inline ClhLodRecord clh_lod_record_for_box(__global const ClhGroomGpu* g, float2 lo,
                                                  float2 hi, bool all_behind, bool unprojectable,
                                                  float width, float height, uint n_full,
                                                  float delta, uint min_points) {
  const uint C_full = clamp(g->control_points, 3u, (uint)CLH_MAX_CONTROL_POINTS);
  bool off_screen = hi.x < 0.0f || hi.y < 0.0f || lo.x > width || lo.y > height;
  if (all_behind || (!unprojectable && off_screen))
    return clh_lod_record_make(0u, C_full, 1.0f, 0.0f);
  if (g->lod_enabled == 0u || unprojectable) return clh_lod_record_make(n_full, C_full, 1.0f, 0.0f);
  float2 ext = hi - lo;
  float L = clh_lod_value(ext.x, ext.y, height, g->lod_lambda); /* Eq. 2 */
  return clh_lod_record_at(L, n_full, delta, min_points, C_full, g->lod_morph_window);
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
  for (uint l = 0; l < layers; ++l) {
    for (uint c = 0; c < 4u; ++c) {
      int vi = clamp(bundle->vtx[c], 0, (int)nv - 1);
      float3 p = clh_xform_point(to_view, vload3(0, verts_g[(size_t)l * nv + (uint)vi].pos));
      if (p.z >= -reach) all_behind = false;
      if (p.z <= 1e-4f) {
        unprojectable = true;
        continue;
      }
      float2 s = (float2)(cx + fx * p.x / p.z, cy - fy * p.y / p.z);
      float r = fx * reach / p.z; /* styling can move strands this far off the mesh */
      lo = fmin(lo, s - r);
      hi = fmax(hi, s + r);
    }
  }

  const ClhLodRecord rec = clh_lod_record_for_box(g, lo, hi, all_behind, unprojectable, width,
                                                  height, n_full, bundle->lod_delta, layers);
  lod_g[b] = rec;
  counts_g[b] = rec.strands;
  /* the full-detail count of every bundle not culled, for beta = drawn / visible */
  counts_g[clh_lod_full_count_at(g->bundle_count, b)] = rec.strands > 0u ? n_full : 0u;
  counts_g[clh_lod_segment_count_at(g->bundle_count, b)] =
      rec.strands * (max(rec.control_points, 2u) - 1u);
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
  }

  const ClhLodRecord rec = clh_lod_record_for_box(g, lo, hi, all_behind, unprojectable, width,
                                                  height, n_full, as_float(chunk.z), 3u);
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
}

/* Sum of v over the work-group (every item must call it; sums_l holds SCAN_WG words). */
static inline uint clh_group_sum(uint v, __local uint* sums_l) {
  const uint lid = (uint)get_local_id(0);
  barrier(CLK_LOCAL_MEM_FENCE);
  sums_l[lid] = v;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint off = SCAN_WG / 2u; off > 0u; off >>= 1) {
    if (lid < off) sums_l[lid] += sums_l[lid + off];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  const uint sum = sums_l[0];
  barrier(CLK_LOCAL_MEM_FENCE);
  return sum;
}

/* The scan of n bundles' counts into offsets with the three totals (gpu_types.h), by one
 * work-group of SCAN_WG items (uniform control flow). */
static void clh_scan_counts(__global const uint* counts_g, __global uint* offsets_g, uint n,
                            __local uint* sums_l) {
  uint lid = (uint)get_local_id(0);
  uint carry = 0u;
  for (uint base = 0u; base < n; base += SCAN_WG) {
    uint i = base + lid;
    uint v = i < n ? counts_g[i] : 0u;
    sums_l[lid] = v;
    barrier(CLK_LOCAL_MEM_FENCE);
    /* Hillis-Steele inclusive scan */
    for (uint off = 1u; off < SCAN_WG; off <<= 1) {
      uint add = lid >= off ? sums_l[lid - off] : 0u;
      barrier(CLK_LOCAL_MEM_FENCE);
      sums_l[lid] += add;
      barrier(CLK_LOCAL_MEM_FENCE);
    }
    if (i < n) offsets_g[i] = carry + sums_l[lid] - v;
    carry += sums_l[SCAN_WG - 1];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (lid == 0u) offsets_g[clh_lod_drawn_total_at(n)] = carry;
  /* the visible total, the sum of counts[n .. 2n), and the segment total, counts[2n .. 3n) */
  uint visible = 0u, segments = 0u;
  for (uint i = lid; i < n; i += SCAN_WG) {
    visible += counts_g[clh_lod_full_count_at(n, i)];
    segments += counts_g[clh_lod_segment_count_at(n, i)];
  }
  visible = clh_group_sum(visible, sums_l);
  segments = clh_group_sum(segments, sums_l);
  if (lid == 0u) {
    offsets_g[clh_lod_visible_total_at(n)] = visible;
    offsets_g[clh_lod_segment_total_at(n)] = segments;
  }
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
    r.strands = kept;
    r.lod = fmin(r.lod, c.lod);
    rec_g[b] = r;
    counts_g[b] = kept;
    counts_g[clh_lod_segment_count_at(n, b)] = (uint)min(s2, (ulong)0xFFFFFFFFu);
  }
  barrier(CLK_GLOBAL_MEM_FENCE | CLK_LOCAL_MEM_FENCE);
  clh_scan_counts(counts_g, offsets_g, n, sums_l);
}

/* ---- the segment budget --------------------------------------------------------------- */

/* Control points of a record whose groom drops every other point: 2^(k-1) + 1 from
 * 2^k + 1, not below min_points (nor 3). */
static inline uint clh_budget_halved_points(uint C, uint min_points) {
  const uint halved = (C - 1u) / 2u + 1u;
  return max(halved, max(min_points, 3u));
}

/* Strands a drawn bundle keeps under the factor f: at least one. */
static inline uint clh_budget_strands(uint n, float f) {
  if (n == 0u || !(f < 1.0f)) return n;
  const float kept = floor((float)n * f);
  return kept < 1.0f ? 1u : min((uint)kept, n);
}

/* Segments of a record with `segs` segments over `n` strands once it keeps `kept` strands
 * at C (halved: at the halved C). Hair meshes: exact. Strand files: the chunk's mean per
 * strand (exact when its strands have equal point counts; a halved strand of k segments
 * keeps ceil(k / 2) <= (k + 1) / 2 of them). */
static inline ulong clh_budget_segments(__global const ClhBudgetDraw* d, uint n, uint segs, uint C,
                                        uint C2, uint kept) {
  if (n == 0u) return 0ul;
  if (d->kind == 0u) return (ulong)kept * (ulong)(max(C2, 2u) - 1u);
  const ulong N = n, S = segs, K = kept;
  if (C2 == C) return (K * S + N - 1ul) / N;
  return (K * (S + N) + 2ul * N - 1ul) / (2ul * N);
}

/* Sum over a work-group of 64-bit values held as two 32-bit halves per item. */
static inline ulong clh_group_sum64(ulong v, __local uint* sums_l) {
  const uint lo = clh_group_sum((uint)(v & 0xFFFFu), sums_l);
  const uint mid = clh_group_sum((uint)((v >> 16) & 0xFFFFu), sums_l);
  const uint hi = clh_group_sum((uint)(v >> 32), sums_l);
  return (ulong)lo + ((ulong)mid << 16) + ((ulong)hi << 32);
}

/* The frame's segments with factor f, far grooms (CLH_BUDGET_HALVED in their flags,
 * flags_g[4 d]) halved. */
static ulong clh_budget_total(__global const ClhBudgetDraw* draws_g, uint draws,
                              __global const ClhLodRecord* rec_g, __global const uint* words_g,
                              __global const uint* flags_g, float f, __local uint* sums_l) {
  const uint lid = (uint)get_local_id(0);
  ulong total = 0ul;
  for (uint d = 0u; d < draws; ++d) {
    __global const ClhBudgetDraw* dr = draws_g + d;
    if (dr->active != CLH_BUDGET_DRAW_BUDGETED) continue;
    const uint n = dr->records;
    for (uint b = lid; b < n; b += SCAN_WG) {
      const ClhLodRecord r = rec_g[dr->records_at + b];
      const uint segs = words_g[dr->counts_at + clh_lod_segment_count_at(n, b)];
      const uint C2 = (flags_g[4u * d] & CLH_BUDGET_HALVED) != 0u
                          ? clh_budget_halved_points(r.control_points, dr->min_points)
                          : r.control_points;
      const uint C = r.control_points;
      total +=
          clh_budget_segments(dr, r.strands, segs, C, min(C2, C), clh_budget_strands(r.strands, f));
    }
  }
  return clh_group_sum64(total, sums_l);
}

/* state_g: the header then 4 words per draw (gpu_types.h), of which budget_plan writes the
 * header and word 3 (the flags) and budget_apply the rest. */
__kernel __attribute__((reqd_work_group_size(SCAN_WG, 1, 1))) void budget_plan(
    __global const ClhBudgetDraw* draws_g, uint draws, __global const ClhLodRecord* rec_g,
    __global const uint* words_g, ulong budget, __global uint* state_g) {
  __local uint sums_l[SCAN_WG];
  const uint lid = (uint)get_local_id(0);
  __global uint* flags_g = state_g + CLH_BUDGET_HEADER + 3u;
  for (uint d = lid; d < draws; d += SCAN_WG) flags_g[4u * d] = 0u;
  barrier(CLK_GLOBAL_MEM_FENCE);
  /* One call site of clh_budget_total (each inlined copy of its group sums is compiled
   * anew), stepped through the plan: step 0 the frame's segments; over the budget, step 1
   * with far grooms halved (CLH_BUDGET_HALVED); still over, step 2 at the proportional
   * f = budget / total; when the one-strand floors push that sum over, steps 3.. bisect
   * for the largest f that fits (0: one strand per drawn bundle). The sums are uniform over
   * the work-group, so every work-item takes the same steps. */
  ulong total = 0ul;
  bool over = false;
  float f = 1.0f, lo = 0.0f, hi = 0.0f, at = 1.0f;
  for (uint step = 0u;; ++step) {
    const ulong sum = clh_budget_total(draws_g, draws, rec_g, words_g, flags_g, at, sums_l);
    if (step == 0u) {
      total = sum;
      over = budget > 0ul && total > budget;
      if (!over) break;
      /* far grooms (the host marks them by their size on screen) */
      for (uint d = lid; d < draws; d += SCAN_WG)
        flags_g[4u * d] = draws_g[d].far != 0u && draws_g[d].active == CLH_BUDGET_DRAW_BUDGETED
                              ? CLH_BUDGET_HALVED
                              : 0u;
      barrier(CLK_GLOBAL_MEM_FENCE);
    } else if (step == 1u) {
      if (sum <= budget) break;
      f = fmin((float)budget / (float)sum, 1.0f);
      at = f;
      continue;
    } else if (step == 2u) {
      if (sum <= budget) break;
      hi = f;
    } else {
      if (sum > budget)
        hi = at;
      else
        lo = at;
      if (step == 2u + 24u) {
        f = lo;
        break;
      }
    }
    at = step == 0u ? 1.0f : 0.5f * (lo + hi);
  }
  if (lid == 0u) {
    state_g[0] = as_uint(f);
    state_g[1] = over ? 1u : 0u;
    state_g[2] = 0u;
    state_g[3] = (uint)(total & 0xFFFFFFFFul);
    state_g[4] = (uint)(total >> 32);
    state_g[5] = state_g[6] = state_g[7] = 0u;
  }
}

/* One work-group per draw: applies the plan to the draw's records and counts, scans them
 * again and reports its strands, segments and visible strands. */
__kernel __attribute__((reqd_work_group_size(SCAN_WG, 1, 1))) void budget_apply(
    __global const ClhBudgetDraw* draws_g, uint draws, __global ClhLodRecord* rec_g,
    __global uint* words_g, __global uint* state_g) {
  __local uint sums_l[SCAN_WG];
  const uint d = (uint)get_group_id(0);
  const uint lid = (uint)get_local_id(0);
  if (d >= draws) return; /* uniform per group */
  __global const ClhBudgetDraw* dr = draws_g + d;
  __global uint* out = state_g + CLH_BUDGET_HEADER + 4u * d;
  if (dr->active == 0u) {
    if (lid == 0u) out[0] = out[1] = out[2] = 0u;
    return;
  }
  const uint n = dr->records;
  __global uint* counts = words_g + dr->counts_at;
  __global uint* offsets = words_g + dr->offsets_at;
  const float f = as_float(state_g[0]);
  const bool halve = (out[3] & CLH_BUDGET_HALVED) != 0u;
  if (state_g[1] != 0u && dr->active == CLH_BUDGET_DRAW_BUDGETED) {
    for (uint b = lid; b < n; b += SCAN_WG) {
      ClhLodRecord r = rec_g[dr->records_at + b];
      const uint C = r.control_points;
      const uint C2 = halve ? min(clh_budget_halved_points(C, dr->min_points), C) : C;
      const uint kept = clh_budget_strands(r.strands, f);
      const ulong segs =
          clh_budget_segments(dr, r.strands, counts[clh_lod_segment_count_at(n, b)], C, C2, kept);
      r.strands = kept;
      if (C2 != C) {
        r.control_points = C2;
        r.gamma = 0.0f; /* no morph: the level is fixed for the frame */
      }
      rec_g[dr->records_at + b] = r;
      counts[b] = kept;
      counts[clh_lod_segment_count_at(n, b)] = (uint)min(segs, (ulong)0xFFFFFFFFu);
    }
    barrier(CLK_GLOBAL_MEM_FENCE | CLK_LOCAL_MEM_FENCE);
    clh_scan_counts(counts, offsets, n, sums_l);
    barrier(CLK_GLOBAL_MEM_FENCE | CLK_LOCAL_MEM_FENCE);
  }
  if (lid == 0u) {
    out[0] = offsets[clh_lod_drawn_total_at(n)];
    out[1] = offsets[clh_lod_segment_total_at(n)];
    out[2] = offsets[clh_lod_visible_total_at(n)];
  }
}
