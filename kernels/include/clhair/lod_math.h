/* lod_math.h — the LOD formulas, shared by lod.cl and the host (tests, benchmark).
 *
 * Lipp et al. 2026 §3.2: L from the bundle's screen AABB (Eq. 2), the strand count N_LOD
 * with the per-bundle offset delta (Eq. 1), the control-point count C (Eq. 4-5, snapped
 * to 2^k + 1). Bhokare et al. 2024 §3.6.2: the morph factor gamma that moves a strand
 * toward the next coarser level inside a transition window, so C can halve without a
 * jump: at the point where C switches from 2^k + 1 to 2^(k-1) + 1, gamma is exactly 1.
 * C_max is the groom's full-detail control-point count (at most CLH_MAX_CONTROL_POINTS,
 * 129, see gpu_types.h), so LOD never draws more points than LOD off. clh_lod_record_at
 * puts them together into one bundle's LOD record (Lipp's strand count, which the strand
 * export uses); clh_lod_record_screen is the record the LOD pre-pass writes, its strand count
 * set by the bundle's width on screen instead (DESIGN.md, "LOD from the screen"). Written
 * in the common subset of C++17 and OpenCL C like gpu_types.h.
 */
#ifndef CLHAIR_LOD_MATH_H
#define CLHAIR_LOD_MATH_H

#include "clhair/gpu_types.h"

#ifndef CLH_DEVICE_CODE
namespace clhair {
namespace gpu {
#endif

/* Eq. 2: L = clamp(|AABB_max - AABB_min| / R_y * lambda, 0, 1), the diagonal in pixels. */
CLH_FN float clh_lod_value(float aabb_w, float aabb_h, float res_y, float lambda) {
  return clh_clamp01(sqrt(aabb_w * aabb_w + aabb_h * aabb_h) / res_y * lambda);
}

/* Eq. 1: N_LOD = clamp(ceil(L (N + delta)), 1, N); 0 strands stay 0. */
CLH_FN clh_u32 clh_lod_strands(float L, clh_u32 n_full, float delta) {
  if (n_full == 0u) return 0u;
  float n = ceil(L * ((float)n_full + delta));
  if (n < 1.0f) return 1u;
  if (n > (float)n_full) return n_full;
  return (clh_u32)n;
}

/* N_LOD from the screen (DESIGN.md, "LOD from the screen"): per_px strands per pixel of the
 * bundle's projected width width_px, with the bundle's delta in [0, 1) as the dither of Eq. 1,
 * between 1 and N; 0 strands stay 0. The count follows the pixels the bundle covers, not the
 * strands the groom has; the strands left out widen the kept ones by N / N_LOD. */
CLH_FN clh_u32 clh_lod_strands_screen(float width_px, float per_px, clh_u32 n_full, float delta) {
  if (n_full == 0u) return 0u;
  float n = ceil(fmax(width_px, 0.0f) * per_px + delta);
  if (!(n >= 1.0f)) return 1u;
  if (n > (float)n_full) return n_full;
  return (clh_u32)n;
}

/* Eq. 4 without the floor: the continuous control-point target, at least the layer count
 * and at least 3. */
CLH_FN float clh_lod_points_continuous(float L, clh_u32 layers, clh_u32 c_max) {
  float c = sqrt(clh_clamp01(L)) * (float)c_max;
  return fmax(fmax(c, (float)layers), 3.0f);
}

/* Eq. 5: C = min(2^ceil(log2(C_raw - 1)) + 1, C_max) with C_raw = floor(continuous). */
CLH_FN clh_u32 clh_lod_snap(clh_u32 c_raw, clh_u32 c_max) {
  if (c_raw < 3u) c_raw = 3u;
  clh_u32 p = 1u;
  while (p < c_raw - 1u) p <<= 1;
  clh_u32 c = p + 1u;
  return c > c_max ? c_max : c;
}

CLH_FN clh_u32 clh_lod_control_points(float L, clh_u32 layers, clh_u32 c_max) {
  return clh_lod_snap((clh_u32)floor(clh_lod_points_continuous(L, layers, c_max)), c_max);
}

/* Bhokare Eq. 10-12 in C's terms: C = 2^k + 1 holds while the continuous target c lies in
 * [2^(k-1) + 2, 2^k + 2); with y = log2(c - 2) in [k-1, k), the strand is morphed toward
 * level k-1 by gamma = 1 - (y - (k-1)) / window inside the first `window` of the level.
 * No morph when level k-1 would have fewer points than the layers (C never goes there). */
CLH_FN float clh_lod_morph(float L, clh_u32 layers, clh_u32 c_max, float window) {
  float c = clh_lod_points_continuous(L, layers, c_max);
  clh_u32 C = clh_lod_snap((clh_u32)floor(c), c_max);
  if (C < 5u || !(window > 0.0f)) return 0.0f;
  clh_u32 lower = (C - 1u) / 2u + 1u;
  if (lower < layers) return 0.0f;
  float y = log2(fmax(c - 2.0f, 1.0f));
  float k_minus_1 = log2((float)(C - 1u)) - 1.0f;
  return clh_clamp01(1.0f - (y - k_minus_1) / window);
}

/* The LOD record (gpu_types.h) of a bundle or chunk of n_full strands drawn at LOD value
 * L: N_LOD by Eq. 1 with its delta, C by Eq. 4-5 between min_points (the layer count; 3
 * for strand files) and c_full, the widening N / N_LOD, and gamma for the morph window. lod.cl
 * writes it for every bundle LOD does not cull or keep at full detail; the host writes it when it
 * fixes L (strand export). */
CLH_FN ClhLodRecord clh_lod_record_at(float L, clh_u32 n_full, float delta, clh_u32 min_points,
                                      clh_u32 c_full, float window) {
  const clh_u32 n = clh_lod_strands(L, n_full, delta);
  return clh_lod_record_make(n, clh_lod_control_points(L, min_points, c_full),
                             clh_lod_widening(n_full, n),
                             clh_lod_morph(L, min_points, c_full, window));
}

/* The LOD record lod.cl writes: C and gamma from L as clh_lod_record_at, the strands from the
 * screen (clh_lod_strands_screen) with the widening N / N_LOD. */
CLH_FN ClhLodRecord clh_lod_record_screen(float L, float width_px, float per_px, clh_u32 n_full,
                                          float delta, clh_u32 min_points, clh_u32 c_full,
                                          float window) {
  const clh_u32 n = clh_lod_strands_screen(width_px, per_px, n_full, delta);
  return clh_lod_record_make(n, clh_lod_control_points(L, min_points, c_full),
                             clh_lod_widening(n_full, n),
                             clh_lod_morph(L, min_points, c_full, window));
}

/* Strand files (strands_explicit.cl): drawn point j of a stored strand of n points is
 * stored point min(j * step, n - 1), with step the power of two that brings the chunk's
 * C points up to the full-detail c_full (C_full of the LOD formulas), halved again while
 * the strand would keep fewer than 3 points. */
CLH_FN clh_u32 clh_explicit_step(clh_u32 n, clh_u32 C, clh_u32 c_full) {
  clh_u32 step = 1u;
  while ((C - 1u) * step < c_full - 1u) step <<= 1;
  while (step > 1u && n - 1u < 2u * step) step >>= 1;
  return step;
}

/* The segments a stored strand of n >= 2 points draws at the chunk's C (0 below 2). */
CLH_FN clh_u32 clh_explicit_segments(clh_u32 n, clh_u32 C, clh_u32 c_full) {
  if (n < 2u) return 0u;
  const clh_u32 step = clh_explicit_step(n, C, c_full);
  return (n - 1u + step - 1u) / step;
}

#ifndef CLH_DEVICE_CODE
} /* namespace gpu */
} /* namespace clhair */
#endif

#endif /* CLHAIR_LOD_MATH_H */
