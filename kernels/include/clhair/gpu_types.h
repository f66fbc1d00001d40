/* gpu_types.h — the contract between the C++ host and the OpenCL C kernels.
 *
 * Every struct that crosses the host/device boundary and every packed bit layout lives
 * here, written once in the common subset of C++17 and OpenCL C 1.2: fixed-width scalars,
 * float arrays instead of float3/float4 members (12 vs 16 bytes), explicit padding, and
 * small pack/unpack helpers as inline functions. The kernels, the CPU references and the
 * tests all call the same helpers, so a layout changes in exactly one place.
 *
 * Invariants: every struct size is a multiple of 16 bytes and is pinned by static_asserts
 * on the host (host/cl/layout_check.cpp) and by a device-side size kernel in the tests.
 */
#ifndef CLHAIR_GPU_TYPES_H
#define CLHAIR_GPU_TYPES_H

#if defined(__OPENCL_VERSION__) || defined(__OPENCL_C_VERSION__)
#define CLH_DEVICE_CODE 1
/* No fused multiply-add contraction: the shared helpers round the same on every device and
 * on the host (the CPU floor of the benchmark compares G-buffer words exactly). */
#pragma OPENCL FP_CONTRACT OFF
typedef uint clh_u32;
typedef int clh_i32;
typedef ulong clh_u64;
#define CLH_FN static inline
#else
#include <cmath>
#include <cstdint>
namespace clhair {
namespace gpu {
typedef std::uint32_t clh_u32;
typedef std::int32_t clh_i32;
typedef std::uint64_t clh_u64;
using std::ceil;
using std::fabs;
using std::floor;
using std::fmax;
using std::fmin;
using std::log2;
using std::sqrt;
#define CLH_FN inline
#endif

/* ---- limits shared by host validation and kernel array sizes ----------------------- */
#define CLH_MAX_LAYERS 64 /* layers per bundle (local-memory array in strands.cl) */
/* C_max of Lipp et al. Eq. 4-5. The paper caps at 127; clhair uses 2^7 + 1 = 129 so every
 * level nests in the next (vertex-LOD morphing, Bhokare §3.6.2, needs the points of level
 * 2^k + 1 to be the even points of level 2^(k+1) + 1). 129 points still fit 4 per lane:
 * the last lane owns the tip (strands.cl). */
#define CLH_MAX_CONTROL_POINTS 129
#define CLH_MAX_LIGHTS 16
#define CLH_MAX_MSAA 8
#define CLH_MAX_HIT_DIAMETER 3.0f /* pixels: widest center-hit band (LOD compensation cap) */

/* ---- hair-mesh vertex: one per (layer, root vertex), 64 bytes ------------------------
 * pos : xyz object-space position,  w: styling coordinate w (0 at root layer)
 * tan : xyz given tangent dP/d(layer index) (valid when the groom has tangents),
 *       w: baked ambient occlusion in [0,1] (1 = unoccluded)
 * du  : xyz object-space styling direction u = dP/du (Bhokare Eq. 1-3, not normalised)
 * dv  : xyz object-space styling direction v = dP/dv;  w unused                        */
typedef struct {
  float pos[4];
  float tan[4];
  float du[4];
  float dv[4];
} ClhMeshVertex;

/* ---- bundle: one per scalp face, 64 bytes ---------------------------------------------
 * vtx   : root-layer vertex indices in counter-clockwise order; triangles repeat vtx[2]
 *         in vtx[3] so bilinear interpolation at (s, t) is barycentric (Bhokare §3.3)
 * strand_count : N, strands of this bundle at full detail
 * triangle     : 1 for triangle faces (roots come from the triangle blue-noise set)
 * lod_delta    : per-bundle random offset delta in [0,1) of Lipp Eq. 1
 * first_strand : strands of the bundles before this one at full detail: strand k of the
 *                bundle is strand first_strand + k of the groom (its identity, below)
 * uv    : root uv of the four corners (u0 v0 u1 v1 u2 v2 u3 v3)                         */
typedef struct {
  clh_i32 vtx[4];
  clh_u32 strand_count;
  clh_u32 triangle;
  float lod_delta;
  clh_u32 first_strand;
  float uv[8];
} ClhBundle;

/* ---- per-groom parameters for one view, 304 bytes ------------------------------------- */
typedef struct {
  float obj_to_view[12];  /* 3x4 row-major: object space -> view space (+z forward) */
  float obj_to_world[12]; /* 3x4 row-major: object space -> world space */

  clh_u32 bundle_count;
  clh_u32 layer_count;
  clh_u32 vertex_count; /* root vertices; the mesh holds layer_count * vertex_count */
  clh_u32 has_tangents;

  clh_u32 control_points; /* C when LOD is off: 2^k + 1 */
  clh_u32 lod_enabled;
  clh_u32 seed;
  clh_u32 root_set_size; /* samples in each progressive blue-noise root set */

  float lod_lambda;       /* Lipp Eq. 2 sensitivity */
  float lod_morph_window; /* Bhokare Eq. 10 transition window */
  float depth_near;       /* G-buffer depth mapping range (view z) */
  float depth_far;

  float hit_diameter_px;         /* center-layer hit diameter in pixels */
  float strand_width;            /* world-space strand diameter */
  clh_u32 total_strands;         /* strands at full detail (all bundles) */
  clh_u32 shadow_lod_correction; /* 1: shadow lookups shift by -log(beta) (Lipp Eq. 8) */

  /* styling (Bhokare §3.4 frames; functions documented in docs/hair-mesh-format.md) */
  float clump_strength;    /* 0..1: how far tips move toward the clump center */
  float clump_frequency;   /* clump cells per unit of root uv */
  float clump_shape;       /* exponent of w in the clump profile */
  float curl_amplitude;    /* object units */
  float curl_frequency;    /* turns per strand (over w in [0,1]) */
  float curl_helix;        /* 1: helical curl, 0: planar wave */
  float curl_phase_jitter; /* 0: clumps curl in phase, 1: every strand random */
  float frizz_amplitude;   /* object units at the tip */
  float frizz_frequency;   /* noise cells per strand */
  float flyaway_fraction;  /* fraction of strands with stronger frizz */
  float flyaway_amplitude;
  float length_variation; /* strands are shortened by up to this fraction */

  /* appearance (shade.cl): the fibre's absorption comes from melanin concentrations
   * (Chiang et al. 2016) blended root to tip over w, or, when use_melanin is 0, from the
   * root/tip colours; each strand varies its melanin by up to +-variation (hashed from uv) */
  float root_color[4];
  float tip_color[4];
  float melanin[4]; /* eumelanin root, tip; pheomelanin root, tip */
  float bsdf[4];    /* beta_m, beta_n, cuticle tilt (radians), index of refraction */
  float look[4];    /* variation, use_melanin (0/1), file colour (0/1: explicit grooms
                     * whose G-buffer words carry per-point colour, see below), file
                     * thickness scale (0: none; > 0: object -> world scale of the
                     * per-point thickness; -1: per-point opacity times strand_width) */
  /* LOD from the screen (lod_math.h clh_lod_strands_screen): strands per pixel of a bundle's
   * projected width (0: Lipp Eq. 1 from L instead); then padding */
  float lod_strands_px;
  /* > 0: a faint groom (host/io/faint_groom.h) whose centre hits were widened to
   * hit_diameter_px beyond its true width fy * strand_width / z = faint_width_px1 / z; the
   * filters scale its alpha by true width / hit diameter */
  float faint_width_px1;
  float lod_pad[2];
} ClhGroomGpu;

/* ---- camera for one view, 128 bytes ------------------------------------------------
 * View space: camera at the origin looking down +z, +y up, +x right.
 * Pixel coordinates: x_px = cx + fx * x / z,  y_px = cy - fy * y / z; pixel (i, j) has
 * its center at (i + 0.5, j + 0.5).                                                      */
typedef struct {
  float world_to_view[12];
  float view_to_world[12];
  float fx, fy, cx, cy;
  clh_u32 width, height, samples, pad0;
  float eye[4];
} ClhViewGpu;

/* ---- the previous frame of a deforming groom, 80 bytes ----------------------------------
 * The motion pass (strands.cl / strands_explicit.cl built with CLH_RASTER_MOTION) evaluates
 * each strand a second time from the previous frame's cage or points and projects it with
 * the previous frame's object -> view transform and camera (same pixel conventions as
 * ClhViewGpu). depth_layers: the G-buffer layers the composite takes the pixel's depth from
 * (the nearest word of layers 0 .. depth_layers - 1, composite.cl); the fragment whose word
 * that is gives the pixel its motion.                                                      */
typedef struct {
  float prev_obj_to_view[12];
  float fx, fy, cx, cy;
  clh_u32 depth_layers, pad0, pad1, pad2;
} ClhMotionGpu;

/* ---- lights and opaque primitives ---------------------------------------------------- */
typedef struct {
  float pos[4];   /* w = 1: point light at xyz; w = 0: directional, xyz points to the light */
  float color[4]; /* linear rgb radiance scale (point lights: intensity at distance 1);
                     w: shadow slot (>= 0: index into the ClhShadowGpu array), -1: no shadow */
} ClhLightGpu;

/* ---- deep opacity map of one shadowed light (Yuksel & Keyser 2008), 160 bytes -------
 * The light's view is a pinhole camera (directional lights: a distant, narrow one). Per
 * texel the map holds the opaque scene's depth, the nearest hair depth z0 and
 * CLH_DOM_LAYERS opacity layers: layer k accumulates the coverage of hair between
 * z0 + bound[k-1] and z0 + bound[k] (bound[-1] = 0), in units of 1/CLH_DOM_FIXED.   */
#define CLH_DOM_LAYERS 3
#define CLH_DOM_FIXED 4096.0f
#define CLH_MAX_SHADOWS 4
typedef struct {
  float world_to_view[12];
  float fx, fy, cx, cy;
  clh_u32 width, height;
  clh_u32 offset; /* first texel of this light in the shared DOM buffers */
  float density;  /* transmittance = exp(-density * accumulated coverage) */
  float bound[4]; /* layer ends, view-depth units past z0 (3 used) */
  float pad_shift;
  float bias;       /* opaque shadow-map bias, view-depth units */
  float depth_near; /* hair depth mapping of the light's G-buffer pass */
  float depth_far;
  clh_u32 pcf; /* opaque surfaces: 1 percentage-closer filtering (4x4 texels), 0 bilinear */
  float pad[11];
} ClhShadowGpu;

typedef struct {
  float center[4]; /* w = radius */
  float color[4];  /* linear albedo */
} ClhSphereGpu;

typedef struct {
  float normal[4]; /* xyz unit normal, w = d with dot(n, x) = d on the plane */
  float color[4];
} ClhPlaneGpu;

typedef struct {
  float background[4];
  float ambient[4];
  clh_u32 sphere_count;
  clh_u32 plane_count;
  clh_u32 light_count;
  clh_u32 env_levels; /* prefiltered environment levels; 0: no environment (ambient instead);
                         bit 31 set: the environment is also the background */
  clh_u32 bg_width;   /* background image texels (0: none), stretched over the frame */
  clh_u32 bg_height;
  clh_u32 pad1, pad2;
} ClhSceneGpu;
#define CLH_ENV_VISIBLE 0x80000000u

/* ---- reconstruction filter parameters (Lipp §3.3), 32 bytes ------------------------- */
typedef struct {
  clh_u32 radius;       /* window radius r in pixels: (2r + 1)^2 neighbours */
  float s_par;          /* sigma_parallel = r * s_par (along the screen tangent) */
  float s_perp;         /* sigma_perp = r * s_perp (across it) */
  float sigma_c;        /* colour similarity */
  float depth_reject;   /* neighbours farther than this relative depth are ignored */
  float depth_mismatch; /* a conservative strand nearer by this relative depth is blended on top */
  float strip;          /* alpha strip: neighbours within this distance of the tangent line */
  clh_u32 promote;      /* 1: conservative-only pixels are promoted (§3.3.2), 0: left empty */
} ClhFilterGpu;

/* ---- baked spherical visibility of one groom instance, 96 bytes ------------------------
 * (Kulikov 2025, "precomputed self-shadowing"; include/clhair/visibility_sh.h, shade.cl)
 * world_to_obj : 3x4 row-major inverse of the instance's object -> world transform; its
 *                linear part turns light directions into the bake's space, the whole
 *                matrix shaded points into the AO field's
 * absorption   : visibility = exp(-absorption * max(0, SH(light direction)))
 * cells        : SH cells in the table (CLH_VIS_CELLS), 0 when the groom has no bake
 * enabled      : 1 to look the table up for lights without a deep opacity map
 * shade_flags  : the groom instance's per-draw shading choices (this record carries them):
 *                CLH_SHADE_AGGREGATE shades strands LOD widened with the aggregated BCSDF
 *                (Huang 2024, hair_aggregate.h) instead of the single-fibre one;
 *                CLH_SHADE_SINGLE_SCATTER leaves out the light scattered between fibres
 *                (dual scattering, hair_dual.h)                                          */
#define CLH_SHADE_AGGREGATE 1u
#define CLH_SHADE_SINGLE_SCATTER 2u
typedef struct {
  float world_to_obj[12];
  float absorption;
  clh_u32 cells;
  clh_u32 enabled;
  clh_u32 shade_flags;
  float ao_lo[4];     /* the groom's AO field (kernels/ao.cl, ao_field): object-space corner
                         of voxel (0, 0, 0), w: voxel size */
  clh_u32 ao_dims[4]; /* voxels per axis (x fastest in the table), w: 1 to multiply the
                         word's AO by the field at the shaded point, 3: also the light
                         diffused through the groom (three more planes, r, g, b:
                         host/groom/diffusion_field.h), 0: no field */
} ClhVisibilityGpu;

/* ---- LOD record: one per bundle of a hair mesh or chunk of a strand file, 16 bytes -----
 * Written by lod_bundles / lod_chunks (lod.cl), or by the host when it fixes L itself
 * (strand export, clh_lod_record_at in lod_math.h), rewritten by the segment budget
 * (budget.cl); read by the strand kernels (strands.cl, strands_explicit.cl) for the bundle
 * or chunk a strand belongs to.
 *
 *   bytes   member          type  meaning
 *   0..3    strands         u32   N_LOD, strands drawn (Lipp Eq. 1); 0: culled
 *   4..7    control_points  u32   C, points per strand (Lipp Eq. 4-5), 2^k + 1
 *   8..11   coverage        f32   the factor by which its strands widen their hit diameter
 *                                 for the strands left out: N / N_LOD from the pre-pass
 *                                 (1 at full detail or culled), N / N' once the segment
 *                                 budget keeps N' (less under a widening cap)
 *   12..15  gamma           f32   vertex-LOD morph factor (Bhokare Eq. 10-12), 0: none
 *
 * A culled bundle keeps the groom's full-detail C, with coverage 1 and gamma = 0.       */
typedef struct {
  clh_u32 strands;
  clh_u32 control_points;
  float coverage;
  float gamma;
} ClhLodRecord;

CLH_FN ClhLodRecord clh_lod_record_make(clh_u32 strands, clh_u32 control_points, float coverage,
                                        float gamma) {
  ClhLodRecord r;
  r.strands = strands;
  r.control_points = control_points;
  r.coverage = coverage;
  r.gamma = gamma;
  return r;
}

/* The widening of a bundle (or chunk) of n_full strands that draws n of them: N / n, at
 * least 1, and 1 when it draws none. */
CLH_FN float clh_lod_widening(clh_u32 n_full, clh_u32 n) {
  return n > 0u ? fmax((float)n_full / (float)n, 1.0f) : 1.0f;
}

/* The factor by which a strand of the record widens its hit diameter (at least 1; 1 when
 * the record draws nothing). */
CLH_FN float clh_lod_record_coverage(ClhLodRecord r) {
  return r.strands > 0u ? fmax(r.coverage, 1.0f) : 1.0f;
}

/* ---- the LOD counts and their scan, for n bundles (or chunks) --------------------------
 * counts: lod_bundles / lod_chunks -> scan_bundles, clh_lod_counts_length(n) = 7n uints
 *   [b]      N_LOD of bundle b (its record's strands)
 *   [n + b]  N of bundle b when it is not culled, else 0    (clh_lod_full_count_at)
 *   [2n + b] segments bundle b draws: N_LOD (C - 1) for a hair mesh; for a strand-file
 *            chunk the sum over its drawn strands of their drawn points - 1
 *                                                            (clh_lod_segment_count_at)
 *   [3n + b .. 6n + b], step n: the bundle's screen box (its LOD AABB) clipped to the
 *            image, pixels, as f32 bits: x0, y0, x1, y1 (all 0 when culled); the segment
 *            budget's screen rule reads it (budget.cl)      (clh_lod_box_at(n, b, k))
 * offsets: scan_bundles -> strand kernels, shade.cl and the host,
 *   clh_lod_offsets_length(n) = n + 3 uints
 *   [b]      exclusive scan of counts[0..n): the first draw index of bundle b
 *   [n]      drawn total, the sum of N_LOD: sizes the strand pass (clh_lod_drawn_total_at)
 *   [n + 1]  visible total, the sum of counts[n..2n): full-detail strands of the bundles
 *            not culled; beta = drawn / visible (Lipp §3.2.3, shade.cl)
 *                                                            (clh_lod_visible_total_at)
 *   [n + 2]  segment total, the sum of counts[2n..3n)       (clh_lod_segment_total_at)
 * A draw index i < offsets[n] belongs to the last bundle b with offsets[b] <= i and is
 * that bundle's (i - offsets[b])-th strand.                                            */
CLH_FN clh_u32 clh_lod_counts_length(clh_u32 n) { return 7u * n; }
CLH_FN clh_u32 clh_lod_full_count_at(clh_u32 n, clh_u32 b) { return n + b; }
CLH_FN clh_u32 clh_lod_segment_count_at(clh_u32 n, clh_u32 b) { return 2u * n + b; }
/* k: 0 x0, 1 y0, 2 x1, 3 y1 */
CLH_FN clh_u32 clh_lod_box_at(clh_u32 n, clh_u32 b, clh_u32 k) { return (3u + k) * n + b; }
CLH_FN clh_u32 clh_lod_offsets_length(clh_u32 n) { return n + 3u; }
CLH_FN clh_u32 clh_lod_drawn_total_at(clh_u32 n) { return n; }
CLH_FN clh_u32 clh_lod_visible_total_at(clh_u32 n) { return n + 1u; }
CLH_FN clh_u32 clh_lod_segment_total_at(clh_u32 n) { return n + 2u; }

/* ---- the segment budget: one frame's LOD records of every groom in one buffer, 32 bytes
 * per groom draw (host/frame/frame_lod.h, lod.cl: budget_measure, budget_plan,
 * budget_apply).
 * The records, counts and offsets of draw d lie in one shared buffer (the "arena") at
 * records_at (in ClhLodRecord units), counts_at and offsets_at (in uint units), with the
 * layouts above for `records` bundles or chunks.
 *   kind    0: hair mesh (a strand draws C - 1 segments), 1: strand file (its chunk's mean)
 *   active  0: not drawn this frame; CLH_BUDGET_DRAW_FIXED: prepared in the camera pass
 *           (its records are fresh) without LOD, so the budget neither counts nor cuts
 *           it; CLH_BUDGET_DRAW_BUDGETED: prepared with LOD, under the budget
 *   min_points  the least control-point count the budget may halve a record's C to
 *   far     1: the groom is small on screen; over budget it drops every other control
 *           point (Kulikov 2025)                                                        */
typedef struct {
  clh_u32 records_at;
  clh_u32 counts_at;
  clh_u32 offsets_at;
  clh_u32 records;
  clh_u32 kind;
  clh_u32 active;
  clh_u32 min_points;
  clh_u32 far;
} ClhBudgetDraw;

/* How the budget shares the segments out, 32 bytes (DESIGN.md, "The segment budget").
 *   rule        CLH_BUDGET_RULE_UNIFORM: one factor f for every groom (the largest that
 *               fits); CLH_BUDGET_RULE_SCREEN: each groom's share by its screen area
 *   image_area  the view's width x height, pixels
 *   keep_lo, keep_hi  screen shares (groom box area / image area) between which a groom's
 *               claim to keep its LOD count ramps from 0 to 1 (smoothstep)
 *   room_lo     the claims hold in full while the budget above every groom's floor covers
 *               them; they fade out linearly as that room falls to room_lo of them
 *   widen_cap   the screen rule widens a surviving strand by at most this factor for the
 *               strands the budget removed, on top of LOD's own widening; 0: no cap
 *               (N_LOD / N')                                                            */
typedef struct {
  clh_u32 rule;
  float image_area;
  float keep_lo;
  float keep_hi;
  float room_lo;
  float widen_cap;
  clh_u32 pad0;
  clh_u32 pad1;
} ClhBudgetRule;
#define CLH_BUDGET_RULE_UNIFORM 0u
#define CLH_BUDGET_RULE_SCREEN 1u

/* What the budget measures, decides for the frame and reports per draw: a header of
 * CLH_BUDGET_HEADER words, then CLH_BUDGET_DRAW_WORDS words per draw.
 *   header: [0] the uniform rule's factor f (f32 bits; 1 within budget or under the screen
 *           rule), [1] 1: the LOD pre-passes exceeded the budget, [2] the rule, [3] and
 *           [4]: the segment total of the pre-passes (low and high 32 bits), [5] the
 *           screen rule's level mu (segments per pixel of screen box, f32), [6] the
 *           strength phi of the claims (f32), [7] 0
 *   per draw, by budget_apply: [0] strands, [1] segments, [2] visible strands;
 *           by budget_plan: [3] flags (CLH_BUDGET_HALVED: every other control point
 *           dropped);
 *           by budget_measure (every active draw, either rule): [4] R, the segments its
 *           LOD records ask, [5] R at every other control point, [6] F, its floor: one
 *           strand per drawn record, [7] F at every other control point, [8] A, its
 *           screen box (the union of its records' boxes clipped to the image, pixels,
 *           f32), [9] its drawn records;
 *           by budget_plan (screen rule over the budget; else S = R, f = 1): [10] S, its
 *           share of segments, [11] its factor f_d (f32), [12] its claim p (f32), [13] G,
 *           the floor of its share with its claim; [14], [15] 0                         */
#define CLH_BUDGET_HEADER 8u
#define CLH_BUDGET_DRAW_WORDS 16u
#define CLH_BUDGET_DRAW_FIXED 1u
#define CLH_BUDGET_DRAW_BUDGETED 2u
#define CLH_BUDGET_HALVED 1u

/* ---- the 64-bit G-buffer word --------------------------------------------------------
 *  bits 63..40  depth, 24 bits: view z mapped linearly from [near, far]; smaller = closer
 *  bits 39..24  tangent, octahedral, 8 bits x then 8 bits y
 *  bits 23..18  u   bits 17..12  v   bits 11..6  w   (styling coordinates, 6 bits each)
 *  bits  5..0   baked ambient occlusion
 * All ones is the empty word. atom_min over it is order independent, which makes frames
 * bit-identical across runs and thread counts.                                          */
#define CLH_GBUF_EMPTY (~(clh_u64)0)
#define CLH_DEPTH_MAX_CODE 0xFFFFFEu /* all-ones depth is reserved for the empty word */

CLH_FN float clh_clamp01(float x) { return fmin(fmax(x, 0.0f), 1.0f); }

CLH_FN clh_u32 clh_unorm_bits(float x, clh_u32 bits) {
  float scale = (float)((1u << bits) - 1u);
  return (clh_u32)(clh_clamp01(x) * scale + 0.5f);
}

CLH_FN float clh_unorm_value(clh_u32 code, clh_u32 bits) {
  return (float)code / (float)((1u << bits) - 1u);
}

CLH_FN clh_u32 clh_depth_encode(float z, float near_z, float far_z) {
  float t = clh_clamp01((z - near_z) / (far_z - near_z));
  clh_u32 code = (clh_u32)(t * (float)CLH_DEPTH_MAX_CODE + 0.5f);
  return code > CLH_DEPTH_MAX_CODE ? CLH_DEPTH_MAX_CODE : code;
}

CLH_FN float clh_depth_decode(clh_u32 code, float near_z, float far_z) {
  return near_z + (far_z - near_z) * ((float)code / (float)CLH_DEPTH_MAX_CODE);
}

/* Octahedral unit-vector encoding, 8 + 8 bits (the full sphere: hair tangents keep their
 * root-to-tip sign). */
CLH_FN float clh_sign_nz(float x) { return x >= 0.0f ? 1.0f : -1.0f; }

CLH_FN clh_u32 clh_oct_encode(float x, float y, float z) {
  float s = fabs(x) + fabs(y) + fabs(z);
  if (!(s > 0.0f)) return (128u << 8) | 128u;
  float px = x / s, py = y / s;
  if (z < 0.0f) {
    float ox = (1.0f - fabs(py)) * clh_sign_nz(px);
    float oy = (1.0f - fabs(px)) * clh_sign_nz(py);
    px = ox;
    py = oy;
  }
  clh_u32 qx = clh_unorm_bits(px * 0.5f + 0.5f, 8u);
  clh_u32 qy = clh_unorm_bits(py * 0.5f + 0.5f, 8u);
  return (qx << 8) | qy;
}

/* Decodes to a unit vector written to out[0..2]. */
CLH_FN void clh_oct_decode(clh_u32 code, float* out) {
  float px = clh_unorm_value((code >> 8) & 0xFFu, 8u) * 2.0f - 1.0f;
  float py = clh_unorm_value(code & 0xFFu, 8u) * 2.0f - 1.0f;
  float pz = 1.0f - fabs(px) - fabs(py);
  if (pz < 0.0f) {
    float ox = (1.0f - fabs(py)) * clh_sign_nz(px);
    float oy = (1.0f - fabs(px)) * clh_sign_nz(py);
    px = ox;
    py = oy;
  }
  float len = sqrt(px * px + py * py + pz * pz);
  out[0] = px / len;
  out[1] = py / len;
  out[2] = pz / len;
}

CLH_FN clh_u64 clh_gbuf_pack(clh_u32 depth24, clh_u32 oct16, clh_u32 u6, clh_u32 v6, clh_u32 w6,
                             clh_u32 ao6) {
  return ((clh_u64)(depth24 & 0xFFFFFFu) << 40) | ((clh_u64)(oct16 & 0xFFFFu) << 24) |
         ((clh_u64)(u6 & 63u) << 18) | ((clh_u64)(v6 & 63u) << 12) | ((clh_u64)(w6 & 63u) << 6) |
         (clh_u64)(ao6 & 63u);
}

/* ---- file colour in the G-buffer word (explicit grooms with look[2] = 1) ---------------
 * A strand file's per-point colour replaces the styling and AO fields, which such a groom
 * does not need (its colour is given, its AO is 1):
 *  bits 23..18  red     bits 17..12  green     bits 11..6  w (unchanged)     bits 5..0  blue
 * Each channel is the 6-bit code of sqrt(linear colour), which spends the codes where dark
 * hair colours lie (linear 0.05 has steps of about 0.006).                               */
CLH_FN clh_u32 clh_file_color_code(float linear) {
  return clh_unorm_bits(sqrt(clh_clamp01(linear)), 6u);
}

CLH_FN float clh_file_color_value(clh_u32 code) {
  const float s = clh_unorm_value(code, 6u);
  return s * s;
}

CLH_FN clh_u32 clh_gbuf_depth(clh_u64 word) { return (clh_u32)(word >> 40) & 0xFFFFFFu; }
CLH_FN clh_u32 clh_gbuf_oct(clh_u64 word) { return (clh_u32)(word >> 24) & 0xFFFFu; }
CLH_FN clh_u32 clh_gbuf_u(clh_u64 word) { return (clh_u32)(word >> 18) & 63u; }
CLH_FN clh_u32 clh_gbuf_v(clh_u64 word) { return (clh_u32)(word >> 12) & 63u; }
CLH_FN clh_u32 clh_gbuf_w(clh_u64 word) { return (clh_u32)(word >> 6) & 63u; }
CLH_FN clh_u32 clh_gbuf_ao(clh_u64 word) { return (clh_u32)word & 63u; }

/* ---- the strand identity word (a second 64-bit word per pixel of the centre layer) -----
 *  bits 63..40  depth code, the same 24 bits as the G-buffer word's
 *  bits 39..16  strand, 24 bits: its index in the groom at full detail (hair meshes: the
 *               bundle's first_strand plus the strand's index in the bundle; strand files:
 *               the strand's index in the file), independent of LOD and of the frame
 *  bits 15..1   position along the strand, 15 bits: u in [0, 1] from root to tip (point
 *               index over the point count minus one, linear within a segment)
 *  bit   0      1: written by hair linking (a propagated pixel), 0: drawn by the strand pass
 * Written next to the centre word with the same depth test and its own atom_min, so the
 * two name the same strand wherever their depth codes differ from every competitor's;
 * strands that tie in depth code may leave the word of one and the identity of another.
 * All ones is empty, as for the G-buffer word.                                            */
#define CLH_ID_STRAND_BITS 24u
#define CLH_ID_MAX_STRAND 0xFFFFFEu /* all ones is the empty word's */
#define CLH_ID_POS_MAX 32767u

CLH_FN clh_u64 clh_id_pack(clh_u32 depth24, clh_u32 strand, clh_u32 pos15, clh_u32 linked) {
  return ((clh_u64)(depth24 & 0xFFFFFFu) << 40) | ((clh_u64)(strand & 0xFFFFFFu) << 16) |
         ((clh_u64)(pos15 & 0x7FFFu) << 1) | (clh_u64)(linked & 1u);
}
CLH_FN clh_u32 clh_id_strand(clh_u64 id) { return (clh_u32)(id >> 16) & 0xFFFFFFu; }
CLH_FN clh_u32 clh_id_pos(clh_u64 id) { return (clh_u32)(id >> 1) & 0x7FFFu; }
CLH_FN clh_u32 clh_id_linked(clh_u64 id) { return (clh_u32)id & 1u; }
CLH_FN clh_u32 clh_id_pos_code(float u) {
  return (clh_u32)(clh_clamp01(u) * (float)CLH_ID_POS_MAX + 0.5f);
}

/* ---- hair linking, alpha fix and the anisotropic filter (Huang et al. 2025), 48 bytes --
 * Layers of the G-buffer past the conservative one (MSAA 1): CLH_LAYER_ID the identity
 * words of the centre layer; with linking, CLH_LAYER_CURVE / CLH_LAYER_CURVE_ID the words
 * and identities of the source strands' centre lines (one pixel per column or row), and
 * CLH_LAYER_LINKED the identities linking propagated into empty pixels.                  */
#define CLH_LAYER_ID 2u
#define CLH_LAYER_CURVE 3u
#define CLH_LAYER_CURVE_ID 4u
#define CLH_LAYER_LINKED 5u
#define CLH_LINK_NONE 0xFFFFFFFFu
/* the hash table of the alpha fix: 4 uints per entry (key = strand + 1, 0: free; M; N; 0) */
#define CLH_HASH_PROBES 32u
/* link counters: [0] pixels selecting a source, [1] pixels filled, [2] strands counted,
 * [3] strands the full table turned away, [4..7] hair bounds min x, min y, max x, max y */
#define CLH_LINK_COUNTERS 8u
/* the anisotropic filter's widest major axis, pixels (Huang Eq. 13 clamped, link.cl): the
 * host bounds the alpha fix's output to a groom's screen box grown by this much */
#define CLH_LINK_MAX_RADIUS 3
typedef struct {
  float align_threshold; /* epsilon_align of Huang Eq. 5 */
  float sigma_px;        /* sigma of the proximity term of Huang Eq. 4, pixels */
  clh_u32 max_steps;     /* pixels one propagation may fill */
  clh_u32 table_size;    /* entries of the alpha fix's hash table */
  clh_u32 alpha_fix;     /* 1: alpha = M / (M + N) per strand (Huang Eq. 8-10) */
  clh_u32 aniso;         /* 1: the orientation-aware filter follows (Huang Eq. 11-13) */
  float sigma_d, sigma_theta, sigma_c; /* Huang Eq. 11 */
  float kernel_k;                      /* Huang Eq. 13: r = k sqrt(Bx By) */
  clh_u32 strand_words;                /* words of the source-strand bitmap */
  clh_u32 pad0;
} ClhLinkGpu;

/* ---- children of an explicit groom's guides, 32 bytes ---------------------------------
 * Drawn strand slot j of a chunk of n guides is child j / n (0: the guide itself) of the
 * chunk's guide j % n (host/groom/children.h has the rules; kernels/common/children.h
 * draws them). count: children per guide (0: none); mode: CLH_CHILD_FOLLOW or
 * CLH_CHILD_INTERPOLATED; neighbours: guides listed per guide in the neighbour table;
 * guides: guide (stored strand) count; radius: the half side of the square of root offsets
 * (object units); tip_spread: TressFX's tip separation factor; clump: Blender's clump
 * factor in [-1, 1]; seed: the offsets' hash seed. */
#define CLH_CHILD_FOLLOW 0u
#define CLH_CHILD_INTERPOLATED 1u
#define CLH_CHILD_NEIGHBOURS 8u
typedef struct {
  clh_u32 count;
  clh_u32 mode;
  clh_u32 neighbours;
  clh_u32 guides;
  float radius;
  float tip_spread;
  float clump;
  clh_u32 seed;
} ClhChildrenGpu;

/* ---- per-point shading: the sample identity word, one more layer per sample ------------
 * With per-point shading (DESIGN.md, "Shading once per visible strand point") the strand
 * pass writes, next to each sample word of sample layer s (0 <= s < MSAA), the identity of
 * the segment that drew it into layer CLH_LAYER_POINT_ID(msaa) + s, by the same depth test
 * and its own atom_min:
 *  bits 63..40  depth code, the same 24 bits as the sample word's
 *  bits 39..8   point: the index of the segment's first point in the groom's point space
 *               (hair meshes: strand x CLH_MAX_CONTROL_POINTS + k; strand files: the
 *               strand's first stored point + k; k the point's index among the drawn ones),
 *               so the segment's second point is point + 1
 *  bits  7..0   t: where the sample lies between the two, 0 (the first) .. 255 (the
 *               second), perspective-correct
 * All ones is empty. The marked points are one bit each in a bitmap over the point space;
 * a point's slot in the lists below is its rank among the marked bits.                   */
#define CLH_LAYER_POINT_ID(msaa) ((clh_u32)(msaa) + 1u)
#define CLH_PT_T_MAX 255u
CLH_FN clh_u64 clh_pt_pack(clh_u32 depth24, clh_u32 point, clh_u32 t8) {
  return ((clh_u64)(depth24 & 0xFFFFFFu) << 40) | ((clh_u64)point << 8) | (clh_u64)(t8 & 0xFFu);
}
CLH_FN clh_u32 clh_pt_point(clh_u64 id) { return (clh_u32)(id >> 8); }
CLH_FN clh_u32 clh_pt_t(clh_u64 id) { return (clh_u32)id & 0xFFu; }
CLH_FN float clh_pt_fraction(clh_u64 id) { return (float)clh_pt_t(id) * (1.0f / 255.0f); }

/* A marked point's shading inputs, written by the point pass of the strand kernels
 * (CLH_RASTER_POINTS) at the point's slot and read by shade_points (shade.cl), 32 bytes.
 *   pos    world position; pos[3] its view depth
 *   word   the G-buffer word at the point, as the raster forms it there (tangent, u, v, w,
 *          AO; depth bits 0), low and high 32 bits                                       */
typedef struct {
  float pos[4];
  clh_u32 word_lo, word_hi;
  clh_u32 pad0, pad1;
} ClhPointGpu;

/* The point lists of one groom: the marked-point bitmap over `space` points (space / 32
 * + 1 words), then per bitmap word the marked points before it (its words + 1 entries, the
 * last the total). CLH_POINT_BLOCK words per block of the scan.                          */
#define CLH_POINT_BLOCK 32u
CLH_FN clh_u32 clh_point_words(clh_u32 space) { return space / 32u + 1u; }

/* ---- random numbers: identical streams on host and device ----------------------------
 * lowbias32 integer hash (Chris Wellons' hash-prospector), combined per key.            */
CLH_FN clh_u32 clh_hash(clh_u32 x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

CLH_FN clh_u32 clh_hash2(clh_u32 a, clh_u32 b) { return clh_hash(a ^ clh_hash(b + 0x9e3779b9u)); }

CLH_FN clh_u32 clh_hash3(clh_u32 a, clh_u32 b, clh_u32 c) { return clh_hash2(clh_hash2(a, b), c); }

/* Uniform float in [0, 1) from the top 24 bits of a hash. */
CLH_FN float clh_u01(clh_u32 h) { return (float)(h >> 8) * (1.0f / 16777216.0f); }

/* Stream identifiers: the per-strand random values used by styling and shading. */
#define CLH_RNG_LENGTH 1u
#define CLH_RNG_PHASE 2u
#define CLH_RNG_FLYAWAY 3u
#define CLH_RNG_FRIZZ 4u
#define CLH_RNG_CLUMP 5u
#define CLH_RNG_LOD_DELTA 6u
#define CLH_RNG_CHILD 7u

#ifndef CLH_DEVICE_CODE
} /* namespace gpu */
} /* namespace clhair */
#endif

#endif /* CLHAIR_GPU_TYPES_H */
