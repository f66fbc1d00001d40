/* ao_field.h — the ambient occlusion of a groom without baked vertex AO (strand files), read
 * at the shaded point from the groom's AO field: the visibility of every voxel centre of a
 * density grid of its fibres (kernels/ao.cl, ao_field), interpolated trilinearly in the
 * groom's object space. The field's voxels lie on a grid one voxel wider than the hair on
 * every side, so a fibre's lookup never reads outside it; points outside are clamped to
 * the border voxels. With the light diffused through a strand file's groom
 * (host/groom/diffusion_field.h) the table holds three more planes, r, g, b, read at the
 * same voxels and weights (one clh_field_cell per shaded point). */
#ifndef CLHAIR_AO_FIELD_H
#define CLHAIR_AO_FIELD_H

#include "clhair/gpu_types.h"

/* The field's eight voxels around world position (px, py, pz) and the trilinear weights: the
 * point in the groom's object space, in voxel-centre coordinates clamped to the grid (all 0
 * when the record has no field: the lookups below then read nothing). */
typedef struct {
  size_t at[8]; /* x fastest: (x0,y0,z0) (x1,y0,z0) (x0,y1,z0) (x1,y1,z0), then z1 */
  float fx, fy, fz;
  size_t plane; /* voxels in one plane of the table */
} clh_field_cell;

static inline void clh_field_cell_to(clh_field_cell* c, __global const ClhVisibilityGpu* vis,
                                     float px, float py, float pz) {
  c->fx = c->fy = c->fz = 0.0f;
  c->plane = 0;
  for (int k = 0; k < 8; ++k) c->at[k] = 0;
  if (vis->ao_dims[3] == 0u) return;
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
  c->fx = cx - (float)x0;
  c->fy = cy - (float)y0;
  c->fz = cz - (float)z0;
  c->plane = (size_t)nx * (size_t)ny * (size_t)nz;
  const int xs[2] = {x0, x1}, ys[2] = {y0, y1}, zs[2] = {z0, z1};
  for (int k = 0; k < 8; ++k)
    c->at[k] = ((size_t)zs[k >> 2] * (size_t)ny + (size_t)ys[(k >> 1) & 1]) * (size_t)nx +
               (size_t)xs[k & 1];
}

/* Plane `p` of the table (0: the AO) interpolated at the cell. */
static inline float clh_field_value(__global const float* field_g, const clh_field_cell* c,
                                    uint p) {
  __global const float* f = field_g + c->plane * (size_t)p;
  const float c00 = mix(f[c->at[0]], f[c->at[1]], c->fx);
  const float c10 = mix(f[c->at[2]], f[c->at[3]], c->fx);
  const float c01 = mix(f[c->at[4]], f[c->at[5]], c->fx);
  const float c11 = mix(f[c->at[6]], f[c->at[7]], c->fx);
  return mix(mix(c00, c10, c->fy), mix(c01, c11, c->fy), c->fz);
}

/* AO in [0, 1] at the cell, or 1 when the record has no field. */
static inline float clh_ao_field_at(__global const ClhVisibilityGpu* vis,
                                    __global const float* field_g, const clh_field_cell* c) {
  if (vis->ao_dims[3] == 0u) return 1.0f;
  return clamp(clh_field_value(field_g, c, 0u), 0.0f, 1.0f);
}

/* The radiance a fibre at the cell sends toward the eye from the light diffused through the
 * groom (host/groom/diffusion_field.h: the three planes after the AO), or 0 when the
 * record's field has none. */
static inline clh_v3 clh_diffused_at(__global const ClhVisibilityGpu* vis,
                                     __global const float* field_g, const clh_field_cell* c) {
  if ((vis->ao_dims[3] & 2u) == 0u) return clh_v3_splat(0.0f);
  return clh_v3_make(fmax(clh_field_value(field_g, c, 1u), 0.0f),
                     fmax(clh_field_value(field_g, c, 2u), 0.0f),
                     fmax(clh_field_value(field_g, c, 3u), 0.0f));
}

#endif /* CLHAIR_AO_FIELD_H */
