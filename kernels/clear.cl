/* clear.cl — fills 64-bit words with one value (the empty G-buffer word). Kernels rather
 * than clEnqueueFillBuffer so simulators and checkers (Oclgrind) see the words as written.
 *
 *  clear_words  `count` words from the start of the buffer, one work-item per word.
 *  clear_uints  the same for 32-bit words (counters, bitmaps, hash tables).
 *  copy_uints   `count` 32-bit words from word src_first of one buffer to word dst_first of
 *               another (statistics gathered into one buffer, a light's depth into its
 *               slice): kernels rather than clEnqueueCopyBuffer, whose writes into part of a
 *               buffer Oclgrind 21.10's --uninitialized check records wrongly.
 *  clear_box    the box [box.x, box.z) x [box.y, box.w) of the first `layers` planes of a
 *               width x height image (a groom's screen box in its G-buffer layers): one
 *               work-item per pixel of the box, looping over the planes.
 * Tails guarded; clear_box writes nothing outside the box or the image.
 */
#include "clh_math.h"

__kernel void clear_words(__global ulong* words_g, ulong value, ulong count) {
  size_t i = get_global_id(0);
  if (i < count) words_g[i] = value;
}

__kernel void clear_uints(__global uint* words_g, uint value, ulong count) {
  size_t i = get_global_id(0);
  if (i < count) words_g[i] = value;
}

__kernel void copy_uints(__global const uint* src_g, ulong src_first, __global uint* dst_g,
                         ulong dst_first, ulong count) {
  size_t i = get_global_id(0);
  if (i < count) dst_g[dst_first + i] = src_g[src_first + i];
}

__kernel void clear_box(__global ulong* words_g, ulong value, int width, int height, uint layers,
                        int4 box) {
  int x, y;
  if (!clh_box_pixel(box, width, height, &x, &y)) return;
  const size_t plane = (size_t)width * (size_t)height;
  const size_t idx = (size_t)y * (size_t)width + (size_t)x;
  for (uint l = 0u; l < layers; ++l) words_g[(size_t)l * plane + idx] = value;
}
