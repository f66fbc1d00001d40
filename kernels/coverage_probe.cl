/* coverage_probe.cl — the coverage mode's device code (clhair/coverage.h, raster_core.h)
 * run on its own for the tests (tests/test_coverage.cpp); CLH_RASTER_COVER is 1 by default.
 *
 * coverage_probe_area: one work-item per pixel of a width x height grid writes the area of
 * one trapezoid (ax, ay, bx, by, wa, wb in trap_g) inside its pixel.
 * coverage_probe_segments: one work-item per segment (ax, ay, iza, bx, by, izb in seg_g)
 * draws it with the strand pass's coverage raster (clh_cover_segment: depth test, chained
 * layers, coverage plane) into a G-buffer of CLH_LAYER_COVERAGE + 1 planes; the strand's
 * width is width_px1 / z at each end, its word's styling w the segment's index / 63.
 * coverage_probe_insert: one work-item per word inserts words_g[i] into the three layers
 * of pixel 0 of a one-pixel G-buffer and adds coverage (i % 7) / 8 (the raster's two
 * writes, in whatever order the device runs the work-items).
 */
#ifndef CLH_RASTER_COVER
#define CLH_RASTER_COVER 1 /* the coverage raster is what this file probes */
#endif
#include "clhair/gpu_types.h"
#include "clhair/raster_core.h"

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_int64_extended_atomics : enable

__kernel void coverage_probe_area(__global const float* trap_g, uint width, uint height,
                                  __global float* area_g) {
  const uint x = (uint)get_global_id(0), y = (uint)get_global_id(1);
  if (x >= width || y >= height) return;
  clh_poly8 q;
  float area = 0.0f;
  if (clh_trapezoid(trap_g[0], trap_g[1], trap_g[2], trap_g[3], trap_g[4], trap_g[5], &q))
    area = clh_trapezoid_pixel_area(&q, (float)x, (float)y);
  area_g[(size_t)y * width + x] = area;
}

__kernel void coverage_probe_segments(__global const float* seg_g, uint count, uint width,
                                      uint height, float width_px1,
                                      __global const float* scene_depth_g, __global ulong* gbuf_g) {
  const uint i = (uint)get_global_id(0);
  if (i >= count) return;
  clh_raster_ctx rc;
  clh_raster_init(&rc, 1.0f, 1.0f, 0.0f, 0.0f, width, height, 0.0f, 100.0f, 1.0f, 0.0f);
  rc.width_px1 = width_px1;
  ClhRasterVertex v[2];
  for (int e = 0; e < 2; ++e) {
    const float iz = seg_g[6 * i + 3 * e + 2];
    v[e].sx = seg_g[6 * i + 3 * e];
    v[e].sy = seg_g[6 * i + 3 * e + 1];
    v[e].iz = iz;
    v[e].z = 1.0f / iz;
    v[e].x = v[e].sx * v[e].z;
    v[e].y = -v[e].sy * v[e].z;
    v[e].tx = 1.0f;
    v[e].ty = 0.0f;
    v[e].tz = 0.0f;
    v[e].ao = 1.0f;
    v[e].w = (float)(i % 64u) / 63.0f;
    v[e].u = 0.0f;
  }
  uint counts[4] = {0u, 0u, 0u, 0u};
  clh_cover_segment(&rc, scene_depth_g, gbuf_g, counts, &v[0], &v[1]);
}

__kernel void coverage_probe_insert(__global const ulong* words_g, uint count,
                                    __global ulong* gbuf_g) {
  const uint i = (uint)get_global_id(0);
  if (i >= count) return;
  clh_cover_insert(gbuf_g, 1u, 0u, words_g[i]);
  clh_cover_add(gbuf_g, 1u, 0u, (float)(i % 7u) / 8.0f);
}
