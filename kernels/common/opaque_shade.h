/* opaque_shade.h — the shading of every opaque surface (analytic spheres and planes in
 * opaque.cl, triangle meshes in mesh.cl), so they look alike under the same lights.
 *
 * Lambert: albedo / pi times the scene's point and directional lights (point lights fall
 * off with the squared distance), each scaled by its deep-opacity-map transmittance when
 * the light casts shadows (shadow.h: hair and the opaque scene both shadow the surface;
 * percentage-closer filtered unless the scene turns it off),
 * plus the ambient term: the environment's SH irradiance / pi when there is one, else the
 * constant ambient colour. Inputs: the world hit point `pos`, the unit normal `n` facing
 * the viewer, the albedo and the view depth `t` (the shadow lookup starts 1e-3 t off the
 * surface along n and compares the opaque shadow map with the tangent plane there, so a
 * surface does not shadow itself).
 */
#ifndef CLHAIR_OPAQUE_SHADE_H
#define CLHAIR_OPAQUE_SHADE_H

static inline float3 clh_opaque_shade(
    __global const ClhSceneGpu* scene_g, __global const ClhLightGpu* lights_g,
    __global const ClhShadowGpu* shadows_g, __global const float* shadow_opaque_g,
    __global const float* shadow_hair_g, __global const uint* shadow_opacity_g,
    __global const float* env_sh_g, float3 pos, float3 n, float3 albedo, float t) {
  const uint env_levels = scene_g->env_levels & ~CLH_ENV_VISIBLE;
  float3 radiance = env_levels > 0u ? albedo * clh_env_irradiance(env_sh_g, n) / CLH_PI
                                    : albedo * vload3(0, scene_g->ambient);
  uint nl = min(scene_g->light_count, (uint)CLH_MAX_LIGHTS);
  for (uint i = 0; i < nl; ++i) {
    float4 lp = vload4(0, lights_g[i].pos);
    float3 lc = vload3(0, lights_g[i].color);
    float3 l;
    float falloff = 1.0f;
    if (lp.w > 0.5f) {
      float3 d = lp.xyz - pos;
      float d2 = fmax(dot(d, d), 1e-8f);
      l = d * rsqrt(d2);
      falloff = 1.0f / d2;
    } else {
      l = normalize(lp.xyz);
    }
    float visibility = 1.0f;
    int slot = clh_light_shadow_slot(lights_g + i);
    if (slot >= 0 && slot < CLH_MAX_SHADOWS)
      visibility = clh_shadow_transmittance_opaque(shadows_g + slot, shadow_opaque_g, shadow_hair_g,
                                                   shadow_opacity_g, pos + n * (1e-3f * t), n);
    radiance += albedo * lc * (visibility * falloff * fmax(dot(n, l), 0.0f) / CLH_PI);
  }
  return radiance;
}

#endif /* CLHAIR_OPAQUE_SHADE_H */
