/* visibility.h — the shading pass's lookup of a groom's baked spherical visibility
 * (Kulikov 2025, "precomputed self-shadowing"; table layout and SH in
 * clhair/visibility_sh.h, bake in host/groom/visibility_bake.cpp).
 *
 * Input: the groom instance's ClhVisibilityGpu, the four SH coefficients of the shaded
 * word's (u, v, w) cell (already scaled for LOD), and the world-space direction to the
 * light. Output: exp(-absorption * max(0, SH(l))) in (0, 1], l turned into the bake's object
 * space by the linear part of world_to_obj and normalised (a non-uniform scale changes a
 * direction's length, and the SH's linear band needs a unit vector). */
#ifndef CLHAIR_VISIBILITY_H
#define CLHAIR_VISIBILITY_H

#include "clh_math.h"
#include "clhair/fast_math.h"
#include "clhair/gpu_types.h"
#include "clhair/visibility_sh.h"

static inline float clh_vis_transmittance(__global const ClhVisibilityGpu* vis, float4 sh,
                                          clh_v3 l) {
  __global const float* m = vis->world_to_obj;
  const float x = m[0] * l.x + m[1] * l.y + m[2] * l.z;
  const float y = m[4] * l.x + m[5] * l.y + m[6] * l.z;
  const float z = m[8] * l.x + m[9] * l.y + m[10] * l.z;
  const float inv = 1.0f / sqrt(fmax(x * x + y * y + z * z, 1e-20f));
  const float events = clh_vis_events(sh.x, sh.y, sh.z, sh.w, x * inv, y * inv, z * inv);
  return clh_fast_exp(-vis->absorption * events);
}

#endif /* CLHAIR_VISIBILITY_H */
