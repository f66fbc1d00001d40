/* shadow.cl — building the deep opacity maps (the strand passes themselves are in
 * strands.cl: strands_raster draws the light's G-buffer, strands_opacity accumulates).
 *
 * shadow_resolve_depth: the nearest hair depth z0 per texel from the conservative layer
 * of the light's G-buffer (INFINITY where no hair), written at the light's offset.
 * shadow_clear: zeroes the opacity layers of one light.
 */
#include "clhair/gpu_types.h"

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable

__kernel void shadow_resolve_depth(__global const ClhShadowGpu* shadow_g,
                                   __global const ulong* gbuf_g, __global float* hair_depth_g) {
  const uint x = (uint)get_global_id(0), y = (uint)get_global_id(1);
  const uint w = shadow_g->width, h = shadow_g->height;
  if (x >= w || y >= h) return;
  const size_t plane = (size_t)w * h, idx = (size_t)y * w + x;
  const ulong word = gbuf_g[plane + idx]; /* layer 1: conservative */
  hair_depth_g[(size_t)shadow_g->offset + idx] =
      word == CLH_GBUF_EMPTY
          ? INFINITY
          : clh_depth_decode(clh_gbuf_depth(word), shadow_g->depth_near, shadow_g->depth_far);
}

__kernel void shadow_clear(__global const ClhShadowGpu* shadow_g, __global uint* opacity_g) {
  const size_t i = get_global_id(0);
  const size_t plane = (size_t)shadow_g->width * shadow_g->height;
  if (i >= plane * CLH_DOM_LAYERS) return;
  opacity_g[(size_t)shadow_g->offset * CLH_DOM_LAYERS + i] = 0u;
}
