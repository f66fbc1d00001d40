/* opaque.cl — the opaque scene: analytic spheres and planes ray cast per pixel.
 *
 * Writes the render target's linear colour (float4, alpha 1) and view-space depth (the
 * z of the hit in camera space, +INFINITY for background) that the hair passes test
 * against and composite over. Lambert shading with the scene's point and directional
 * lights plus a constant ambient term; shadowed lights look up their deep opacity maps,
 * so hair and opaque objects shadow the opaque scene. With shade = 0 only the depth is
 * written (the opaque scene seen from a light). Triangle meshes are drawn over this
 * result by mesh.cl with the same shading (opaque_shade.h). With an environment, the ambient term
 * is its SH irradiance and a visible environment replaces the background colour; a background
 * image, when given, is stretched over the frame behind everything.
 */
#include "clhair/gpu_types.h"
#include "clh_math.h"
#include "shadow.h"
#include "env_lookup.h"
#include "opaque_shade.h"

/* Nearest hit along origin + t * dir (t > 0); returns t or INFINITY, normal and albedo. */
static inline float opaque_trace(__global const ClhSceneGpu* scene_g,
                                 __global const ClhSphereGpu* spheres_g,
                                 __global const ClhPlaneGpu* planes_g, float3 origin, float3 dir,
                                 float3* normal, float3* albedo) {
  float best = INFINITY;
  for (uint i = 0; i < scene_g->sphere_count; ++i) {
    float4 c = vload4(0, spheres_g[i].center);
    float3 oc = origin - c.xyz;
    float b = dot(oc, dir);
    float a = dot(dir, dir);
    float disc = b * b - a * (dot(oc, oc) - c.w * c.w);
    if (disc < 0.0f) continue;
    float sq = sqrt(disc);
    float t = (-b - sq) / a;
    if (t <= 0.0f) t = (-b + sq) / a;
    if (t > 0.0f && t < best) {
      best = t;
      *normal = normalize(oc + t * dir);
      *albedo = vload3(0, spheres_g[i].color);
    }
  }
  for (uint i = 0; i < scene_g->plane_count; ++i) {
    float4 p = vload4(0, planes_g[i].normal);
    float denom = dot(p.xyz, dir);
    if (fabs(denom) < 1e-12f) continue;
    float t = (p.w - dot(p.xyz, origin)) / denom;
    if (t > 0.0f && t < best) {
      best = t;
      *normal = denom < 0.0f ? p.xyz : -p.xyz;
      *albedo = vload3(0, planes_g[i].color);
    }
  }
  return best;
}

__kernel void opaque_render(
    __global const ClhSceneGpu* scene_g, __global const ClhViewGpu* view_g,
    __global const ClhSphereGpu* spheres_g, __global const ClhPlaneGpu* planes_g,
    __global const ClhLightGpu* lights_g, __global const ClhShadowGpu* shadows_g,
    __global const float* shadow_opaque_g, __global const float* shadow_hair_g,
    __global const uint* shadow_opacity_g, __global const float4* env_texels_g,
    __global const ClhEnvLevel* env_levels_g, __global const float* env_sh_g,
    __global const float4* background_g, __global float4* color_g, __global float* depth_g,
    uint shade) {
  uint x = (uint)get_global_id(0), y = (uint)get_global_id(1);
  uint width = view_g->width, height = view_g->height;
  if (x >= width || y >= height) return;
  size_t idx = (size_t)y * width + x;
  /* view-space ray with z = 1, so the hit distance t is the view depth */
  float3 dv = (float3)(((float)x + 0.5f - view_g->cx) / view_g->fx,
                       -((float)y + 0.5f - view_g->cy) / view_g->fy, 1.0f);
  clh_mat34 to_world = clh_load_mat34(view_g->view_to_world);
  float3 origin = vload3(0, view_g->eye);
  float3 dir = clh_xform_dir(to_world, dv);
  float3 n = (float3)(0.0f, 1.0f, 0.0f), albedo = (float3)(0.0f);
  float t = opaque_trace(scene_g, spheres_g, planes_g, origin, dir, &n, &albedo);
  const uint env_levels = scene_g->env_levels & ~CLH_ENV_VISIBLE;
  if (!(t < INFINITY)) {
    float3 bg = vload3(0, scene_g->background);
    if (shade != 0u && env_levels > 0u && (scene_g->env_levels & CLH_ENV_VISIBLE) != 0u)
      bg = clh_env_radiance(env_texels_g, env_levels_g, env_levels, normalize(dir), 0.0f);
    if (shade != 0u && scene_g->bg_width > 0u && scene_g->bg_height > 0u) {
      /* the background image stretched over the frame, bilinear, clamped at the borders */
      const int bw = (int)scene_g->bg_width, bh = (int)scene_g->bg_height;
      const float u = ((float)x + 0.5f) / (float)width * (float)bw - 0.5f;
      const float v = ((float)y + 0.5f) / (float)height * (float)bh - 0.5f;
      const float fu = floor(u), fv = floor(v);
      const int x0 = clamp((int)fu, 0, bw - 1), x1 = clamp((int)fu + 1, 0, bw - 1);
      const int y0 = clamp((int)fv, 0, bh - 1), y1 = clamp((int)fv + 1, 0, bh - 1);
      const float ax = u - fu, ay = v - fv;
      const float3 t0 =
          mix(background_g[(size_t)y0 * bw + x0].xyz, background_g[(size_t)y0 * bw + x1].xyz, ax);
      const float3 t1 =
          mix(background_g[(size_t)y1 * bw + x0].xyz, background_g[(size_t)y1 * bw + x1].xyz, ax);
      bg = mix(t0, t1, ay);
    }
    color_g[idx] = (float4)(bg, 1.0f);
    depth_g[idx] = INFINITY;
    return;
  }
  depth_g[idx] = t;
  if (shade == 0u) return;
  float3 pos = origin + t * dir;
  color_g[idx] =
      (float4)(clh_opaque_shade(scene_g, lights_g, shadows_g, shadow_opaque_g, shadow_hair_g,
                                shadow_opacity_g, env_sh_g, pos, n, albedo, t),
               1.0f);
}
