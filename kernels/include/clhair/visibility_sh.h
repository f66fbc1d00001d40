/* visibility_sh.h — the baked spherical visibility's table layout and its SH evaluation,
 * shared by the bake (host/groom/visibility_bake.cpp), the shading kernel (shade.cl) and
 * the tests, in the common subset of C++17 and OpenCL C.
 *
 * Kulikov 2025 ("precomputed self-shadowing"): rays from points of the groom count the
 * fibres (scattering events) they pass; the mean count per direction is projected onto
 * real L1 spherical harmonics, rays that hit nothing entering as -CLH_HAIR_MAX_SCATTER_EVENTS
 * so that the clamped reconstruction max(0, SH(l)) falls to zero quickly where the groom
 * is open and the backlit glow is not lost. Shading: visibility = exp(-absorption * events).
 *
 * The table is keyed by what a G-buffer word carries: the 6-bit styling codes u, v (the
 * strand's root uv) and w (position along the strand), 64^3 cells of 4 coefficients in
 * the order Y00, Y1-1 (y), Y10 (z), Y11 (x), directions in the groom's object space. */
#ifndef CLHAIR_VISIBILITY_SH_H
#define CLHAIR_VISIBILITY_SH_H

#include "clhair/gpu_types.h"

#ifndef CLH_DEVICE_CODE
namespace clhair {
namespace gpu {
#endif

#define CLH_HAIR_MAX_SCATTER_EVENTS 5.0f
#define CLH_VIS_AXIS 64u /* cells per styling coordinate: the word's 6-bit codes */
#define CLH_VIS_CELLS (CLH_VIS_AXIS * CLH_VIS_AXIS * CLH_VIS_AXIS)
#define CLH_VIS_COEFFS 4u
#define CLH_SH_Y0 0.282094792f /* 1 / (2 sqrt(pi)) */
#define CLH_SH_Y1 0.488602512f /* sqrt(3 / (4 pi)) */

/* The cell of styling codes (u6, v6, w6), each < 64. */
CLH_FN clh_u32 clh_vis_cell(clh_u32 u6, clh_u32 v6, clh_u32 w6) {
  return ((u6 & 63u) * CLH_VIS_AXIS + (v6 & 63u)) * CLH_VIS_AXIS + (w6 & 63u);
}

/* The L1 reconstruction sum_i c_i Y_i(d) at unit direction d = (x, y, z). */
CLH_FN float clh_vis_sh_eval(float c0, float c1, float c2, float c3, float x, float y, float z) {
  return CLH_SH_Y0 * c0 + CLH_SH_Y1 * (c1 * y + c2 * z + c3 * x);
}

/* Scattering events toward d, clamped at zero (misses were biased below it). */
CLH_FN float clh_vis_events(float c0, float c1, float c2, float c3, float x, float y, float z) {
  return fmax(clh_vis_sh_eval(c0, c1, c2, c3, x, y, z), 0.0f);
}

#ifndef CLH_DEVICE_CODE
} /* namespace gpu */
} /* namespace clhair */
#endif

#endif /* CLHAIR_VISIBILITY_SH_H */
