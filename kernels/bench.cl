/* bench.cl — the atomic-throughput probe of the benchmark (bench/).
 *
 * bench_atomic_min: every work-item issues `per_item` 64-bit atom_min on words of a
 * target of `words` entries. Address k of item i is (i + k * items) % words, so
 * neighbouring work-items touch neighbouring words (coherent, like a strand's pixels) and
 * every word receives the same number of attempts. Values come from a hash, so about
 * half of the later attempts cannot lower the word; with `load_skip` a plain load first
 * skips those, as the raster kernel does.
 */
#include "clhair/gpu_types.h"

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_int64_extended_atomics : enable

__kernel void bench_atomic_min(__global ulong* target_g, uint words, uint per_item,
                               uint load_skip) {
  uint items = (uint)get_global_size(0);
  uint i = (uint)get_global_id(0);
  if (words == 0u) return;
  for (uint k = 0; k < per_item; ++k) {
    uint at = (uint)(((ulong)i + (ulong)k * items) % words);
    ulong v = ((ulong)clh_hash2(i, k) << 32) | (ulong)clh_hash(k ^ i);
    if (load_skip != 0u && v >= target_g[at]) continue;
    atom_min(target_g + at, v);
  }
}
