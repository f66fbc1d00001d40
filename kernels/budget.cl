/* budget.cl — the segment budget over every groom's LOD records (Kulikov 2025, "LODs": a
 * per-frame cap on the segments of all grooms together; DESIGN.md "The segment budget").
 *
 * Once every groom's LOD pre-pass has run, all grooms' records, counts and scans lie in one
 * buffer (the arena; ClhBudgetDraw in gpu_types.h gives each draw's place), and three
 * kernels run on it with no host round trip before the strand passes:
 *
 * budget_measure (one work-group per draw) sums what the draw's records ask: R, the
 * segments of its LOD request; F, its floor, one strand per drawn record; both again at
 * every other control point; and A, its screen box, the union of its records' boxes
 * clipped to the image.
 *
 * budget_plan (one work-group) decides. Within the budget, or with the budget 0, nothing
 * changes. Over it, far grooms (small on screen, marked by the host) draw every other
 * control point (R and F are then the halved ones), and then
 *  - the uniform rule keeps N' = max(1, floor(f N)) of the N strands of every drawn record,
 *    with the largest f <= budget / total that fits (one factor for every groom);
 *  - the screen rule gives draw d the share of segments
 *        S_d = min(R_d, max(G_d, floor(mu A_d))),  G_d = F_d + floor(phi p_d (R_d - F_d)),
 *    mu the largest level (segments per pixel of screen box) at which the shares fit the
 *    budget (bisection); p_d = smoothstep(keep_lo, keep_hi, A_d / image area) the draw's
 *    claim to keep its LOD count; phi = clamp((room - room_lo) / (1 - room_lo), 0, 1) with
 *    room = (budget - sum F) / sum p (R - F), so the claims hold whenever the other grooms'
 *    cuts down to their floors pay for them, and fade out as they cannot. When the floors
 *    alone exceed the budget, S_d = F_d. Draw d then keeps in each drawn record its first
 *    strand and f_d = (S_d - F_d) / (R_d - F_d) of the others, apportioned over the records
 *    in order (the running total rounded down), so its segments never exceed S_d.
 *
 * budget_apply (one work-group per draw) rewrites the records (strands, control points,
 * widening), counts and scan, and reports each draw's strands, segments and visible
 * strands. The strand kernels widen the survivors by the record's widening N / N' (under
 * the screen rule at most widen_cap times LOD's own, when a cap is set).
 */
#include "clhair/gpu_types.h"
#include "group_scan.h"

/* Control points of a record whose groom drops every other point: 2^(k-1) + 1 from
 * 2^k + 1, not below min_points (nor 3). */
static inline uint clh_budget_halved_points(uint C, uint min_points) {
  const uint halved = (C - 1u) / 2u + 1u;
  return max(halved, max(min_points, 3u));
}

/* The control-point count record r is drawn with (halved: every other point dropped). */
static inline uint clh_budget_points(__global const ClhBudgetDraw* d, ClhLodRecord r, bool halve) {
  return halve ? min(clh_budget_halved_points(r.control_points, d->min_points), r.control_points)
               : r.control_points;
}

/* The uniform rule: strands a drawn bundle keeps under the factor f, at least one. */
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

/* The words of draw d in the state buffer. */
static inline __global uint* clh_budget_out(__global uint* state_g, uint d) {
  return state_g + CLH_BUDGET_HEADER + CLH_BUDGET_DRAW_WORDS * d;
}

/* One work-group per draw: its request, floors, screen box and drawn records (state words
 * 4..9, gpu_types.h). Every active draw is measured, under either rule. */
__kernel __attribute__((reqd_work_group_size(SCAN_WG, 1, 1))) void budget_measure(
    __global const ClhBudgetDraw* draws_g, uint draws, __global const ClhLodRecord* rec_g,
    __global const uint* words_g, __global uint* state_g) {
  __local uint sums_l[SCAN_WG];
  const uint d = (uint)get_group_id(0);
  const uint lid = (uint)get_local_id(0);
  if (d >= draws) return; /* uniform per group */
  __global const ClhBudgetDraw* dr = draws_g + d;
  __global uint* out = clh_budget_out(state_g, d);
  const uint n = dr->active != 0u ? dr->records : 0u;
  __global const uint* counts = words_g + dr->counts_at;
  /* per-draw sums stay below 2^32: a record's segments are a u32 (gpu_types.h) and a draw
   * of 2^32 segments would be beyond any budget (kMaxSegmentBudget) */
  uint R = 0u, Rh = 0u, F = 0u, Fh = 0u, drawn = 0u;
  uint x0 = as_uint(INFINITY), y0 = as_uint(INFINITY), x1 = 0u, y1 = 0u;
  for (uint b = lid; b < n; b += SCAN_WG) {
    const ClhLodRecord r = rec_g[dr->records_at + b];
    if (r.strands == 0u) continue;
    const uint segs = counts[clh_lod_segment_count_at(n, b)];
    const uint C = r.control_points, C2 = clh_budget_points(dr, r, true);
    R += (uint)clh_budget_segments(dr, r.strands, segs, C, C, r.strands);
    Rh += (uint)clh_budget_segments(dr, r.strands, segs, C, C2, r.strands);
    F += (uint)clh_budget_segments(dr, r.strands, segs, C, C, 1u);
    Fh += (uint)clh_budget_segments(dr, r.strands, segs, C, C2, 1u);
    ++drawn;
    /* boxes are clipped to the image: coordinates >= 0, which order as their bits do */
    x0 = min(x0, counts[clh_lod_box_at(n, b, 0u)]);
    y0 = min(y0, counts[clh_lod_box_at(n, b, 1u)]);
    x1 = max(x1, counts[clh_lod_box_at(n, b, 2u)]);
    y1 = max(y1, counts[clh_lod_box_at(n, b, 3u)]);
  }
  R = clh_group_sum(R, sums_l);
  Rh = clh_group_sum(Rh, sums_l);
  F = clh_group_sum(F, sums_l);
  Fh = clh_group_sum(Fh, sums_l);
  drawn = clh_group_sum(drawn, sums_l);
  x0 = clh_group_extreme(x0, false, sums_l);
  y0 = clh_group_extreme(y0, false, sums_l);
  x1 = clh_group_extreme(x1, true, sums_l);
  y1 = clh_group_extreme(y1, true, sums_l);
  if (lid == 0u) {
    const float w = drawn > 0u ? fmax(as_float(x1) - as_float(x0), 0.0f) : 0.0f;
    const float h = drawn > 0u ? fmax(as_float(y1) - as_float(y0), 0.0f) : 0.0f;
    out[4] = R;
    out[5] = Rh;
    out[6] = F;
    out[7] = Fh;
    out[8] = as_uint(w * h);
    out[9] = drawn;
    out[10] = R; /* the share and factor, until the screen rule says otherwise */
    out[11] = as_uint(1.0f);
    out[12] = as_uint(0.0f);
    out[13] = R;
    out[14] = out[15] = 0u;
  }
}

/* The frame's segments with the uniform factor f, far grooms (CLH_BUDGET_HALVED in their
 * flags) halved. */
static ulong clh_budget_total(__global const ClhBudgetDraw* draws_g, uint draws,
                              __global const ClhLodRecord* rec_g, __global const uint* words_g,
                              __global uint* state_g, float f, __local uint* sums_l) {
  const uint lid = (uint)get_local_id(0);
  ulong total = 0ul;
  for (uint d = 0u; d < draws; ++d) {
    __global const ClhBudgetDraw* dr = draws_g + d;
    if (dr->active != CLH_BUDGET_DRAW_BUDGETED) continue;
    const bool halve = (clh_budget_out(state_g, d)[3] & CLH_BUDGET_HALVED) != 0u;
    const uint n = dr->records;
    for (uint b = lid; b < n; b += SCAN_WG) {
      const ClhLodRecord r = rec_g[dr->records_at + b];
      const uint segs = words_g[dr->counts_at + clh_lod_segment_count_at(n, b)];
      total +=
          clh_budget_segments(dr, r.strands, segs, r.control_points,
                              clh_budget_points(dr, r, halve), clh_budget_strands(r.strands, f));
    }
  }
  return clh_group_sum64(total, sums_l);
}

/* The uniform rule's factor: step 1 is the frame's segments with far grooms halved; still
 * over, step 2 at the proportional f = budget / total; when the one-strand floors push
 * that sum over, steps 3.. bisect for the largest f that fits (0: one strand per drawn
 * bundle). One call site of clh_budget_total (each inlined copy of its group sums is
 * compiled anew). The sums are uniform over the work-group, so every work-item takes the
 * same steps. */
static float clh_budget_uniform(__global const ClhBudgetDraw* draws_g, uint draws,
                                __global const ClhLodRecord* rec_g, __global const uint* words_g,
                                ulong budget, __global uint* state_g, __local uint* sums_l) {
  float f = 1.0f, lo = 0.0f, hi = 0.0f, at = 1.0f;
  for (uint step = 1u;; ++step) {
    const ulong sum = clh_budget_total(draws_g, draws, rec_g, words_g, state_g, at, sums_l);
    if (step == 1u) {
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
    at = 0.5f * (lo + hi);
  }
  return f;
}

/* Draw d's request and floor under the plan (halved when its flags say so). */
static inline void clh_budget_bounds(__global const uint* out, uint* R, uint* F) {
  const bool halve = (out[3] & CLH_BUDGET_HALVED) != 0u;
  *R = halve ? out[5] : out[4];
  *F = halve ? out[7] : out[6];
}

/* Draw d's share at level mu: min(R, max(G, floor(mu A))). */
static inline uint clh_budget_share_at(__global const uint* out, float mu) {
  uint R, F;
  clh_budget_bounds(out, &R, &F);
  const uint G = out[13];
  const float s = floor(mu * as_float(out[8]));
  return s >= (float)R ? R : (s > (float)G ? (uint)s : G);
}

/* The screen rule, over the budget: each budgeted draw's claim, share and factor (state
 * words 10..13). Every work-item handles draws lid, lid + SCAN_WG, ... in every loop, so
 * it reads back only words it wrote itself. Returns mu; phi goes to the header (word 6). */
static float clh_budget_screen(__global const ClhBudgetDraw* draws_g, uint draws,
                               __constant ClhBudgetRule* rule, ulong budget, __global uint* state_g,
                               __local uint* sums_l) {
  const uint lid = (uint)get_local_id(0);
  ulong floors = 0ul, claims = 0ul, requests = 0ul;
  uint mu_hi = 0u; /* the largest R_d / A_d (f32 bits, >= 0) */
  for (uint d = lid; d < draws; d += SCAN_WG) {
    __global uint* out = clh_budget_out(state_g, d);
    if (draws_g[d].active != CLH_BUDGET_DRAW_BUDGETED) continue;
    uint R, F;
    clh_budget_bounds(out, &R, &F);
    const float area = as_float(out[8]);
    const float share = rule->image_area > 0.0f ? area / rule->image_area : 0.0f;
    const float p = rule->keep_hi > rule->keep_lo ? smoothstep(rule->keep_lo, rule->keep_hi, share)
                                                  : (share >= rule->keep_lo ? 1.0f : 0.0f);
    out[12] = as_uint(p);
    floors += F;
    requests += R;
    claims += (ulong)ceil(p * (float)(R - F)); /* up: sum G stays within the budget */
    if (area > 0.0f) mu_hi = max(mu_hi, as_uint((float)R / area));
  }
  floors = clh_group_sum64(floors, sums_l);
  requests = clh_group_sum64(requests, sums_l);
  claims = clh_group_sum64(claims, sums_l);
  mu_hi = clh_group_extreme(mu_hi, true, sums_l);
  /* the claims' strength: whole while the room above the floors covers them */
  float phi = 1.0f;
  if (floors >= budget) {
    phi = 0.0f;
  } else if (claims > 0ul) {
    const float room = (float)(budget - floors) / (float)claims;
    phi = rule->room_lo < 1.0f ? clamp((room - rule->room_lo) / (1.0f - rule->room_lo), 0.0f, 1.0f)
                               : (room >= 1.0f ? 1.0f : 0.0f);
  }
  for (uint d = lid; d < draws; d += SCAN_WG) {
    __global uint* out = clh_budget_out(state_g, d);
    if (draws_g[d].active != CLH_BUDGET_DRAW_BUDGETED) continue;
    uint R, F;
    clh_budget_bounds(out, &R, &F);
    const float p = as_float(out[12]);
    out[13] = F + min((uint)floor(phi * p * (float)(R - F)), R - F);
  }
  /* mu: the largest level whose shares fit (sum G <= budget whenever the floors fit, as
   * phi <= room), by bisection over [0, max R / A] */
  float mu = 0.0f;
  if (requests <= budget) {
    mu = INFINITY; /* the far grooms' halving alone fits: every share is its request */
  } else if (floors < budget) {
    /* [0, max R / A] with a margin: floor(mu A) reaches R at the top despite rounding */
    float lo = 0.0f, hi = as_float(mu_hi) * 1.001f;
    for (uint step = 0u; step < 40u; ++step) {
      const float at = 0.5f * (lo + hi);
      ulong sum = 0ul;
      for (uint d = lid; d < draws; d += SCAN_WG)
        if (draws_g[d].active == CLH_BUDGET_DRAW_BUDGETED)
          sum += clh_budget_share_at(clh_budget_out(state_g, d), at);
      sum = clh_group_sum64(sum, sums_l);
      if (sum <= budget)
        lo = at;
      else
        hi = at;
    }
    mu = lo;
  }
  for (uint d = lid; d < draws; d += SCAN_WG) {
    __global uint* out = clh_budget_out(state_g, d);
    if (draws_g[d].active != CLH_BUDGET_DRAW_BUDGETED) continue;
    uint R, F;
    clh_budget_bounds(out, &R, &F);
    const uint S = requests <= budget ? R : (floors < budget ? clh_budget_share_at(out, mu) : F);
    /* a strand file's chunks round their mean up: one segment of slack per drawn chunk */
    const uint slack = draws_g[d].kind == 1u ? out[9] : 0u;
    float f = 1.0f;
    if (S < R) f = S > F + slack ? fmin((float)(S - F - slack) / (float)(R - F), 1.0f) : 0.0f;
    out[10] = S;
    out[11] = as_uint(f);
  }
  if (lid == 0u) state_g[6] = as_uint(phi);
  return mu;
}

/* One work-group: the plan (state header and each draw's flags, and under the screen rule
 * its share and factor). */
__kernel __attribute__((reqd_work_group_size(SCAN_WG, 1, 1))) void budget_plan(
    __global const ClhBudgetDraw* draws_g, uint draws, __global const ClhLodRecord* rec_g,
    __global const uint* words_g, ulong budget, __constant ClhBudgetRule* rule,
    __global uint* state_g) {
  __local uint sums_l[SCAN_WG];
  const uint lid = (uint)get_local_id(0);
  ulong total = 0ul;
  for (uint d = lid; d < draws; d += SCAN_WG) {
    __global uint* out = clh_budget_out(state_g, d);
    out[3] = 0u;
    if (draws_g[d].active == CLH_BUDGET_DRAW_BUDGETED) total += out[4];
  }
  total = clh_group_sum64(total, sums_l);
  const bool over = budget > 0ul && total > budget;
  float f = 1.0f, mu = 0.0f;
  if (lid == 0u) state_g[6] = as_uint(1.0f);
  if (over) {
    /* far grooms (the host marks them by their size on screen) */
    for (uint d = lid; d < draws; d += SCAN_WG)
      clh_budget_out(state_g, d)[3] =
          draws_g[d].far != 0u && draws_g[d].active == CLH_BUDGET_DRAW_BUDGETED ? CLH_BUDGET_HALVED
                                                                                : 0u;
    barrier(CLK_GLOBAL_MEM_FENCE);
    if (rule->rule == CLH_BUDGET_RULE_SCREEN)
      mu = clh_budget_screen(draws_g, draws, rule, budget, state_g, sums_l);
    else
      f = clh_budget_uniform(draws_g, draws, rec_g, words_g, budget, state_g, sums_l);
  }
  if (lid == 0u) {
    state_g[0] = as_uint(f);
    state_g[1] = over ? 1u : 0u;
    state_g[2] = rule->rule;
    state_g[3] = (uint)(total & 0xFFFFFFFFul);
    state_g[4] = (uint)(total >> 32);
    state_g[5] = as_uint(mu);
    state_g[7] = 0u;
  }
}

/* The screen rule's strands for a record of n > 0 strands whose draw keeps f of the
 * strands above its floors: the record's first strand and the whole strands between the
 * draw's running total before it (at, over the records before it) and after it, rounded
 * down, so each record gets f (n - 1) within one strand and the draw no more than f of
 * them in all. plain: f (n - 1) rounded down in each record on its own. */
static inline uint clh_budget_strands_screen(uint n, float f, uint at, bool plain) {
  if (n == 0u) return 0u;
  if (!(f < 1.0f)) return n;
  const uint more = plain ? (uint)floor(f * (float)(n - 1u))
                          : (uint)floor(f * (float)(at + n - 1u)) - (uint)floor(f * (float)at);
  return 1u + min(more, n - 1u);
}

/* One work-group per draw: applies the plan to the draw's records and counts, scans them
 * again and reports its strands, segments and visible strands. */
__kernel __attribute__((reqd_work_group_size(SCAN_WG, 1, 1))) void budget_apply(
    __global const ClhBudgetDraw* draws_g, uint draws, __global ClhLodRecord* rec_g,
    __global uint* words_g, __constant ClhBudgetRule* rule, __global uint* state_g) {
  __local uint sums_l[SCAN_WG];
  const uint d = (uint)get_group_id(0);
  const uint lid = (uint)get_local_id(0);
  if (d >= draws) return; /* uniform per group */
  __global const ClhBudgetDraw* dr = draws_g + d;
  __global uint* out = clh_budget_out(state_g, d);
  if (dr->active == 0u) {
    if (lid == 0u) out[0] = out[1] = out[2] = 0u;
    return;
  }
  const uint n = dr->records;
  __global uint* counts = words_g + dr->counts_at;
  __global uint* offsets = words_g + dr->offsets_at;
  const bool screen = rule->rule == CLH_BUDGET_RULE_SCREEN;
  const float f = screen ? as_float(out[11]) : as_float(state_g[0]);
  const bool halve = (out[3] & CLH_BUDGET_HALVED) != 0u;
  if (state_g[1] != 0u && dr->active == CLH_BUDGET_DRAW_BUDGETED &&
      (!screen || f < 1.0f || halve)) {
    /* Under the screen rule with f < 1, a first pass scans n - 1 over the drawn records
     * (counts[b] holds N_LOD until the records are rewritten) for the running totals, and
     * checks the apportioned strands against the share: apportioned, the draw's segments
     * stay within it when its records share one control-point count; otherwise a record of
     * many points may round up where one of few rounds down, and then every record rounds
     * down on its own (plain). The last pass rewrites the records and scans the counts.
     * One call site of clh_scan_counts: PoCL 3.1's compiler fails on two inlined copies. */
    const uint passes = screen && f < 1.0f ? 2u : 1u;
    bool plain = true;
    for (uint pass = 0u; pass < passes; ++pass) {
      const bool last = pass + 1u == passes;
      for (uint b = lid; b < n; b += SCAN_WG) {
        ClhLodRecord r = rec_g[dr->records_at + b];
        if (!last) {
          counts[b] = r.strands > 0u ? r.strands - 1u : 0u;
          continue;
        }
        const uint C = r.control_points;
        const uint C2 = clh_budget_points(dr, r, halve);
        const uint kept = screen ? clh_budget_strands_screen(r.strands, f, offsets[b], plain)
                                 : clh_budget_strands(r.strands, f);
        const ulong segs =
            clh_budget_segments(dr, r.strands, counts[clh_lod_segment_count_at(n, b)], C, C2, kept);
        const uint n_full = counts[clh_lod_full_count_at(n, b)];
        float widening = clh_lod_widening(n_full, kept);
        if (screen && rule->widen_cap > 0.0f && kept > 0u)
          widening = fmin(widening, clh_lod_record_coverage(r) * fmax(rule->widen_cap, 1.0f));
        r.strands = kept;
        r.coverage = widening;
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
      if (!last) {
        ulong segments = 0ul;
        for (uint b = lid; b < n; b += SCAN_WG) {
          const ClhLodRecord r = rec_g[dr->records_at + b];
          const uint kept = clh_budget_strands_screen(r.strands, f, offsets[b], false);
          segments += clh_budget_segments(dr, r.strands, counts[clh_lod_segment_count_at(n, b)],
                                          r.control_points, clh_budget_points(dr, r, halve), kept);
        }
        plain = clh_group_sum64(segments, sums_l) > (ulong)out[10];
      }
    }
  }
  if (lid == 0u) {
    out[0] = offsets[clh_lod_drawn_total_at(n)];
    out[1] = offsets[clh_lod_segment_total_at(n)];
    out[2] = offsets[clh_lod_visible_total_at(n)];
  }
}
