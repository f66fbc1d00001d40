/* aov.cl — the layers for compositing (Frame::aovs, clhair/aov.h), gathered on the device
 * while a frame is drawn, one work-item per pixel.
 *
 * aov_begin starts the planes from the opaque scene's depth; aov_groom runs after each
 * groom's composite and folds that groom in: its premultiplied hair over the hair so far,
 * its coverage into the hair alpha (1 - prod(1 - a_k)), the nearest centre word's depth,
 * tangent and (with the identity layer) strand, and the owner of the pixel's depth: the last
 * groom whose composite lowered it, with that groom's motion-pass word. The host turns owner
 * and motion words into the motion plane when the frame is read back. Plain IEEE arithmetic
 * in the order the host's reference builder used, without contraction.
 */
#include "clhair/gpu_types.h"

#pragma OPENCL FP_CONTRACT OFF

__kernel void aov_begin(__global const float* opaque_depth_g, uint pixels,
                        __global float* last_depth_g, __global int* owner_g,
                        __global ulong* owner_motion_g, __global float* alpha_g,
                        __global float4* hair_g, __global float* centre_z_g,
                        __global float4* tangent_g, __global float4* strand_g) {
  const size_t p = get_global_id(0);
  if (p >= pixels) return;
  last_depth_g[p] = opaque_depth_g[p];
  owner_g[p] = -1;
  owner_motion_g[p] = CLH_GBUF_EMPTY;
  alpha_g[p] = 0.0f;
  hair_g[p] = (float4)(0.0f);
  centre_z_g[p] = INFINITY;
  tangent_g[p] = (float4)(0.0f);
  strand_g[p] = (float4)(-1.0f, -1.0f, -1.0f, 0.0f);
}

/* `layers` centre sample layers of `pixels` words, and at word `ids_at` the identity layer
 * (has_ids); `motion_g` the groom's motion plane (has_motion); `depth_g` the depth after its
 * composite. */
__kernel void aov_groom(__global const ClhGroomGpu* groom_g, uint pixels, uint groom_index,
                        __global const ulong* gbuf_g, uint layers, ulong ids_at, uint has_ids,
                        __global const float4* result_g, __global const float* depth_g,
                        __global const ulong* motion_g, uint has_motion,
                        __global float* last_depth_g, __global int* owner_g,
                        __global ulong* owner_motion_g, __global float* alpha_g,
                        __global float4* hair_g, __global float* centre_z_g,
                        __global float4* tangent_g, __global float4* strand_g) {
  const size_t p = get_global_id(0);
  if (p >= pixels) return;
  const float4 h = result_g[p];
  const float a = fmin(fmax(h.w, 0.0f), 1.0f);
  alpha_g[p] = a + (1.0f - a) * alpha_g[p];
  if (h.w > 0.0f) {
    const float4 acc = hair_g[p];
    const float k = 1.0f - h.w;
    hair_g[p] = (float4)(h.x + k * acc.x, h.y + k * acc.y, h.z + k * acc.z, h.w + k * acc.w);
  }
  const float d = depth_g[p];
  if (d < last_depth_g[p]) {
    owner_g[p] = (int)groom_index;
    owner_motion_g[p] = has_motion ? motion_g[p] : CLH_GBUF_EMPTY;
  }
  last_depth_g[p] = d;
  ulong word = CLH_GBUF_EMPTY;
  for (uint s = 0; s < layers; ++s) word = min(word, gbuf_g[(size_t)s * pixels + p]);
  if (word == CLH_GBUF_EMPTY) return;
  const float z = clh_depth_decode(clh_gbuf_depth(word), groom_g->depth_near, groom_g->depth_far);
  if (!(z < centre_z_g[p])) return;
  centre_z_g[p] = z;
  float t[3];
  clh_oct_decode(clh_gbuf_oct(word), t);
  tangent_g[p] = (float4)(t[0], t[1], t[2], 0.0f);
  if (!has_ids) return;
  const ulong id = gbuf_g[ids_at + p];
  if (id == CLH_GBUF_EMPTY) {
    strand_g[p] = (float4)(-1.0f, -1.0f, -1.0f, 0.0f);
    return;
  }
  strand_g[p] = (float4)((float)groom_index, (float)clh_id_strand(id),
                         (float)clh_id_pos(id) / (float)CLH_ID_POS_MAX, 0.0f);
}
