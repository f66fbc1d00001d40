/* composite.cl — blends one groom's shaded hair over the render target.
 *
 * hair_g holds premultiplied RGBA; the target colour becomes hair + (1 - alpha) * target.
 * Where the hair is at least half opaque its depth (the nearest word of the G-buffer's
 * `depth_layers` first layers: the samples, plus the conservative layer after the filter)
 * replaces the scene depth when nearer, so the next groom is depth tested against it;
 * fainter hair does not hide what lies behind it. The launch covers the int4 `box` [x0, x1) x
 * [y0, y1) of the image: a groom's screen box when the host knows the hair is transparent
 * (alpha 0) outside it, else the whole image.
 */
#include "clhair/gpu_types.h"
#include "clh_math.h"

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable

#ifndef CLH_MSAA
#define CLH_MSAA 1
#endif

__kernel void composite_over(__global const ClhGroomGpu* groom_g, __global const ClhViewGpu* view_g,
                             __global const float4* hair_g, __global const ulong* gbuf_g,
                             __global float4* color_g, __global float* depth_g, uint depth_layers,
                             int4 box) {
  const uint width = view_g->width, height = view_g->height;
  int bx, by;
  if (!clh_box_pixel(box, (int)width, (int)height, &bx, &by)) return;
  const uint x = (uint)bx, y = (uint)by;
  size_t idx = (size_t)y * width + x;
  float4 h = hair_g[idx];
  if (!(h.w > 0.0f)) return;
  float4 c = color_g[idx];
  color_g[idx] = (float4)(h.xyz + (1.0f - h.w) * c.xyz, 1.0f);
  if (h.w < 0.5f) return;
  size_t plane = (size_t)width * height;
  ulong word = CLH_GBUF_EMPTY;
  for (uint s = 0; s < min(depth_layers, (uint)CLH_MSAA + 1u); ++s)
    word = min(word, gbuf_g[s * plane + idx]);
  if (word != CLH_GBUF_EMPTY) {
    float z = clh_depth_decode(clh_gbuf_depth(word), groom_g->depth_near, groom_g->depth_far);
    depth_g[idx] = fmin(depth_g[idx], z);
  }
}
