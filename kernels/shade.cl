/* shade.cl — deferred shading of the center G-buffer, one work-item per pixel.
 *
 * Decodes the 64-bit word (gpu_types.h), rebuilds the view-space position from the sample
 * position and the 24-bit depth, and shades with shade_placeholder: a PLACEHOLDER hair
 * model (Kajiya-Kay diffuse and specular, root-to-tip colour over w, times baked AO) that
 * the physically based hair BSDF will replace. With CLH_MSAA samples per pixel every
 * sample layer is shaded and the results averaged (the MSAA resolve). Output:
 * premultiplied RGBA, alpha = fraction of samples hit.
 */
#include "clhair/gpu_types.h"
#include "clh_math.h"
#include "shadow.h"
#include "env_lookup.h"

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable

#ifndef CLH_MSAA
#define CLH_MSAA 1
#endif

typedef struct {
  __global const ClhShadowGpu* params;
  __global const float* opaque;
  __global const float* hair;
  __global const uint* opacity;
  float lod_shift; /* -log(beta) of this groom's LOD pass (Lipp Eq. 8), or 0 */
  __global const float4* env_texels;
  __global const ClhEnvLevel* env_levels;
  __global const float* env_sh;
} shade_shadows;

static inline float3 shade_word(__global const ClhGroomGpu* groom_g, __global const ClhViewGpu* view_g,
                                 __global const ClhSceneGpu* scene_g,
                                 __global const ClhLightGpu* lights_g, shade_shadows sh, ulong word, float2 pixel) {
  float z = clh_depth_decode(clh_gbuf_depth(word), groom_g->depth_near, groom_g->depth_far);
  float3 pv = (float3)((pixel.x - view_g->cx) / view_g->fx * z, -(pixel.y - view_g->cy) / view_g->fy * z, z);
  clh_mat34 to_world = clh_load_mat34(view_g->view_to_world);
  float3 pos = clh_xform_point(to_world, pv);
  float tv[3];
  clh_oct_decode(clh_gbuf_oct(word), tv);
  float3 T = (float3)(tv[0], tv[1], tv[2]);
  float w = clh_unorm_value(clh_gbuf_w(word), 6u);
  float ao = clh_unorm_value(clh_gbuf_ao(word), 6u);
  float3 albedo = mix(vload3(0, groom_g->root_color), vload3(0, groom_g->tip_color), w);
  float3 V = normalize(vload3(0, view_g->eye) - pos);

  /* baked AO darkens the ambient (probe) light; shadowed lights have their own occlusion.
   * With an environment: SH irradiance at the fibre normal turned toward the viewer. */
  const uint env_levels = scene_g->env_levels & ~CLH_ENV_VISIBLE;
  const float3 n_view = clh_normalize_or(V - dot(V, T) * T, V);
  float3 radiance = (env_levels > 0u ? clh_env_irradiance(sh.env_sh, n_view) / CLH_PI : vload3(0, scene_g->ambient)) *
                    albedo * ao;
  uint nl = min(scene_g->light_count, (uint)CLH_MAX_LIGHTS);
  for (uint i = 0; i < nl; ++i) {
    float4 lp = vload4(0, lights_g[i].pos);
    float3 lc = vload3(0, lights_g[i].color);
    float3 L;
    float falloff = 1.0f;
    if (lp.w > 0.5f) {
      float3 d = lp.xyz - pos;
      float d2 = fmax(dot(d, d), 1e-8f);
      L = d * rsqrt(d2);
      falloff = 1.0f / d2;
    } else {
      L = normalize(lp.xyz);
    }
    int slot = clh_light_shadow_slot(lights_g + i);
    if (slot >= 0 && slot < CLH_MAX_SHADOWS)
      falloff *= clh_shadow_transmittance(sh.params + slot, sh.opaque, sh.hair, sh.opacity, pos, sh.lod_shift);
    float tl = dot(T, L);
    float diffuse = sqrt(fmax(1.0f - tl * tl, 0.0f));
    float3 H = normalize(L + V);
    float th = dot(T, H);
    float spec = pow(sqrt(fmax(1.0f - th * th, 0.0f)), 80.0f);
    radiance += lc * falloff * (albedo * diffuse * 0.6f + (float3)(0.12f * spec)) / CLH_PI;
  }
  return radiance;
}

__kernel void shade_placeholder(__global const ClhGroomGpu* groom_g,
                                __global const ClhViewGpu* view_g,
                                __global const ClhSceneGpu* scene_g,
                                __global const ClhLightGpu* lights_g,
                                __global const ClhShadowGpu* shadows_g, __global const float* shadow_opaque_g,
                                __global const float* shadow_hair_g, __global const uint* shadow_opacity_g,
                                __global const float4* env_texels_g, __global const ClhEnvLevel* env_levels_g,
                                __global const float* env_sh_g, __global const ulong* gbuf_g,
                                __global const uint* offsets_g, __global float4* hair_g) {
  uint x = (uint)get_global_id(0), y = (uint)get_global_id(1);
  uint width = view_g->width, height = view_g->height;
  if (x >= width || y >= height) return;
  size_t idx = (size_t)y * width + x;
  size_t plane = (size_t)width * height;
  shade_shadows sh;
  sh.params = shadows_g;
  sh.opaque = shadow_opaque_g;
  sh.hair = shadow_hair_g;
  sh.opacity = shadow_opacity_g;
  sh.env_texels = env_texels_g;
  sh.env_levels = env_levels_g;
  sh.env_sh = env_sh_g;
  /* Lipp Eq. 8 with beta the share of the hair's coverage this frame kept: the fraction
   * of the visible bundles' strands the LOD pass drew, times the widening that
   * compensated it (N / N_LOD, bounded by the widest hit band) at this pixel's depth */
  sh.lod_shift = 0.0f;
  const uint nb = groom_g->bundle_count;
  const float drawn = nb > 0u ? (float)offsets_g[nb] : 0.0f;
  const float visible = nb > 0u ? (float)offsets_g[nb + 1u] : 0.0f;
  const float beta = visible > 0.0f ? drawn / visible : 1.0f;
  const ulong w0 = gbuf_g[idx];
  if (groom_g->shadow_lod_correction != 0u && beta > 0.0f && beta < 1.0f && w0 != CLH_GBUF_EMPTY) {
    const float z = clh_depth_decode(clh_gbuf_depth(w0), groom_g->depth_near, groom_g->depth_far);
    const float width_px = fmax(view_g->fy * groom_g->strand_width / z, groom_g->hit_diameter_px);
    const float widen = fmin(1.0f / beta, CLH_MAX_HIT_DIAMETER / fmax(width_px, 1e-6f));
    const float kept = fmin(beta * fmax(widen, 1.0f), 1.0f);
    sh.lod_shift = -log(kept);
  }
  float3 sum = (float3)(0.0f);
  uint hits = 0u;
  for (uint s = 0; s < CLH_MSAA; ++s) {
    ulong word = gbuf_g[s * plane + idx];
    if (word == CLH_GBUF_EMPTY) continue;
    /* positions are rebuilt at the pixel center: the depth of every sample is stored */
    sum += shade_word(groom_g, view_g, scene_g, lights_g, sh, word, (float2)((float)x + 0.5f, (float)y + 0.5f));
    ++hits;
  }
  hair_g[idx] = (float4)(sum, (float)hits) / (float)CLH_MSAA;
}
