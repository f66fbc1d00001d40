/* selftest.cl — small kernels that check the device against the host's assumptions.
 *
 * selftest_subgroup: one work-group (SG_STRANDS strands of SG_SIZE lanes) exercises every
 *   operation of the sub-group layer, twice in a row so both halves of the __local
 *   ping-pong are used; the host compares the SELFTEST_WORDS words per work-item with its
 *   CPU model.
 * selftest_layout: writes sizeof() of every struct of gpu_types.h (host pins the same).
 * selftest_gbuffer: packs G-buffer words from float inputs with the shared helpers.
 */
#include "clhair/gpu_types.h"
#include "subgroup.h"

#define SELFTEST_WORDS 16

__kernel SG_KERNEL_ATTRS void selftest_subgroup(__global uint* out_g) {
  SG_DECLARE(sg);
  uint lane = sg_lane();
  uint x = lane * 7u + 3u + sg_slot() * 1000u; /* each strand slot exchanges its own values */
  uint y = lane * 13u + 100u + sg_slot() * 1000u;
  uint4 x4 = (uint4)(x, x + 1u, x + 2u, x + 3u);
  uint4 fill4 = (uint4)(1u, 2u, 3u, 4u);
  uint r0 = sg_shuffle_up1(&sg, x, 0xF00Du);
  uint r1 = sg_shuffle_down1(&sg, x, 0xBEEFu);
  uint r2 = sg_broadcast0(&sg, x);
  uint4 r3 = sg_shuffle_up1_u4(&sg, x4, fill4);
  uint4 r4 = sg_shuffle_down1_u4(&sg, x4, fill4);
  uint r5 = sg_shuffle_up1(&sg, y, 0xF00Du);
  uint r6 = sg_shuffle_down1(&sg, y, 0xBEEFu);
  __global uint* o = out_g + get_local_id(0) * SELFTEST_WORDS;
  o[0] = r0;
  o[1] = r1;
  o[2] = r2;
  vstore4(r3, 0, o + 3);
  vstore4(r4, 0, o + 7);
  o[11] = r5;
  o[12] = r6;
  o[13] = lane;
  o[14] = (uint)get_local_size(0);
  o[15] = 0u;
}

__kernel void selftest_layout(__global uint* out_g) {
  if (get_global_id(0) != 0) return;
  out_g[0] = (uint)sizeof(ClhMeshVertex);
  out_g[1] = (uint)sizeof(ClhBundle);
  out_g[2] = (uint)sizeof(ClhGroomGpu);
  out_g[3] = (uint)sizeof(ClhViewGpu);
  out_g[4] = (uint)sizeof(ClhLightGpu);
  out_g[5] = (uint)sizeof(ClhSphereGpu);
  out_g[6] = (uint)sizeof(ClhPlaneGpu);
  out_g[7] = (uint)sizeof(ClhSceneGpu);
  out_g[8] = (uint)sizeof(ClhLodRecord);
  out_g[9] = (uint)sizeof(ClhVisibilityGpu);
  out_g[10] = (uint)sizeof(ClhChildrenGpu);
}

/* in_g: 8 floats per word (depth z, near, far, tx, ty, tz, u, v) and 2 more (w, ao) —
 * 10 floats per entry; out_g: the packed word. */
__kernel void selftest_gbuffer(__global const float* in_g, __global ulong* out_g, uint n) {
  uint i = (uint)get_global_id(0);
  if (i >= n) return;
  __global const float* e = in_g + (size_t)i * 10u;
  out_g[i] = clh_gbuf_pack(clh_depth_encode(e[0], e[1], e[2]), clh_oct_encode(e[3], e[4], e[5]),
                           clh_unorm_bits(e[6], 6u), clh_unorm_bits(e[7], 6u),
                           clh_unorm_bits(e[8], 6u), clh_unorm_bits(e[9], 6u));
}
