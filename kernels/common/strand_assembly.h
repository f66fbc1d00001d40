/* strand_assembly.h — one hair-mesh strand assembled by its work-group (strands.cl's kernels,
 * strands_store among them): the lane's share of the strand after assembly
 * (clh_lane_span), the cooperative assembly itself (clh_assemble_strand: layers sampled at
 * the root, styled control points, tangents; strands.cl's header describes it), the
 * lookup of the strand a work-group draws (clh_strand_job, and clh_stored_job for a still's
 * stored strands) and the write of a lane's run (clh_write_lane).
 *
 * Include after gpu_types.h, subgroup.h, clh_math.h, fast_math.h, hair_style.h, raster.h and
 * strand_common.h. Every lane must call clh_assemble_strand (it exchanges with its
 * neighbours and synchronises the group).
 */
#ifndef CLHAIR_STRAND_ASSEMBLY_H
#define CLHAIR_STRAND_ASSEMBLY_H

#define CLH_PTS_PER_LANE ((CLH_MAX_CONTROL_POINTS - 1 + SG_SIZE - 1) / SG_SIZE)
#define CLH_PTS_CAP (CLH_PTS_PER_LANE + 1)
#define CLH_LAYERS_PER_LANE ((CLH_MAX_LAYERS + SG_SIZE - 1) / SG_SIZE)

/* The lane's share of the strand after assembly. */
typedef struct {
  uint C;        /* control points of the strand */
  uint first;    /* index of the lane's first point */
  uint count;    /* points the lane owns */
  float4 next_p; /* point first+count (position, styling w), from the next lane */
  float4 next_t; /* its final tangent (xyz, ambient occlusion in w) */
  float2 uv;     /* the strand's root styling coordinates */
} clh_lane_span;

/* Tangent k of the fine level from raw points in local memory (central differences, the
 * reflection rule at the ends). */
static inline float3 clh_fine_tangent(SG_SHARED const float4* pts_l, uint k, uint C) {
  if (k > 0u && k + 1u < C) return clh_normalize_or(pts_l[k + 1u].xyz - pts_l[k - 1u].xyz, CLH_UP);
  if (k == 0u) {
    float3 q = clh_normalize_or(pts_l[1].xyz - pts_l[0].xyz, CLH_UP);
    float3 t1 = C > 2u ? clh_normalize_or(pts_l[2].xyz - pts_l[0].xyz, q) : q;
    return clh_normalize_or(clh_end_tangent(q, t1), q);
  }
  float3 q = clh_normalize_or(pts_l[C - 1u].xyz - pts_l[C - 2u].xyz, CLH_UP);
  float3 tm = C > 2u ? clh_normalize_or(pts_l[C - 1u].xyz - pts_l[C - 3u].xyz, q) : q;
  return clh_normalize_or(clh_end_tangent(q, tm), q);
}

/* Tangent of the coarse level (the even points) at even index e. */
static inline float3 clh_coarse_tangent(SG_SHARED const float4* pts_l, uint e, uint C) {
  if (e > 0u && e + 1u < C) return clh_normalize_or(pts_l[e + 2u].xyz - pts_l[e - 2u].xyz, CLH_UP);
  if (e == 0u) {
    float3 q = clh_normalize_or(pts_l[2].xyz - pts_l[0].xyz, CLH_UP);
    float3 t1 = C > 3u ? clh_normalize_or(pts_l[4].xyz - pts_l[0].xyz, q) : q;
    return clh_normalize_or(clh_end_tangent(q, t1), q);
  }
  float3 q = clh_normalize_or(pts_l[C - 1u].xyz - pts_l[C - 3u].xyz, CLH_UP);
  float3 tm = C > 3u ? clh_normalize_or(pts_l[C - 1u].xyz - pts_l[C - 5u].xyz, q) : q;
  return clh_normalize_or(clh_end_tangent(q, tm), q);
}

/* Cooperative assembly of one strand. Every lane must call it. */
static inline void clh_assemble_strand(sg_ctx* sg, SG_SHARED clh_layer_pt* layers_l,
                                       SG_SHARED clh_strand* strand_l, SG_SHARED float4* pts_l,
                                       __global const ClhGroomGpu* g, __global const ClhBundle* b,
                                       __global const ClhMeshVertex* verts_g,
                                       __global const float2* roots_quad_g,
                                       __global const float2* roots_tri_g, uint bundle,
                                       uint local_index, uint C, float gamma, float4* P, float4* T,
                                       clh_lane_span* span) {
  const uint lane = sg_lane();
  const uint layer_count = clamp(g->layer_count, 2u, (uint)CLH_MAX_LAYERS);
  const int4 vtx = vload4(0, b->vtx);
  const uint root = min(local_index, g->root_set_size - 1u);
  const float2 st = b->triangle ? roots_tri_g[root] : roots_quad_g[root];
  /* the strand's constants are the same for every lane: lane 0 computes them once */
  if (lane == 0u) *strand_l = clh_strand_setup(g, b, bundle, local_index, st);

  /* ---- pass 1: the strand's sample on every layer -------------------------------- */
  const uint SL = (layer_count + SG_SIZE - 1u) / SG_SIZE;
  const uint lfirst = lane * SL;
  const uint lcount = lfirst < layer_count ? min(SL, layer_count - lfirst) : 0u;
  clh_layer_pt lay[CLH_LAYERS_PER_LANE];
  for (uint i = 0; i < CLH_LAYERS_PER_LANE; ++i) {
    if (i < lcount) {
      lay[i] = clh_bundle_layer(verts_g, vtx, lfirst + i, g->vertex_count, st);
    } else {
      lay[i].pos = lay[i].tan = lay[i].du = lay[i].dv = (float4)(0.0f);
    }
  }
  const float4 lay_last = lay[lcount > 0u ? lcount - 1u : 0u].pos;
  const float4 lay_prev = sg_shuffle_up1_f4(sg, lay_last, (float4)(0.0f));
  const float4 lay_next = sg_shuffle_down1_f4(sg, lay[0].pos, (float4)(0.0f));
  for (uint i = 0; i < CLH_LAYERS_PER_LANE; ++i) {
    if (i < lcount) {
      uint l = lfirst + i;
      if (g->has_tangents == 0u) {
        float3 prev = (i > 0u ? lay[i - 1u].pos : lay_prev).xyz;
        float3 next = (i + 1u < lcount ? lay[i + 1u].pos : lay_next).xyz;
        float3 cur = lay[i].pos.xyz;
        float3 m = (l == 0u)                 ? next - cur
                   : (l == layer_count - 1u) ? cur - prev
                                             : 0.5f * (next - prev);
        lay[i].tan.xyz = m;
      }
      layers_l[l] = lay[i];
    }
  }
  sg_barrier();
  const clh_strand s = *strand_l;

  /* ---- pass 2: styled control points ---------------------------------------------- */
  const uint S = (C - 1u + SG_SIZE - 1u) / SG_SIZE;
  const uint first = lane * S;
  const uint end = (lane == (uint)(SG_SIZE - 1)) ? C : min(first + S, C);
  const uint count = end > first ? min(end - first, (uint)CLH_PTS_CAP) : 0u;
  float ao[CLH_PTS_CAP];
  clh_noise_knots knots;
  clh_noise_knots_init(&knots);
  for (uint i = 0; i < CLH_PTS_CAP; ++i) {
    P[i] = (float4)(0.0f);
    T[i] = (float4)(0.0f);
    ao[i] = 1.0f;
    if (i < count) {
      float3 deriv, du, dv;
      float4 base =
          clh_base_point(layers_l, layer_count, first + i, C, s.length, &deriv, &du, &dv, &ao[i]);
      P[i] = (float4)(base.xyz + clh_style_offset(g, &s, base.w, deriv, du, dv, &knots), base.w);
    }
  }

  float4 next_p;
  if (gamma > 0.0f) {
    /* vertex-LOD transition: raw points through local memory, then the morphed positions
     * (Eq. 11-12) and tangents blended between this level and the coarser one */
    for (uint i = 0; i < CLH_PTS_CAP; ++i)
      if (i < count) pts_l[first + i] = P[i];
    sg_barrier();
    for (uint i = 0; i < CLH_PTS_CAP; ++i) {
      uint k = first + i;
      if (i < count) {
        float3 fine = clh_fine_tangent(pts_l, k, C);
        float3 coarse;
        if ((k & 1u) == 0u) {
          coarse = clh_coarse_tangent(pts_l, k, C);
        } else {
          coarse = clh_normalize_or(
              clh_coarse_tangent(pts_l, k - 1u, C) + clh_coarse_tangent(pts_l, k + 1u, C), fine);
          float3 mid = 0.5f * (pts_l[k - 1u].xyz + pts_l[k + 1u].xyz);
          P[i].xyz = mix(P[i].xyz, mid, gamma);
        }
        T[i] = (float4)(clh_normalize_or(mix(fine, coarse, gamma), fine), ao[i]);
      }
    }
    next_p = sg_shuffle_down1_f4(sg, P[0], (float4)(0.0f));
  } else {
    /* exchange 1: neighbour points for the finite-difference tangents */
    const float4 prev_p = sg_shuffle_up1_f4(sg, P[count > 0u ? count - 1u : 0u], (float4)(0.0f));
    next_p = sg_shuffle_down1_f4(sg, P[0], (float4)(0.0f));
    for (uint i = 0; i < CLH_PTS_CAP; ++i) T[i].w = ao[i];
    clh_finish_tangents(sg, P, T, CLH_PTS_CAP, first, count, C, prev_p, next_p, CLH_TANGENT_RSQRT);
  }

  /* last exchange: the next lane's first tangent, now final */
  span->next_t = sg_shuffle_down1_f4(sg, T[0], (float4)(0.0f));
  span->next_p = next_p;
  span->uv = s.uv;
  span->C = C;
  span->first = first;
  span->count = count;
}

/* Which strand a work-group draws; false when there is none (uniform per group). */
static inline bool clh_strand_job(__global const ClhGroomGpu* g, __global const ClhLodRecord* lod_g,
                                  __global const uint* offsets_g,
                                  __global const ClhBundle* bundles_g, uint strand, uint* bundle,
                                  uint* local_index, uint* C, float* gamma, float* coverage) {
  uint b = 0u;
  if (!clh_lod_find_strand(offsets_g, g->bundle_count, strand, &b, local_index)) return false;
  const ClhLodRecord lod = lod_g[b];
  *bundle = b;
  *C = clamp(lod.control_points, 2u, (uint)CLH_MAX_CONTROL_POINTS);
  *gamma = clamp(lod.gamma, 0.0f, 1.0f);
  *coverage = clh_lod_record_coverage(lod);
  return *local_index < lod.strands;
}

typedef struct {
  SG_SHARED clh_layer_pt* layers;
  SG_SHARED clh_strand* strand;
  SG_SHARED float4* pts;
} clh_strand_scratch;

/* Writes the lane's run of an assembled strand from stored point `base` on (its points at
 * base + span->first + i): strands_export and strands_store. */
static inline void clh_write_lane(__global float4* points_g, __global float4* tangents_g,
                                  size_t base, const float4* P, const float4* T,
                                  const clh_lane_span* span) {
  for (uint i = 0; i < CLH_PTS_CAP; ++i) {
    if (i < span->count) {
      points_g[base + span->first + i] = P[i];
      tangents_g[base + span->first + i] = T[i];
    }
  }
}

/* The job of a stored strand (strands_store's layout: bundle b's strands of C points each
 * from point_base_g[b] on): clh_strand_job within strand_capacity, and the strand's first
 * stored point through *base; false when there is none or it lies past point_capacity
 * (uniform per group). */
static inline bool clh_stored_job(__global const ClhGroomGpu* g, __global const ClhLodRecord* lod_g,
                                  __global const uint* offsets_g,
                                  __global const ClhBundle* bundles_g,
                                  __global const uint* point_base_g, ulong point_capacity,
                                  uint strand_capacity, uint strand, uint* bundle,
                                  uint* local_index, uint* C, float* gamma, float* coverage,
                                  size_t* base) {
  if (strand >= strand_capacity || !clh_strand_job(g, lod_g, offsets_g, bundles_g, strand, bundle,
                                                   local_index, C, gamma, coverage))
    return false;
  *base = (size_t)point_base_g[*bundle] + (size_t)(*local_index) * (*C);
  return *base + *C <= point_capacity;
}

#endif /* CLHAIR_STRAND_ASSEMBLY_H */
