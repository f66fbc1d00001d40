/* mesh.cl — opaque triangle meshes, drawn into the scene's depth buffer after opaque.cl's
 * analytic spheres and planes and before any hair, from the camera and from each shadowed
 * light.
 *
 * mesh_raster: one work-item per triangle. Its vertices go to view space; the triangle is
 * clipped against the near plane z = CLH_MESH_NEAR (at most a quad, drawn as two
 * triangles); each piece is scan-converted over its screen bounding box clipped to the
 * target, row by row over the span its edges allow (so a triangle larger than the screen
 * costs the pixels it covers, not its extent). A pixel is covered when its center is inside
 * all three edges; a center exactly on an edge belongs to one side only (a fixed rule on
 * the edge's direction, and each edge function evaluated from its lower endpoint so the two
 * triangles sharing it compute exactly opposite values): no cracks, no double coverage.
 * The depth is the exact view z of the triangle's plane along the pixel's center ray,
 * the quantity opaque_render writes for spheres and planes. The word
 * (float bits of z) << 32 | triangle index goes into words_g by 64-bit atom_min: z > 0, so
 * its bits order like the floats; the nearest triangle wins and ties go to the lower index,
 * whatever order the work-items run in (the technique of Schütz et al.'s compute
 * rasterizer, as in the hair G-buffer).
 *
 * mesh_resolve: one work-item per pixel. Where the winning triangle is nearer than the
 * depth already there (the analytic primitives, or INFINITY), writes its depth and, with
 * shade != 0, its colour: Lambert with the scene's lights, hair shadows and ambient
 * (opaque_shade.h, the same as spheres and planes), the normal interpolated from the
 * per-vertex normals at the hit's barycentric coordinates and turned toward the viewer.
 *
 * Buffers: verts_g / normals_g one float4 per vertex (world space), tris_g one uint4 per
 * triangle (three vertex indices, the instance index into colors_g), words_g one ulong per
 * pixel cleared to all ones. Every index read from a buffer is checked before use.
 */
#include "clhair/gpu_types.h"
#include "clh_math.h"
#include "shadow.h"
#include "env_lookup.h"
#include "opaque_shade.h"

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_int64_extended_atomics : enable

#ifndef CLH_MESH_NEAR
#define CLH_MESH_NEAR 1e-4f
#endif
#define CLH_MESH_EMPTY 0xFFFFFFFFFFFFFFFFul
#ifndef CLH_ATOMIC_LOAD_SKIP
#define CLH_ATOMIC_LOAD_SKIP 1 /* plain load before the atomic (DESIGN.md, Atomics) */
#endif

/* Edge function of the screen-space edge a -> b at p: > 0 left of the edge (y down).
 * Evaluated from the lexicographically smaller endpoint, so edge b -> a gives exactly the
 * negated value. */
static inline float mesh_edge(float2 a, float2 b, float2 p) {
  const bool swap = b.x < a.x || (b.x == a.x && b.y < a.y);
  const float2 u = swap ? b : a, v = swap ? a : b;
  const float e = (v.x - u.x) * (p.y - u.y) - (v.y - u.y) * (p.x - u.x);
  return swap ? -e : e;
}

/* A center exactly on an edge counts for the side where the edge runs this way; the
 * reversed edge (the neighbour's) then does not. */
static inline bool mesh_edge_owns(float2 a, float2 b) {
  return b.y < a.y || (b.y == a.y && b.x > a.x);
}

static inline bool mesh_inside(float e, bool owns) { return e > 0.0f || (e == 0.0f && owns); }

/* The near-plane crossing of segment p -> q, computed from the endpoint order only, so
 * both triangles sharing the edge get the same point. */
static inline float3 mesh_clip_point(float3 p, float3 q) {
  const bool swap = q.z < p.z || (q.z == p.z && (q.x < p.x || (q.x == p.x && q.y < p.y)));
  const float3 a = swap ? q : p, b = swap ? p : q;
  const float s = (CLH_MESH_NEAR - a.z) / (b.z - a.z);
  return (float3)(a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), CLH_MESH_NEAR);
}

static inline float2 mesh_project(__global const ClhViewGpu* view_g, float3 p) {
  return (float2)(view_g->cx + view_g->fx * p.x / p.z, view_g->cy - view_g->fy * p.y / p.z);
}

/* Scan-converts one screen triangle (any winding) whose depth is the plane
 * dot(plane.xyz, p) = plane.w in view space. */
static void mesh_draw(__global const ClhViewGpu* view_g, float2 a, float2 b, float2 c, float4 plane,
                      uint tri, __global ulong* words_g) {
  const float area = mesh_edge(a, b, c);
  if (!(fabs(area) > 0.0f)) return; /* degenerate, or NaN */
  if (area < 0.0f) {
    const float2 s = b;
    b = c;
    c = s;
  }
  const int w = (int)view_g->width, h = (int)view_g->height;
  /* pixel i has its center at i + 0.5: covered columns are ceil(min - 0.5) .. floor(max - 0.5) */
  const float minx = fmin(a.x, fmin(b.x, c.x)), maxx = fmax(a.x, fmax(b.x, c.x));
  const float miny = fmin(a.y, fmin(b.y, c.y)), maxy = fmax(a.y, fmax(b.y, c.y));
  if (!(maxx >= 0.0f && maxy >= 0.0f && minx <= (float)w && miny <= (float)h)) return;
  const int x0 = (int)fmax(ceil(minx - 0.5f), 0.0f),
            x1 = (int)fmin(floor(maxx - 0.5f), (float)(w - 1));
  const int y0 = (int)fmax(ceil(miny - 0.5f), 0.0f),
            y1 = (int)fmin(floor(maxy - 0.5f), (float)(h - 1));
  const bool oab = mesh_edge_owns(a, b), obc = mesh_edge_owns(b, c), oca = mesh_edge_owns(c, a);
  const float2 v[3] = {a, b, c};
  for (int y = y0; y <= y1; ++y) {
    const float py = (float)y + 0.5f;
    /* the row's span from the three edges (approximate: widened by a pixel, then every
     * pixel is tested exactly) */
    float lo = (float)x0, hi = (float)x1;
    for (int k = 0; k < 3; ++k) {
      const float2 p = v[k], q = v[(k + 1) % 3];
      const float dy = q.y - p.y;
      if (dy == 0.0f) continue;
      /* e(px) = (q.x - p.x)(py - p.y) - dy (px - p.x) >= 0 */
      const float cross_x = p.x + (q.x - p.x) * (py - p.y) / dy - 0.5f;
      if (dy < 0.0f)
        lo = fmax(lo, floor(cross_x) - 1.0f);
      else
        hi = fmin(hi, ceil(cross_x) + 1.0f);
    }
    if (!(lo <= hi)) continue;
    const float yn = -(py - view_g->cy) / view_g->fy;
    for (int x = (int)lo; x <= (int)hi; ++x) {
      const float2 pc = (float2)((float)x + 0.5f, py);
      if (!(mesh_inside(mesh_edge(a, b, pc), oab) && mesh_inside(mesh_edge(b, c, pc), obc) &&
            mesh_inside(mesh_edge(c, a, pc), oca)))
        continue;
      /* the plane's z along the center ray (xn, yn, 1) */
      const float xn = (pc.x - view_g->cx) / view_g->fx;
      const float denom = plane.x * xn + plane.y * yn + plane.z;
      const float z = plane.w / denom;
      if (!(z > 0.0f && z < INFINITY)) continue;
      const ulong word = ((ulong)as_uint(z) << 32) | (ulong)tri;
      const size_t idx = (size_t)y * (size_t)w + (size_t)x;
#if CLH_ATOMIC_LOAD_SKIP
      if (word >= words_g[idx]) continue;
#endif
      atom_min(words_g + idx, word);
    }
  }
}

__kernel void mesh_raster(__global const ClhViewGpu* view_g, __global const float4* verts_g,
                          __global const uint4* tris_g, uint tri_count, uint vert_count,
                          __global ulong* words_g) {
  const uint tri = (uint)get_global_id(0);
  if (tri >= tri_count) return;
  const uint4 t = tris_g[tri];
  if (t.x >= vert_count || t.y >= vert_count || t.z >= vert_count) return;
  const clh_mat34 w2v = clh_load_mat34(view_g->world_to_view);
  const float3 p[3] = {clh_xform_point(w2v, verts_g[t.x].xyz),
                       clh_xform_point(w2v, verts_g[t.y].xyz),
                       clh_xform_point(w2v, verts_g[t.z].xyz)};
  /* the plane through the unclipped triangle: clipping does not move it */
  const float3 n = cross(p[1] - p[0], p[2] - p[0]);
  const float4 plane = (float4)(n, dot(n, p[0]));
  /* near-plane clipping (Sutherland-Hodgman against one plane): up to four vertices */
  float3 poly[4];
  int count = 0;
  for (int k = 0; k < 3; ++k) {
    const float3 cur = p[k], nxt = p[(k + 1) % 3];
    const bool cin = cur.z >= CLH_MESH_NEAR, nin = nxt.z >= CLH_MESH_NEAR;
    if (cin && count < 4) poly[count++] = cur;
    if (cin != nin && count < 4) poly[count++] = mesh_clip_point(cur, nxt);
  }
  if (count < 3) return;
  float2 s[4];
  for (int k = 0; k < count; ++k) s[k] = mesh_project(view_g, poly[k]);
  mesh_draw(view_g, s[0], s[1], s[2], plane, tri, words_g);
  if (count == 4) mesh_draw(view_g, s[0], s[2], s[3], plane, tri, words_g);
}

__kernel void mesh_resolve(
    __global const ClhSceneGpu* scene_g, __global const ClhViewGpu* view_g,
    __global const float4* verts_g, __global const float4* normals_g, __global const uint4* tris_g,
    __global const float4* colors_g, uint tri_count, uint vert_count, uint color_count,
    __global const ClhLightGpu* lights_g, __global const ClhShadowGpu* shadows_g,
    __global const float* shadow_opaque_g, __global const float* shadow_hair_g,
    __global const uint* shadow_opacity_g, __global const float* env_sh_g,
    __global const ulong* words_g, __global float4* color_g, __global float* depth_g, uint shade) {
  const uint x = (uint)get_global_id(0), y = (uint)get_global_id(1);
  const uint width = view_g->width, height = view_g->height;
  if (x >= width || y >= height) return;
  const size_t idx = (size_t)y * width + x;
  const ulong word = words_g[idx];
  if (word == CLH_MESH_EMPTY) return;
  const uint tri = (uint)(word & 0xFFFFFFFFu);
  const float z = as_float((uint)(word >> 32));
  if (tri >= tri_count || !(z < depth_g[idx])) return;
  depth_g[idx] = z;
  if (shade == 0u) return;
  const uint4 t = tris_g[tri];
  if (t.x >= vert_count || t.y >= vert_count || t.z >= vert_count) return;
  /* the hit on the center ray, in world space (the ray has view z = 1 per unit) */
  const float3 dv = (float3)(((float)x + 0.5f - view_g->cx) / view_g->fx,
                             -((float)y + 0.5f - view_g->cy) / view_g->fy, 1.0f);
  const clh_mat34 to_world = clh_load_mat34(view_g->view_to_world);
  const float3 dir = clh_xform_dir(to_world, dv);
  const float3 pos = vload3(0, view_g->eye) + z * dir;
  const float3 a = verts_g[t.x].xyz, b = verts_g[t.y].xyz, c = verts_g[t.z].xyz;
  /* barycentric coordinates of pos (on the plane up to rounding), clamped to the triangle */
  const float3 e0 = b - a, e1 = c - a, ep = pos - a;
  const float d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1), dp0 = dot(ep, e0),
              dp1 = dot(ep, e1);
  const float det = d00 * d11 - d01 * d01;
  float wb = 0.0f, wc = 0.0f;
  if (fabs(det) > 0.0f) {
    wb = clamp((d11 * dp0 - d01 * dp1) / det, 0.0f, 1.0f);
    wc = clamp((d00 * dp1 - d01 * dp0) / det, 0.0f, 1.0f);
  }
  const float wa = fmax(1.0f - wb - wc, 0.0f);
  float3 face = cross(e0, e1);
  const float face_len = length(face);
  face = face_len > 0.0f ? face / face_len : -normalize(dir);
  if (dot(face, dir) > 0.0f) face = -face; /* two-sided: the side the camera sees */
  float3 n = wa * normals_g[t.x].xyz + wb * normals_g[t.y].xyz + wc * normals_g[t.z].xyz;
  const float n_len = length(n);
  n = n_len > 1e-12f ? n / n_len : face;
  if (dot(n, face) < 0.0f) n = -n;
  const float3 albedo = t.w < color_count ? colors_g[t.w].xyz : (float3)(0.5f);
  color_g[idx] =
      (float4)(clh_opaque_shade(scene_g, lights_g, shadows_g, shadow_opaque_g, shadow_hair_g,
                                shadow_opacity_g, env_sh_g, pos, n, albedo, z),
               1.0f);
}
