/* ao.cl — ambient occlusion baked per hair-mesh vertex (Lipp et al. 2026 §3.4), once per
 * groom, in object space.
 *
 * ao_voxelize: the generated strands (points_g: CLH_MAX_CONTROL_POINTS float4 per strand,
 *   counts_g points per strand) deposit their fibre length into a density grid; one
 *   work-item per (strand, segment). Each voxel accumulates length * scale in fixed
 *   point (AO_FIXED), scale = strand width * strands represented per generated strand /
 *   voxel volume, so a voxel ends with the extinction coefficient sigma_t = fibre length
 *   per volume * fibre diameter (Beer-Lambert for randomly oriented fibres).
 * ao_field: the same visibility at every voxel centre, for grooms without layer vertices
 *   (strand files; the density is splatted on the host, host/groom/ao_field.cpp).
 * ao_bake: per hair-mesh vertex, AO_DIRS directions on a spherical Fibonacci set; along
 *   each, the optical depth through the grid (steps of half a voxel, from a voxel away)
 *   gives exp(-tau), and a ray that meets the scalp (the root-layer faces, each as two
 *   triangles) is fully blocked; from a root vertex itself every ray below the scalp
 *   (against the direction its hair grows) enters the head and is blocked. AO is the
 *   mean visibility, 1 = open.
 */
#include "clhair/gpu_types.h"
#include "clh_math.h"

#ifndef AO_DIRS
#define AO_DIRS 64
#endif
#define AO_FIXED 4096.0f

typedef struct {
  float4 lo;  /* grid origin (object space), w: voxel size */
  uint4 dims; /* voxels per axis, w unused */
} ao_grid;

static inline int ao_voxel(ao_grid g, float3 p, int3* v) {
  float3 c = (p - g.lo.xyz) / g.lo.w;
  int3 i = convert_int3(floor(c));
  *v = i;
  return i.x >= 0 && i.y >= 0 && i.z >= 0 && i.x < (int)g.dims.x && i.y < (int)g.dims.y &&
         i.z < (int)g.dims.z;
}

/* Zeroes the density grid (a kernel, so checkers see the words as written). */
__kernel void ao_clear(__global uint* density_g, uint cells) {
  const uint i = (uint)get_global_id(0);
  if (i < cells) density_g[i] = 0u;
}

__kernel void ao_voxelize(__global const float4* points_g, __global const uint* counts_g,
                          uint strands, float4 grid_lo, uint4 grid_dims, float scale,
                          __global uint* density_g) {
  const size_t gid = get_global_id(0);
  const size_t strand = gid / CLH_MAX_CONTROL_POINTS, k = gid % CLH_MAX_CONTROL_POINTS;
  if (strand >= strands) return;
  const uint count = min(counts_g[strand], (uint)CLH_MAX_CONTROL_POINTS);
  if (k + 1u >= count) return;
  const float3 a = points_g[strand * CLH_MAX_CONTROL_POINTS + k].xyz;
  const float3 b = points_g[strand * CLH_MAX_CONTROL_POINTS + k + 1u].xyz;
  ao_grid g;
  g.lo = grid_lo;
  g.dims = grid_dims;
  int3 v;
  if (!ao_voxel(g, 0.5f * (a + b), &v)) return;
  const uint add = (uint)(length(b - a) * scale * AO_FIXED + 0.5f);
  if (add > 0u)
    atomic_add(density_g + ((size_t)v.z * g.dims.y + (size_t)v.y) * g.dims.x + (size_t)v.x, add);
}

/* Optical depth through the hair from p along unit d, starting a voxel away from p itself
 * (steps of half a voxel until the ray leaves the grid). */
static inline float ao_optical_depth(ao_grid g, __global const uint* density_g, float3 p,
                                     float3 d) {
  const float voxel = g.lo.w;
  const float extent = voxel * (float)max(max(g.dims.x, g.dims.y), g.dims.z);
  const float step = 0.5f * voxel;
  float tau = 0.0f;
  for (float t = voxel; t < extent; t += step) {
    int3 v;
    if (!ao_voxel(g, p + d * t, &v)) {
      if (t > 2.0f * voxel) break; /* left the grid */
      continue;
    }
    tau += (float)density_g[((size_t)v.z * g.dims.y + (size_t)v.y) * g.dims.x + (size_t)v.x] *
           (1.0f / AO_FIXED) * step;
  }
  return tau;
}

/* Spherical Fibonacci direction k of AO_DIRS. */
static inline float3 ao_direction(uint k) {
  const float z = 1.0f - (2.0f * (float)k + 1.0f) / (float)AO_DIRS;
  const float r = sqrt(fmax(0.0f, 1.0f - z * z));
  const float phi = (float)k * 2.39996322972865332f;
  return (float3)(r * cos(phi), z, r * sin(phi));
}

/* Ray-triangle distance (Moller-Trumbore), or INFINITY. */
static inline float ao_triangle(float3 o, float3 d, float3 a, float3 b, float3 c) {
  const float3 e1 = b - a, e2 = c - a;
  const float3 p = cross(d, e2);
  const float det = dot(e1, p);
  if (fabs(det) < 1e-14f) return INFINITY;
  const float inv = 1.0f / det;
  const float3 s = o - a;
  const float u = dot(s, p) * inv;
  if (u < 0.0f || u > 1.0f) return INFINITY;
  const float3 q = cross(s, e1);
  const float w = dot(d, q) * inv;
  if (w < 0.0f || u + w > 1.0f) return INFINITY;
  const float t = dot(e2, q) * inv;
  return t > 0.0f ? t : INFINITY;
}

__kernel void ao_bake(__global const ClhMeshVertex* verts_g, uint vertex_total,
                      __global const ClhBundle* bundles_g, uint bundle_count, uint root_vertices,
                      float4 grid_lo, uint4 grid_dims, __global const uint* density_g,
                      __global float* ao_g) {
  const uint vi = (uint)get_global_id(0);
  if (vi >= vertex_total) return;
  ao_grid g;
  g.lo = grid_lo;
  g.dims = grid_dims;
  const float voxel = grid_lo.w;
  const float3 p = vload3(0, verts_g[vi].pos);
  const bool on_scalp = vi < root_vertices && vertex_total > root_vertices;
  const float3 grow = on_scalp ? clh_normalize_or(vload3(0, verts_g[vi + root_vertices].pos) - p,
                                                  (float3)(0.0f, 1.0f, 0.0f))
                               : (float3)(0.0f);
  float visible = 0.0f;
  for (uint k = 0; k < AO_DIRS; ++k) {
    const float3 d = ao_direction(k);
    /* the scalp blocks the ray */
    if (on_scalp && dot(d, grow) < 0.0f) continue;
    float blocked = INFINITY;
    const float eps = 1e-3f * voxel;
    for (uint b = 0; b < bundle_count; ++b) {
      const int4 vtx = vload4(0, bundles_g[b].vtx);
      const float3 a = vload3(0, verts_g[clamp(vtx.x, 0, (int)root_vertices - 1)].pos);
      const float3 bb = vload3(0, verts_g[clamp(vtx.y, 0, (int)root_vertices - 1)].pos);
      const float3 c = vload3(0, verts_g[clamp(vtx.z, 0, (int)root_vertices - 1)].pos);
      const float3 e = vload3(0, verts_g[clamp(vtx.w, 0, (int)root_vertices - 1)].pos);
      blocked = fmin(blocked, ao_triangle(p + d * eps, d, a, bb, c));
      blocked = fmin(blocked, ao_triangle(p + d * eps, d, a, c, e));
    }
    if (blocked < INFINITY) continue;
    visible += exp(-ao_optical_depth(g, density_g, p, d));
  }
  ao_g[vi] = visible / (float)AO_DIRS;
}

/* The AO of every voxel centre (strand files, which have no layer vertices; the shading
 * looks it up trilinearly at the shaded point, kernels/common/ao_field.h): the directions
 * and the march of ao_bake, without a scalp. A voxel with no hair within one voxel of it
 * is never read by a lookup at a fibre and is left open (1). */
__kernel void ao_field(float4 grid_lo, uint4 grid_dims, __global const uint* density_g,
                       __global float* ao_g) {
  const size_t cells = (size_t)grid_dims.x * grid_dims.y * grid_dims.z;
  const size_t i = get_global_id(0);
  if (i >= cells) return;
  ao_grid g;
  g.lo = grid_lo;
  g.dims = grid_dims;
  const int x = (int)(i % grid_dims.x), y = (int)((i / grid_dims.x) % grid_dims.y),
            z = (int)(i / ((size_t)grid_dims.x * grid_dims.y));
  uint near_hair = 0u;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int3 v = (int3)(x + dx, y + dy, z + dz);
        if (v.x >= 0 && v.y >= 0 && v.z >= 0 && v.x < (int)g.dims.x && v.y < (int)g.dims.y &&
            v.z < (int)g.dims.z)
          near_hair |= density_g[((size_t)v.z * g.dims.y + (size_t)v.y) * g.dims.x + (size_t)v.x];
      }
  if (near_hair == 0u) {
    ao_g[i] = 1.0f;
    return;
  }
  const float3 p = grid_lo.xyz + ((float3)((float)x, (float)y, (float)z) + 0.5f) * grid_lo.w;
  float visible = 0.0f;
  for (uint k = 0; k < AO_DIRS; ++k)
    visible += exp(-ao_optical_depth(g, density_g, p, ao_direction(k)));
  ao_g[i] = visible / (float)AO_DIRS;
}
