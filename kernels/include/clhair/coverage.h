/* coverage.h — the coverage raster mode (Kulikov 2025, "coverage layer"), the parts shared
 * by the strand kernels, the shading kernel and the host tests, in the common subset of
 * C++17 and OpenCL C (like gpu_types.h).
 *
 * A segment is drawn as a trapezoid: its two ends pushed out along the screen normal by
 * half the strand's projected width at each end. Each pixel it touches gets the exact area
 * of the trapezoid inside the pixel (clh_trapezoid_pixel_area: the quad clipped to the
 * pixel square, Sutherland-Hodgman, then the shoelace formula), so a segment's per-pixel
 * coverages sum to its area whatever its width, length or slope.
 *
 * The G-buffer of the mode (layers of width x height words, gpu_types.h word format):
 *   layers 0..2               the three nearest fragments, depth-ordered (chained
 *                             atom_min, raster_core.h: a displaced word moves on to the
 *                             next layer);
 *   layer CLH_LAYER_COVERAGE  the additive coverage: the first width x height 32-bit words
 *                             of the plane, every fragment adding coverage x 1024
 *                             (atomic_add), hidden behind other hair or not.
 * The coverage plane is cleared like every G-buffer layer, to all ones, so its sum is read
 * as the stored value + 1 (mod 2^32): one clear for the whole G-buffer.
 *
 * Alpha from additive coverage (clh_cover_alpha): the union of many opaque lines of similar
 * width over a pixel as a function of the sum of their coverages, simulated (random lines,
 * tests/coverage_sim.h) and fitted by a polynomial of degree 4 in x on [0, X1] that starts
 * at 0 and reaches 1 with zero slope at X1 = 5:
 *   t = min(x / X1, 1),  alpha = 1 - (1 - t)^2 (1 + b1 t + b2 t^2).
 * Against the simulation's mean per bin of 0.05 over x in [0, 8]: max error 0.0252, mean
 * 0.0054 (the talk's shipped quadratic x - x^2/4 clamped: 0.0969 / 0.0199 there).
 */
#ifndef CLHAIR_COVERAGE_H
#define CLHAIR_COVERAGE_H

#include "clhair/gpu_types.h"

#ifndef CLH_DEVICE_CODE
namespace clhair {
namespace gpu {
#endif

#define CLH_COVER_LAYERS 3       /* depth-ordered fragment layers */
#define CLH_LAYER_COVERAGE 3u    /* the additive coverage plane */
#define CLH_COVER_FIXED 1024.0f  /* coverage units per fully covered pixel */
#define CLH_COVER_X1 5.0f        /* additive coverage at which alpha reaches 1 */
#define CLH_COVER_B1 (-3.38309f) /* the fit (tests/coverage_sim.h reproduces it) */
#define CLH_COVER_B2 3.39994f
#define CLH_COVER_MAX_ERROR 0.0252f /* against the simulation's bin means, x in [0, 8] */
#define CLH_COVER_MEAN_ERROR 0.0054f

/* Alpha of a pixel whose fragments' coverages sum to x (fully covered pixels). */
CLH_FN float clh_cover_alpha(float x) {
  const float t = x > 0.0f ? (x < CLH_COVER_X1 ? x / CLH_COVER_X1 : 1.0f) : 0.0f;
  const float u = 1.0f - t;
  return 1.0f - u * u * (1.0f + t * (CLH_COVER_B1 + t * CLH_COVER_B2));
}

/* The additive coverage of a stored coverage word (the plane starts at all ones). */
CLH_FN float clh_cover_sum(clh_u32 stored) {
  return (float)(clh_u32)(stored + 1u) * (1.0f / CLH_COVER_FIXED);
}

/* A convex polygon of at most 8 vertices (a quad clipped by four half-planes). */
typedef struct {
  float x[8], y[8];
  int n;
} clh_poly8;

/* Keeps the part of `in` where side * (coordinate - bound) >= 0, the coordinate being x
 * (axis 0) or y (axis 1). */
CLH_FN void clh_poly_clip(const clh_poly8* in, clh_poly8* out, int axis, float bound, float side) {
  out->n = 0;
  const int n = in->n;
  for (int i = 0; i < n; ++i) {
    const int j = i + 1 < n ? i + 1 : 0;
    const float ax = in->x[i], ay = in->y[i], bx = in->x[j], by = in->y[j];
    const float da = side * ((axis == 0 ? ax : ay) - bound);
    const float db = side * ((axis == 0 ? bx : by) - bound);
    if (da >= 0.0f && out->n < 8) {
      out->x[out->n] = ax;
      out->y[out->n] = ay;
      out->n += 1;
    }
    if ((da >= 0.0f) != (db >= 0.0f) && out->n < 8) {
      const float t = da / (da - db);
      out->x[out->n] = axis == 0 ? bound : ax + (bx - ax) * t;
      out->y[out->n] = axis == 0 ? ay + (by - ay) * t : bound;
      out->n += 1;
    }
  }
}

/* Area of a polygon (shoelace), either winding. */
CLH_FN float clh_poly_area(const clh_poly8* p) {
  float a = 0.0f;
  for (int i = 0; i < p->n; ++i) {
    const int j = i + 1 < p->n ? i + 1 : 0;
    a += p->x[i] * p->y[j] - p->x[j] * p->y[i];
  }
  return 0.5f * fabs(a);
}

/* The trapezoid of segment (ax, ay)-(bx, by) with full widths wa, wb at its ends (screen
 * pixels): the ends pushed out by half their width along the unit normal. False when the
 * segment has no length. */
CLH_FN int clh_trapezoid(float ax, float ay, float bx, float by, float wa, float wb, clh_poly8* q) {
  const float dx = bx - ax, dy = by - ay;
  const float len = sqrt(dx * dx + dy * dy);
  if (!(len > 1e-6f) || !(len < 1e7f)) return 0;
  const float nx = -dy / len, ny = dx / len;
  const float ha = 0.5f * wa, hb = 0.5f * wb;
  q->x[0] = ax + nx * ha;
  q->y[0] = ay + ny * ha;
  q->x[1] = bx + nx * hb;
  q->y[1] = by + ny * hb;
  q->x[2] = bx - nx * hb;
  q->y[2] = by - ny * hb;
  q->x[3] = ax - nx * ha;
  q->y[3] = ay - ny * ha;
  q->n = 4;
  return 1;
}

/* The part of polygon q inside the column x in [x0, x0 + 1] (the trapezoid's slice). */
CLH_FN void clh_poly_column(const clh_poly8* q, float x0, clh_poly8* col) {
  clh_poly8 t;
  clh_poly_clip(q, &t, 0, x0, 1.0f);
  clh_poly_clip(&t, col, 0, x0 + 1.0f, -1.0f);
}

/* Area of column slice `col` inside the row y in [y0, y0 + 1]. */
CLH_FN float clh_poly_row_area(const clh_poly8* col, float y0) {
  clh_poly8 t, r;
  clh_poly_clip(col, &t, 1, y0, 1.0f);
  clh_poly_clip(&t, &r, 1, y0 + 1.0f, -1.0f);
  return clh_poly_area(&r);
}

/* Area of quad q inside pixel (px, py) (the square [px, px + 1] x [py, py + 1]). */
CLH_FN float clh_trapezoid_pixel_area(const clh_poly8* q, float px, float py) {
  clh_poly8 col;
  clh_poly_column(q, px, &col);
  return clh_poly_row_area(&col, py);
}

#ifndef CLH_DEVICE_CODE
}  // namespace gpu
}  // namespace clhair
#endif

#endif /* CLHAIR_COVERAGE_H */
