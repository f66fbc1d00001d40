/* shade.cl — deferred hair shading of the G-buffer, one work-item per pixel (Lipp §3.4).
 *
 * Each sample word is decoded (gpu_types.h): the view-space position is rebuilt from the
 * pixel center and the 24-bit depth, the tangent from its octahedral code, and the
 * shading parameters are queried once from the styling coordinates (u, v, w): melanin
 * blended from root to tip over w and varied per strand by a hash of (u, v) (or the
 * root/tip colours when the groom has no melanin), the groom's roughness, tilt and index.
 * The hair BSDF (kernels/common/hair_bsdf.h: R, TT, TRT and a diffuse term, fitted to
 * Chiang et al. 2016) is evaluated for every light, shadowed lights looking up their deep
 * opacity maps (Lipp's LOD depth correction applied). For those lights and for the probe
 * light the light scattered between fibres is added (dual scattering, Zinke et al. 2008,
 * hair_dual.h): the map's optical depth in front of the fibre and behind it give the light
 * forward-scattered through the hair and the light the hair behind sends back; the baked AO
 * gives the same for the probe. A strand file with file colours whose AO field holds the
 * light diffused through the groom (host/groom/diffusion_field.h: fibres that absorb little
 * pass the light round the groom) takes that instead of dual scattering for its mapped
 * lights: the map's unscattered light plus the field's. A strand file's colour is its fibres'
 * albedo (clh_hair_sigma_a_from_albedo). Probe lighting: the environment's prefiltered radiance
 * along the mirror direction about the view-facing fibre normal, with the GGX roughness and weight
 * that stand for R + TRT, and its SH irradiance at that normal (and at its opposite for TT) for the
 * diffuse part; without an environment the constant ambient lights the same energies. Probe light
 * is darkened by the baked AO (a strand file's: its AO field at the point, ao_field.h), the TT part
 * by its cube (the light from behind the fibre crosses the groom). Lights without a deep opacity
 * map are dimmed by the groom's baked spherical visibility when it has one (Kulikov 2025;
 * clhair/visibility_sh.h): exp(-absorption * events), events the clamped L1 SH of the word's (u, v,
 * w) cell toward the light, scaled by the share of fibres LOD kept. Where LOD drew a strand for a
 * cluster of 1/beta fibres, the lights are shaded with the aggregated BCSDF of Huang et al. 2024
 * (hair_bsdf.h) instead of the single-fibre one; probe lighting keeps the single fibre's energies.
 * With CLH_MSAA samples per pixel every sample layer is shaded and averaged (the MSAA
 * resolve). Output: premultiplied RGBA, alpha = fraction of samples hit.
 * Built with CLH_RASTER_COVER (the coverage mode, clhair/coverage.h) the pixel's alpha is
 * reconstructed from its additive coverage and its three depth-ordered layers are shaded
 * and combined front to back (the rule is at the end of shade_deferred).
 *
 * Cost (DESIGN.md, "Vectorizable kernels"): scalar arithmetic (clh_v3, clh_math.h) and the
 * straight-line functions of clhair/fast_math.h, no library calls besides sqrt; empty
 * pixels are skipped. PoCL 3.1 does not vectorize this kernel across pixels (its
 * work-item loop holds the BSDF's private state); the savings are in the BSDF itself.
 */
#include "clhair/gpu_types.h"
#include "clh_math.h"
#include "shadow.h"
#include "env_lookup.h"
#include "clhair/fast_math.h"
#include "visibility.h"
#include "ao_field.h"
#include "hair_bsdf.h"
#include "hair_aggregate.h"
#include "hair_dual.h"
#include "hair_env.h"
#include "clhair/coverage.h"

#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable

#ifndef CLH_MSAA
#define CLH_MSAA 1
#endif
#ifndef CLH_RASTER_COVER
#define CLH_RASTER_COVER 0
#endif
#if CLH_RASTER_COVER && CLH_MSAA != 1
#error "the coverage mode shades one sample per pixel"
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
  __global const ClhVisibilityGpu* vis; /* baked visibility of this groom instance */
  __global const float4* vis_sh;        /* its SH table, vis->cells cells */
  __global const float* ao_field;       /* its AO field (ao_field.h), when vis->ao_dims[3] */
  float vis_scale; /* share of the full groom's fibres this LOD pass keeps (ghost correction) */
  float cluster_k; /* fibres a drawn strand stands for (1: full detail, single-fibre BSDF) */
  float cluster_w; /* how many times a fibre's width it is drawn */
  float cluster_t; /* how many fibre widths deep it is along the view */
} shade_inputs;

/* The fibre material at styling coordinates (u, v, w). */
static inline void shade_material(__global const ClhGroomGpu* g, float u, float v, float w,
                                  clh_hair_material* m) {
  /* per-strand variation from the 6-bit root uv (the same for the whole strand) */
  const uint key = clh_hash2((uint)(u * 63.0f + 0.5f), (uint)(v * 63.0f + 0.5f) ^ g->seed);
  const float vary = 1.0f + g->look[0] * (2.0f * clh_u01(key) - 1.0f);
  if (g->look[1] > 0.5f) {
    const float eu = (g->melanin[0] + (g->melanin[1] - g->melanin[0]) * w) * vary;
    const float pheo = (g->melanin[2] + (g->melanin[3] - g->melanin[2]) * w) * vary;
    m->sigma_a = clh_hair_sigma_a_from_melanin(eu, pheo);
  } else {
    const clh_v3 c = clh_v3_make(g->root_color[0] + (g->tip_color[0] - g->root_color[0]) * w,
                                 g->root_color[1] + (g->tip_color[1] - g->root_color[1]) * w,
                                 g->root_color[2] + (g->tip_color[2] - g->root_color[2]) * w);
    m->sigma_a = clh_v3_scale(clh_hair_sigma_a_from_color(c, g->bsdf[1]), vary);
  }
  m->beta_m = g->bsdf[0];
  m->beta_n = g->bsdf[1];
  m->alpha = g->bsdf[2];
  m->eta = g->bsdf[3];
}

/* The radiance toward the eye of the fibre at world position `pos` whose shading inputs
 * (tangent, u, v, w, AO) are those of G-buffer word `word` (its depth bits are not read). */
static inline clh_v3 shade_at(__global const ClhGroomGpu* groom_g,
                              __global const ClhViewGpu* view_g,
                              __global const ClhSceneGpu* scene_g,
                              __global const ClhLightGpu* lights_g, const shade_inputs* in,
                              ulong word, clh_v3 pos) {
  float tv[3];
  clh_oct_decode(clh_gbuf_oct(word), tv);
  const clh_v3 T = clh_v3_make(tv[0], tv[1], tv[2]);
  const float u = clh_unorm_value(clh_gbuf_u(word), 6u), v = clh_unorm_value(clh_gbuf_v(word), 6u);
  const float w = clh_unorm_value(clh_gbuf_w(word), 6u);
  const bool file_color = groom_g->look[2] > 0.5f; /* u, v, AO fields hold rgb (gpu_types.h) */
  /* baked vertex AO, or (strand files) the groom's AO field at the point */
  /* the groom's AO field (and the light diffused through it) around the point, once */
  clh_field_cell field_cell;
  clh_field_cell_to(&field_cell, in->vis, pos.x, pos.y, pos.z);
  const float ao = (file_color ? 1.0f : clh_unorm_value(clh_gbuf_ao(word), 6u)) *
                   clh_ao_field_at(in->vis, in->ao_field, &field_cell);
  const clh_v3 to_eye =
      clh_v3_sub(clh_v3_make(view_g->eye[0], view_g->eye[1], view_g->eye[2]), pos);
  const clh_v3 V = clh_v3_unit(to_eye);

  clh_hair_material mat;
  shade_material(groom_g, u, v, w, &mat);
  clh_v3 fc = clh_v3_splat(1.0f);
  if (file_color) {
    /* a file's colour is the colour its fibres show under white light: the fibre's albedo */
    fc = clh_v3_make(clh_file_color_value(clh_gbuf_u(word)), clh_file_color_value(clh_gbuf_v(word)),
                     clh_file_color_value(clh_gbuf_ao(word)));
    mat.sigma_a = clh_hair_sigma_a_from_albedo(fc, groom_g->bsdf[3]);
  }
  clh_hair_view hv;
  clh_hair_prepare_to(&hv, &mat, T, V);
  /* light scattered between fibres (Zinke 2008, hair_dual.h) */
  const bool dual = (in->vis->shade_flags & CLH_SHADE_SINGLE_SCATTER) == 0u;
  clh_hair_dual ds;
  if (dual) clh_hair_dual_prepare_to(&ds, &hv);
  /* a LOD strand standing for a cluster: the aggregated BCSDF (Huang 2024, hair_bsdf.h) */
  const bool agg = in->cluster_k > 1.0f;
  clh_hair_agg ag;
  if (agg) clh_hair_agg_prepare_to(&ag, &hv, in->cluster_k, in->cluster_w, in->cluster_t);

  /* baked visibility: the cell of this word's styling codes (a file-colour groom's u, v
   * hold colour, so it has none); scaled down where LOD removed fibres */
  const bool use_vis = in->vis->enabled != 0u && !file_color;
  float4 vis_sh = (float4)(0.0f);
  if (use_vis) {
    const uint cell = clh_vis_cell(clh_gbuf_u(word), clh_gbuf_v(word), clh_gbuf_w(word));
    if (cell < in->vis->cells) vis_sh = in->vis_sh[cell] * in->vis_scale;
  }

  clh_v3 radiance = clh_v3_splat(0.0f);
  const bool diffused = dual && (in->vis->ao_dims[3] & 2u) != 0u;
  const uint nl = min(scene_g->light_count, (uint)CLH_MAX_LIGHTS);
  float map_t = 0.0f, maps = 0.0f; /* the mapped lights' transmittances at the point, summed */
  for (uint i = 0; i < nl; ++i) {
    __global const ClhLightGpu* light = lights_g + i;
    const clh_v3 lc = clh_v3_make(light->color[0], light->color[1], light->color[2]);
    const clh_v3 lpos = clh_v3_make(light->pos[0], light->pos[1], light->pos[2]);
    clh_v3 L;
    float falloff = 1.0f;
    if (light->pos[3] > 0.5f) { /* point light */
      const clh_v3 d = clh_v3_sub(lpos, pos);
      const float d2 = fmax(clh_v3_dot(d, d), 1e-8f);
      L = clh_v3_scale(d, 1.0f / sqrt(d2));
      falloff = 1.0f / d2;
    } else {
      L = clh_v3_unit(lpos);
    }
    const int slot = clh_light_shadow_slot(light);
    const bool mapped = slot >= 0 && slot < CLH_MAX_SHADOWS;
    float tau = 0.0f, tau_b = 0.0f;
    if (mapped && dual) {
      clh_shadow_depths_v3(in->params + slot, in->opaque, in->hair, in->opacity, pos, in->lod_shift,
                           &tau, &tau_b);
      map_t += tau > 0.0f ? clh_hair_exp(-tau) : 1.0f;
      maps += 1.0f;
    } else if (mapped)
      falloff *= clh_shadow_transmittance_v3(in->params + slot, in->opaque, in->hair, in->opacity,
                                             pos, in->lod_shift);
    else if (use_vis)
      falloff *= clh_vis_transmittance(in->vis, vis_sh, L);
    if (!(falloff > 0.0f) || tau >= 80.0f) continue;
    /* the aggregate: the cluster's fibres between the light and the shaded one are already in
     * a deep opacity map (drawn with the LOD's coverage) or a bake (of every fibre) */
    float sin_i, cos_i, cos_phi; /* the light's angles, for the single lobes and the dual term */
    clh_hair_angles_to(&hv, L, &sin_i, &cos_i, &cos_phi);
    clh_v3 f = agg ? clh_hair_agg_eval_cos(&hv, &ag, L, !(mapped || use_vis))
                   : clh_hair_eval_cos_at(&hv, sin_i, cos_i, cos_phi);
    /* a mapped light: what the map took away comes back through the fibres (dual scattering),
     * or, where the groom's field holds the light diffused through it, from the field */
    if (mapped && dual && diffused)
      f = clh_v3_scale(f, tau > 0.0f ? clh_hair_exp(-tau) : 1.0f);
    else if (mapped && dual)
      f = clh_hair_dual_eval_cos_at(&hv, &ds, sin_i, cos_i, cos_phi, f, tau, tau_b);
    radiance = clh_v3_add(radiance, clh_v3_scale(clh_v3_mul(lc, f), falloff));
  }

  /* probe lighting, darkened by the baked AO */
  clh_hair_env env;
  clh_hair_env_terms_to(&env, &hv);
  clh_v3 probe, probe_tt, uniform; /* the probe's light on R, TRT and the diffuse part; on
                                    * TT; and its mean radiance */
  const uint env_levels = scene_g->env_levels & ~CLH_ENV_VISIBLE;
  if (env_levels > 0u) {
    const float3 spec = clh_env_radiance(in->env_texels, in->env_levels, env_levels,
                                         clh_v3_f3(env.refl_dir), env.ggx_alpha);
    const float3 front = clh_env_irradiance(in->env_sh, clh_v3_f3(env.n)) / CLH_PI;
    const float3 back = clh_env_irradiance(in->env_sh, -clh_v3_f3(env.n)) / CLH_PI;
    probe = clh_v3_add(clh_v3_mul(env.spec_weight, clh_v3_from(spec)),
                       clh_v3_mul(env.diffuse_albedo, clh_v3_from(front)));
    probe_tt = clh_v3_mul(env.tt_weight, clh_v3_from(back));
    uniform = clh_v3_scale(clh_v3_add(clh_v3_from(front), clh_v3_from(back)), 0.5f);
  } else {
    uniform = clh_v3_make(scene_g->ambient[0], scene_g->ambient[1], scene_g->ambient[2]);
    probe = clh_v3_mul(uniform, clh_v3_add(env.spec_weight, env.diffuse_albedo));
    probe_tt = clh_v3_mul(uniform, env.tt_weight);
  }
  /* TT carries the light from behind the fibre as the camera sees it: through the rest of
   * the groom (and the head), where the sphere's mean visibility, the AO, says too little.
   * It is darkened by the AO cubed (DESIGN.md, "Hair the colour of hair": measured against
   * the path reference's single scattering of the ambient light). */
  clh_v3 out = clh_v3_add(
      radiance, clh_v3_add(clh_v3_scale(probe, ao), clh_v3_scale(probe_tt, ao * ao * ao)));
  /* the probe light the AO took away, given back by the hair around (dual scattering) */
  if (dual) {
    /* the AO refined by the maps at the point (clh_hair_dual_probe_ao) */
    const float ao_d = clh_hair_dual_probe_ao(ao, maps > 0.0f ? map_t / maps : -1.0f);
    if (ao_d < 1.0f) out = clh_v3_add(out, clh_v3_mul(uniform, clh_hair_dual_probe(&ds, ao_d)));
  }
  if (file_color) {
    /* The absorption above gives the fibre about its colour as albedo (within a few %, at
     * normal incidence); the lobes are scaled so that their energies at this view sum to it
     * exactly, so under uniform white light a fibre shows its colour. The path reference
     * scales its events the same way (host/groom/path_trace.cpp). */
    const clh_v3 albedo =
        clh_v3_add(clh_v3_add(hv.mass[0], hv.mass[1]), clh_v3_add(hv.mass[2], hv.mass[3]));
    out = clh_v3_mul(out, clh_v3_make(fc.x / fmax(albedo.x, 1e-4f), fc.y / fmax(albedo.y, 1e-4f),
                                      fc.z / fmax(albedo.z, 1e-4f)));
  }
  if (diffused) out = clh_v3_add(out, clh_diffused_at(in->vis, in->ao_field, &field_cell));
  return out;
}

/* shade_at for a sample word of pixel position (px, py): the position is rebuilt from the
 * pixel and the word's depth. */
static inline clh_v3 shade_word(__global const ClhGroomGpu* groom_g,
                                __global const ClhViewGpu* view_g,
                                __global const ClhSceneGpu* scene_g,
                                __global const ClhLightGpu* lights_g, const shade_inputs* in,
                                ulong word, float px, float py) {
  const float z = clh_depth_decode(clh_gbuf_depth(word), groom_g->depth_near, groom_g->depth_far);
  const clh_v3 pv =
      clh_v3_make((px - view_g->cx) / view_g->fx * z, -(py - view_g->cy) / view_g->fy * z, z);
  return shade_at(groom_g, view_g, scene_g, lights_g, in, word,
                  clh_v3_xform_point(view_g->view_to_world, pv));
}

/* The LOD terms of shade_inputs for a fibre at view depth z (z > 0), or for none (z <= 0:
 * full detail). Lipp Eq. 8 with beta the share of the hair's coverage this frame kept: the
 * fraction of the visible bundles' strands the LOD pass drew, times the widening that
 * compensated it (N / N_LOD, bounded by the widest hit band) at that depth. */
static inline void shade_lod(shade_inputs* in, __global const ClhGroomGpu* groom_g,
                             __global const ClhViewGpu* view_g,
                             __global const ClhVisibilityGpu* vis_g, __global const uint* offsets_g,
                             float z) {
  in->lod_shift = 0.0f;
  in->vis_scale = 1.0f;
  in->cluster_k = 1.0f;
  in->cluster_w = 1.0f;
  in->cluster_t = 1.0f;
  const uint nb = groom_g->bundle_count;
  const float drawn = nb > 0u ? (float)offsets_g[clh_lod_drawn_total_at(nb)] : 0.0f;
  const float visible = nb > 0u ? (float)offsets_g[clh_lod_visible_total_at(nb)] : 0.0f;
  const float beta = visible > 0.0f ? drawn / visible : 1.0f;
  if (!(beta > 0.0f && beta < 1.0f && z > 0.0f)) return;
  const float width_px = fmax(view_g->fy * groom_g->strand_width / z, groom_g->hit_diameter_px);
  const float widen = fmin(1.0f / beta, CLH_MAX_HIT_DIAMETER / fmax(width_px, 1e-6f));
  const float kept = fmin(beta * fmax(widen, 1.0f), 1.0f);
  if (groom_g->shadow_lod_correction != 0u) in->lod_shift = -0.693147181f * clh_fast_log2(kept);
  /* the bake counted every fibre; the fibres this pass left out and its widening did not
   * make up for no longer scatter (Kulikov's "ghosts"): fewer events in proportion */
  in->vis_scale = kept;
  if ((vis_g->shade_flags & CLH_SHADE_AGGREGATE) != 0u) {
    /* the k fibres cover the drawn width w side by side only when they lie k / w deep:
     * the cluster is as deep as the widening leaves its fibres (rho = 1) */
    in->cluster_k = 1.0f / beta;
    in->cluster_w = fmax(widen, 1.0f);
    in->cluster_t = fmax(in->cluster_k / in->cluster_w, 1.0f);
  }
}

/* The lighting inputs every shading kernel binds the same way. */
#define SHADE_PARAMS                                                                 \
  __global const ClhGroomGpu *groom_g, __global const ClhViewGpu *view_g,            \
      __global const ClhSceneGpu *scene_g, __global const ClhLightGpu *lights_g,     \
      __global const ClhShadowGpu *shadows_g, __global const float *shadow_opaque_g, \
      __global const float *shadow_hair_g, __global const uint *shadow_opacity_g,    \
      __global const float4 *env_texels_g, __global const ClhEnvLevel *env_levels_g, \
      __global const float *env_sh_g, __global const ClhVisibilityGpu *vis_g,        \
      __global const float4 *vis_sh_g, __global const float *ao_field_g

#define SHADE_INPUTS(in)         \
  shade_inputs in;               \
  in.params = shadows_g;         \
  in.opaque = shadow_opaque_g;   \
  in.hair = shadow_hair_g;       \
  in.opacity = shadow_opacity_g; \
  in.env_texels = env_texels_g;  \
  in.env_levels = env_levels_g;  \
  in.env_sh = env_sh_g;          \
  in.vis = vis_g;                \
  in.vis_sh = vis_sh_g;          \
  in.ao_field = ao_field_g

__kernel void shade_deferred(SHADE_PARAMS, __global const ulong* gbuf_g,
                             __global const uint* offsets_g, __global float4* hair_g) {
  const uint x = (uint)get_global_id(0), y = (uint)get_global_id(1);
  const uint width = view_g->width, height = view_g->height;
  if (x >= width || y >= height) return;
  const size_t idx = (size_t)y * width + x;
  const size_t plane = (size_t)width * height;
  SHADE_INPUTS(in);
  /* the LOD terms at this pixel's depth (its first sample's) */
  const ulong w0 = gbuf_g[idx];
  shade_lod(&in, groom_g, view_g, vis_g, offsets_g,
            w0 != CLH_GBUF_EMPTY
                ? clh_depth_decode(clh_gbuf_depth(w0), groom_g->depth_near, groom_g->depth_far)
                : 0.0f);

#if CLH_RASTER_COVER
  const uint nb = groom_g->bundle_count;
  const float drawn = nb > 0u ? (float)offsets_g[clh_lod_drawn_total_at(nb)] : 0.0f;
  const float visible = nb > 0u ? (float)offsets_g[clh_lod_visible_total_at(nb)] : 0.0f;
  const float beta = visible > 0.0f ? drawn / visible : 1.0f;
  /* The coverage mode. alpha: the additive coverage through the fitted curve. Each layer's
   * own coverage is estimated as min(1, its strand's projected width in pixels, widened as
   * the raster widened it for LOD) (the word has no room for the fragment's coverage), and
   * the layers are combined front to back with it: F = sum_k c_k a_k prod_{j<k} (1 - a_j),
   * A3 = 1 - prod_k (1 - a_k). When alpha <= A3 the pixel is F scaled by alpha / A3; else
   * the hair the three layers leave uncovered, alpha - A3, takes the deepest layer's
   * colour: F + (alpha - A3) c_last. */
  const float alpha = clh_cover_alpha(
      clh_cover_sum(((__global const uint*)(gbuf_g + (size_t)CLH_LAYER_COVERAGE * plane))[idx]));
  float fr = 0.0f, fg = 0.0f, fb = 0.0f, trans = 1.0f;
  clh_v3 last = clh_v3_splat(0.0f);
  for (uint k = 0; k < CLH_COVER_LAYERS; ++k) {
    const ulong word = gbuf_g[k * plane + idx];
    if (word == CLH_GBUF_EMPTY) break;
    const clh_v3 c =
        shade_word(groom_g, view_g, scene_g, lights_g, &in, word, (float)x + 0.5f, (float)y + 0.5f);
    const float z = clh_depth_decode(clh_gbuf_depth(word), groom_g->depth_near, groom_g->depth_far);
    const float wpx = view_g->fy * groom_g->strand_width / fmax(z, 1e-6f);
    const float widened = beta > 0.0f && beta < 1.0f ? wpx / beta : wpx;
    const float a = clamp(fmin(widened, CLH_MAX_HIT_DIAMETER), 1e-3f, 1.0f);
    fr += trans * a * c.x;
    fg += trans * a * c.y;
    fb += trans * a * c.z;
    trans *= 1.0f - a;
    last = c;
  }
  const float a3 = 1.0f - trans;
  float4 out = (float4)(0.0f);
  if (a3 > 0.0f && alpha > 0.0f) {
    if (alpha <= a3) {
      const float k = alpha / a3;
      out = (float4)(fr * k, fg * k, fb * k, alpha);
    } else {
      const float rest = alpha - a3;
      out = (float4)(fr + rest * last.x, fg + rest * last.y, fb + rest * last.z, alpha);
    }
  }
  hair_g[idx] = out;
#else
  float sr = 0.0f, sg = 0.0f, sb = 0.0f;
  uint hits = 0u;
  for (uint s = 0; s < CLH_MSAA; ++s) {
    const ulong word = gbuf_g[s * plane + idx];
    if (word == CLH_GBUF_EMPTY) continue;
    /* positions are rebuilt at the pixel center: the depth of every sample is stored */
    const clh_v3 c =
        shade_word(groom_g, view_g, scene_g, lights_g, &in, word, (float)x + 0.5f, (float)y + 0.5f);
    sr += c.x;
    sg += c.y;
    sb += c.z;
    ++hits;
  }
  hair_g[idx] = (float4)(sr, sg, sb, (float)hits) / (float)CLH_MSAA;
#endif
}

/* Per-point shading (DESIGN.md, "Shading once per visible strand point"): the marked
 * points of the groom listed by slot (points_g, written by the strand kernels' point pass),
 * each shaded once at its own position into colors_g. The count is on the device (the
 * total after the ranks of kernels/points.cl, ranks_g[words]); the grid walks the slots in
 * steps of its size. */
__kernel void shade_points(SHADE_PARAMS, __global const uint* offsets_g,
                           __global const ClhPointGpu* points_g, __global const uint* ranks_g,
                           uint words, uint capacity, __global float4* colors_g) {
  const uint n = min(ranks_g[words], capacity);
  for (uint i = (uint)get_global_id(0); i < n; i += (uint)get_global_size(0)) {
    const ClhPointGpu p = points_g[i];
    SHADE_INPUTS(in);
    shade_lod(&in, groom_g, view_g, vis_g, offsets_g, p.pos[3]);
    const ulong word = ((ulong)p.word_hi << 32) | (ulong)p.word_lo;
    const clh_v3 c = shade_at(groom_g, view_g, scene_g, lights_g, &in, word,
                              clh_v3_make(p.pos[0], p.pos[1], p.pos[2]));
    colors_g[i] = (float4)(c.x, c.y, c.z, 1.0f);
  }
}
