/* ao_field.h — the ambient occlusion of a groom without baked vertex AO (strand files), read
 * at the shaded point from the groom's AO field: the visibility of every voxel centre of a
 * density grid of its fibres (kernels/ao.cl, ao_field), interpolated trilinearly in the
 * groom's object space. The field's voxels lie on a grid one voxel wider than the hair on
 * every side, so a fibre's lookup never reads outside it; points outside are clamped to
 * the border voxels. */
#ifndef CLHAIR_AO_FIELD_H
#define CLHAIR_AO_FIELD_H

#include "clhair/gpu_types.h"

/* AO in [0, 1] at world position (px, py, pz), or 1 when the record has no field. */
static inline float clh_ao_field_at(__global const ClhVisibilityGpu* vis,
                                    __global const float* field_g, float px, float py, float pz) {
  if (vis->ao_dims[3] == 0u) return 1.0f;
  __global const float* m = vis->world_to_obj;
  const float ox = m[0] * px + m[1] * py + m[2] * pz + m[3];
  const float oy = m[4] * px + m[5] * py + m[6] * pz + m[7];
  const float oz = m[8] * px + m[9] * py + m[10] * pz + m[11];
  const float inv = 1.0f / vis->ao_lo[3];
  const int nx = (int)vis->ao_dims[0], ny = (int)vis->ao_dims[1], nz = (int)vis->ao_dims[2];
  /* voxel-centre coordinates */
  const float cx = clamp((ox - vis->ao_lo[0]) * inv - 0.5f, 0.0f, (float)(nx - 1));
  const float cy = clamp((oy - vis->ao_lo[1]) * inv - 0.5f, 0.0f, (float)(ny - 1));
  const float cz = clamp((oz - vis->ao_lo[2]) * inv - 0.5f, 0.0f, (float)(nz - 1));
  const int x0 = (int)cx, y0 = (int)cy, z0 = (int)cz;
  const int x1 = min(x0 + 1, nx - 1), y1 = min(y0 + 1, ny - 1), z1 = min(z0 + 1, nz - 1);
  const float fx = cx - (float)x0, fy = cy - (float)y0, fz = cz - (float)z0;
#define CLH_AO_AT(x, y, z) \
  field_g[((size_t)(z) * (size_t)ny + (size_t)(y)) * (size_t)nx + (size_t)(x)]
  const float c00 = mix(CLH_AO_AT(x0, y0, z0), CLH_AO_AT(x1, y0, z0), fx);
  const float c10 = mix(CLH_AO_AT(x0, y1, z0), CLH_AO_AT(x1, y1, z0), fx);
  const float c01 = mix(CLH_AO_AT(x0, y0, z1), CLH_AO_AT(x1, y0, z1), fx);
  const float c11 = mix(CLH_AO_AT(x0, y1, z1), CLH_AO_AT(x1, y1, z1), fx);
#undef CLH_AO_AT
  return clamp(mix(mix(c00, c10, fy), mix(c01, c11, fy), fz), 0.0f, 1.0f);
}

/* The radiance a fibre at world position (px, py, pz) sends toward the eye from the light
 * diffused through the groom (host/groom/diffusion_field.h: the three planes after the AO),
 * or 0 when the record's field has none. */
static inline clh_v3 clh_diffused_at(__global const ClhVisibilityGpu* vis,
                                     __global const float* field_g, float px, float py, float pz) {
  if ((vis->ao_dims[3] & 2u) == 0u) return clh_v3_splat(0.0f);
  __global const float* m = vis->world_to_obj;
  const float ox = m[0] * px + m[1] * py + m[2] * pz + m[3];
  const float oy = m[4] * px + m[5] * py + m[6] * pz + m[7];
  const float oz = m[8] * px + m[9] * py + m[10] * pz + m[11];
  const float inv = 1.0f / vis->ao_lo[3];
  const int nx = (int)vis->ao_dims[0], ny = (int)vis->ao_dims[1], nz = (int)vis->ao_dims[2];
  const float cx = clamp((ox - vis->ao_lo[0]) * inv - 0.5f, 0.0f, (float)(nx - 1));
  const float cy = clamp((oy - vis->ao_lo[1]) * inv - 0.5f, 0.0f, (float)(ny - 1));
  const float cz = clamp((oz - vis->ao_lo[2]) * inv - 0.5f, 0.0f, (float)(nz - 1));
  const int x0 = (int)cx, y0 = (int)cy, z0 = (int)cz;
  const int x1 = min(x0 + 1, nx - 1), y1 = min(y0 + 1, ny - 1), z1 = min(z0 + 1, nz - 1);
  const float fx = cx - (float)x0, fy = cy - (float)y0, fz = cz - (float)z0;
  const size_t plane = (size_t)nx * (size_t)ny * (size_t)nz;
  float rgb[3];
  for (int c = 0; c < 3; ++c) {
    __global const float* f = field_g + plane * (size_t)(c + 1);
#define CLH_DF_AT(x, y, z) f[((size_t)(z) * (size_t)ny + (size_t)(y)) * (size_t)nx + (size_t)(x)]
    const float c00 = mix(CLH_DF_AT(x0, y0, z0), CLH_DF_AT(x1, y0, z0), fx);
    const float c10 = mix(CLH_DF_AT(x0, y1, z0), CLH_DF_AT(x1, y1, z0), fx);
    const float c01 = mix(CLH_DF_AT(x0, y0, z1), CLH_DF_AT(x1, y0, z1), fx);
    const float c11 = mix(CLH_DF_AT(x0, y1, z1), CLH_DF_AT(x1, y1, z1), fx);
#undef CLH_DF_AT
    rgb[c] = fmax(mix(mix(c00, c10, fy), mix(c01, c11, fy), fz), 0.0f);
  }
  return clh_v3_make(rgb[0], rgb[1], rgb[2]);
}

#endif /* CLHAIR_AO_FIELD_H */
