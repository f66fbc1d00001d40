/* hair_style.h — evaluation of one styled hair-mesh strand point on the device.
 *
 * Inputs are the hair-mesh records of gpu_types.h. The functions here are pure: the
 * strand kernel calls them once per layer (clh_bundle_layer) and once per control point
 * (clh_base_point, clh_style_offset); the parallel bookkeeping lives in strands.cl.
 * The styling functions are specified in docs/hair-mesh-format.md; the CPU reference in
 * host/groom/reference.cpp implements the same specification independently.
 */
#ifndef CLHAIR_HAIR_STYLE_H
#define CLHAIR_HAIR_STYLE_H

/* include after subgroup.h (SG_SHARED: where a strand's layer samples live) and
 * clhair/fast_math.h (styling without pow/sin/cos library calls per point) */
/* clh_floor_i */
#include "clhair/raster_core.h"

/* One strand's sample on one layer: the bilinear interpolation of the layer's quad. */
typedef struct {
  float4 pos; /* xyz position, w: styling w */
  float4 tan; /* xyz tangent dP/d(layer), w: ambient occlusion */
  float4 du;  /* xyz styling direction u */
  float4 dv;  /* xyz styling direction v */
} clh_layer_pt;

/* Per-strand constants, identical in every lane. */
typedef struct {
  uint id;          /* hash of (seed, bundle, local index): the strand's random key */
  float2 st;        /* root sample in the bundle's (s, t) square */
  float2 uv;        /* root styling coordinates */
  float2 clump_duv; /* clump center uv minus uv */
  float phase;      /* curl phase in radians */
  float frizz;      /* frizz amplitude at the tip (object units) */
  float length;     /* fraction of the base spline this strand covers */
} clh_strand;

static inline uint clh_vertex_index(uint layer, int root_vertex, uint vertex_count) {
  uint v = (uint)clamp(root_vertex, 0, (int)vertex_count - 1);
  return layer * vertex_count + v;
}

static inline void clh_accum_vertex(clh_layer_pt* acc, __global const ClhMeshVertex* v, float wgt) {
  acc->pos += wgt * vload4(0, v->pos);
  acc->tan += wgt * vload4(0, v->tan);
  acc->du += wgt * vload4(0, v->du);
  acc->dv += wgt * vload4(0, v->dv);
}

/* Bilinear interpolation at (s, t) of the bundle's quad on `layer` (Bhokare §3.3:
 * corners 0,1,2,3 at (0,0),(1,0),(1,1),(0,1); triangles repeat corner 2). */
static inline clh_layer_pt clh_bundle_layer(__global const ClhMeshVertex* verts_g, int4 vtx,
                                            uint layer, uint vertex_count, float2 st) {
  clh_layer_pt r;
  r.pos = r.tan = r.du = r.dv = (float4)(0.0f);
  float s = st.x, t = st.y;
  clh_accum_vertex(&r, verts_g + clh_vertex_index(layer, vtx.x, vertex_count),
                   (1.0f - s) * (1.0f - t));
  clh_accum_vertex(&r, verts_g + clh_vertex_index(layer, vtx.y, vertex_count), s * (1.0f - t));
  clh_accum_vertex(&r, verts_g + clh_vertex_index(layer, vtx.z, vertex_count), s * t);
  clh_accum_vertex(&r, verts_g + clh_vertex_index(layer, vtx.w, vertex_count), (1.0f - s) * t);
  return r;
}

/* Cubic Hermite basis and its derivative at t in [0, 1]. */
static inline float4 clh_hermite_basis(float t) {
  float t2 = t * t, t3 = t2 * t;
  return (float4)(2.0f * t3 - 3.0f * t2 + 1.0f, t3 - 2.0f * t2 + t, -2.0f * t3 + 3.0f * t2,
                  t3 - t2);
}
static inline float4 clh_hermite_dbasis(float t) {
  float t2 = t * t;
  return (float4)(6.0f * t2 - 6.0f * t, 3.0f * t2 - 4.0f * t + 1.0f, -6.0f * t2 + 6.0f * t,
                  3.0f * t2 - 2.0f * t);
}

/* Value noise in [-1, 1] along one axis: random values at integer x, smoothstep between.
 * The frizz uses two channels at the same x; their knot values are kept per lane while x
 * stays between the same two knots (consecutive points of a strand mostly do), so the
 * hashing runs once per knot interval instead of twice per point — the values are the
 * same as hashing every time. */
typedef struct {
  int i;        /* the interval [i, i + 1] the values belong to; INT_MIN: none yet */
  float a0, b0; /* channel 0 at knots i and i + 1, in [-1, 1] */
  float a1, b1; /* channel 1 */
} clh_noise_knots;

static inline void clh_noise_knots_init(clh_noise_knots* k) { k->i = INT_MIN; }

/* The two channels' noise at x: knot hashes hash2(hash2(key, i), channel), as
 * clh_hash3(key, i, channel). */
static inline void clh_value_noise2(uint key, uint channel0, uint channel1, float x,
                                    clh_noise_knots* k, float* n0, float* n1) {
  const int i = clh_floor_i(x); /* raster_core.h */
  if (i != k->i) {
    const uint h0 = clh_hash2(key, (uint)i), h1 = clh_hash2(key, (uint)(i + 1));
    k->a0 = clh_u01(clh_hash2(h0, channel0)) * 2.0f - 1.0f;
    k->b0 = clh_u01(clh_hash2(h1, channel0)) * 2.0f - 1.0f;
    k->a1 = clh_u01(clh_hash2(h0, channel1)) * 2.0f - 1.0f;
    k->b1 = clh_u01(clh_hash2(h1, channel1)) * 2.0f - 1.0f;
    k->i = i;
  }
  const float f = clh_smoothstep01(x - (float)i);
  *n0 = mix(k->a0, k->b0, f);
  *n1 = mix(k->a1, k->b1, f);
}

/* Clump center of the jittered uv grid nearest to uv (Voronoi over the 3x3 cells). */
static inline float2 clh_clump_center(uint seed, float freq, float2 uv, uint* clump_id) {
  float2 g = uv * freq;
  float2 c = floor(g);
  float best = 1e30f;
  float2 best_center = uv;
  uint best_id = 0u;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      int cx = (int)c.x + dx, cy = (int)c.y + dy;
      uint cell_key = clh_hash3(seed ^ 0x5c1u, (uint)cx, (uint)cy);
      float2 jitter = (float2)(clh_u01(clh_hash2(cell_key, 0u)), clh_u01(clh_hash2(cell_key, 1u)));
      float2 center = (float2)((float)cx, (float)cy) + 0.5f + (jitter - 0.5f) * 0.8f;
      float2 d = g - center;
      float d2 = dot(d, d);
      if (d2 < best) {
        best = d2;
        best_center = center / freq;
        best_id = cell_key;
      }
    }
  }
  *clump_id = best_id;
  return best_center;
}

static inline clh_strand clh_strand_setup(__global const ClhGroomGpu* g,
                                          __global const ClhBundle* b, uint bundle,
                                          uint local_index, float2 st) {
  clh_strand s;
  s.id = clh_hash3(g->seed, bundle, local_index);
  s.st = st;
  float w0 = (1.0f - st.x) * (1.0f - st.y), w1 = st.x * (1.0f - st.y), w2 = st.x * st.y,
        w3 = (1.0f - st.x) * st.y;
  s.uv = (float2)(w0 * b->uv[0] + w1 * b->uv[2] + w2 * b->uv[4] + w3 * b->uv[6],
                  w0 * b->uv[1] + w1 * b->uv[3] + w2 * b->uv[5] + w3 * b->uv[7]);
  uint clump_id = 0u;
  s.clump_duv = (float2)(0.0f);
  if (g->clump_frequency > 0.0f) {
    s.clump_duv = clh_clump_center(g->seed, g->clump_frequency, s.uv, &clump_id) - s.uv;
  }
  s.phase = 2.0f * CLH_PI *
            (clh_u01(clh_hash2(clump_id, CLH_RNG_PHASE)) +
             g->curl_phase_jitter * clh_u01(clh_hash2(s.id, CLH_RNG_PHASE)));
  bool flyaway = clh_u01(clh_hash2(s.id, CLH_RNG_FLYAWAY)) < g->flyaway_fraction;
  s.frizz = g->frizz_amplitude + (flyaway ? g->flyaway_amplitude : 0.0f);
  s.length = 1.0f - g->length_variation * clh_u01(clh_hash2(s.id, CLH_RNG_LENGTH));
  return s;
}

/* Point k of C on the base spline: Hermite between the layer samples bracketing the
 * strand parameter (uniform in the strand's length fraction). Returns the position with
 * styling w in .w; writes the derivative along the strand and the interpolated frame. */
static inline float4 clh_base_point(SG_SHARED const clh_layer_pt* layers_l, uint layer_count,
                                    uint k, uint C, float length, float3* deriv, float3* du,
                                    float3* dv, float* ao) {
  float x = ((float)k / (float)(C - 1u)) * length * (float)(layer_count - 1u);
  int i = min((int)floor(x), (int)layer_count - 2);
  i = max(i, 0);
  float t = x - (float)i;
  clh_layer_pt a = layers_l[i];
  clh_layer_pt b = layers_l[i + 1];
  float4 h = clh_hermite_basis(t);
  float4 dh = clh_hermite_dbasis(t);
  float3 p = h.x * a.pos.xyz + h.y * a.tan.xyz + h.z * b.pos.xyz + h.w * b.tan.xyz;
  *deriv = dh.x * a.pos.xyz + dh.y * a.tan.xyz + dh.z * b.pos.xyz + dh.w * b.tan.xyz;
  *du = mix(a.du.xyz, b.du.xyz, t);
  *dv = mix(a.dv.xyz, b.dv.xyz, t);
  *ao = mix(a.tan.w, b.tan.w, t);
  float w = mix(a.pos.w, b.pos.w, t);
  return (float4)(p, w);
}

/* Object-space styling offset for a base point (clumping, curl/wave, frizz) in the frame
 * built from the consistent per-vertex u direction and the base-spline direction. */
static inline float3 clh_style_offset(__global const ClhGroomGpu* g, const clh_strand* s, float w,
                                      float3 deriv, float3 du, float3 dv, clh_noise_knots* knots) {
  float3 et = clh_normalize_or(deriv, (float3)(0.0f, 1.0f, 0.0f));
  float3 e1 = clh_normalize_or(du - dot(du, et) * et,
                               clh_normalize_or(dv - dot(dv, et) * et, (float3)(1.0f, 0.0f, 0.0f)));
  float3 e2 = cross(et, e1);
  float wc = clamp(w, 0.0f, 1.0f);

  float3 off = (float3)(0.0f);
  if (g->clump_strength > 0.0f) {
    off += (g->clump_strength * clh_fast_pow(wc, g->clump_shape)) *
           (du * s->clump_duv.x + dv * s->clump_duv.y);
  }
  if (g->curl_amplitude > 0.0f) {
    float ramp = clh_smoothstep01(wc / 0.15f);
    float theta = 2.0f * CLH_PI * g->curl_frequency * wc + s->phase;
    float st, ct;
    clh_fast_sincos(theta, &st, &ct);
    off += (g->curl_amplitude * ramp) * (ct * e1 + (g->curl_helix * st) * e2);
  }
  if (s->frizz > 0.0f) {
    float x = wc * g->frizz_frequency;
    float n1, n2;
    clh_value_noise2(s->id, CLH_RNG_FRIZZ, CLH_RNG_FRIZZ + 16u, x, knots, &n1, &n2);
    off += (s->frizz * wc * wc) * (n1 * e1 + n2 * e2);
  }
  return off;
}

#endif /* CLHAIR_HAIR_STYLE_H */
