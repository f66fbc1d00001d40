/* cryptomatte.cl — the ranked (key, coverage) lists of the Cryptomatte layers
 * (clhair/cryptomatte.h), folded groom by groom on the device while a frame is drawn, one
 * work-item per pixel.
 *
 * Two layers (grooms, strands), each CRYPTO_RANKS ranks per pixel, plane-major: rank r of
 * pixel p at r * pixels + p, keys (ulong) and coverages (float) in separate buffers. A
 * pixel's ranks are sorted by coverage, largest first, equal coverages by smaller key; an
 * empty rank has key CRYPTO_NONE and coverage 0. The host gives each groom its key (equal
 * names, one key); a strand's key is its groom's key in the high 32 bits and its index at
 * full detail in the low 32.
 *
 * cryptomatte_groom runs after a groom's composite, which puts the groom's premultiplied hair
 * of alpha a over what is there: every coverage already listed keeps (1 - a) of itself and
 * the groom's own key gains a. The coverages of a pixel therefore add up to its hair alpha,
 * 1 - prod(1 - a_k) (aov.cl), and a groom alone in a pixel has exactly its alpha. `first`
 * starts the lists instead of reading them (the frame's first groom drawn). Beyond
 * CRYPTO_RANKS keys in one pixel the smallest coverage drops out.
 *
 * The strand of a pixel is the one in its centre identity word (CLH_LAYER_ID; after hair
 * linking the strand linked into it). A pixel with hair alpha and no identity (the filter
 * reconnected it from the conservative layer, or spread a strand's coverage into it) takes
 * the identity of the nearest pixel around it that has one, ring by ring out to
 * CLH_LINK_MAX_RADIUS; within a ring, the one whose depth code is nearest the pixel's own
 * word's (its centre word, else its conservative word). Without any, that groom's coverage
 * has no strand, and the strand layer's coverages add up to less than the hair alpha there.
 */
#include "clhair/gpu_types.h"

#pragma OPENCL FP_CONTRACT OFF

#ifndef CRYPTO_RANKS
#define CRYPTO_RANKS 6
#endif
#define CRYPTO_NONE 0xFFFFFFFFFFFFFFFFUL

/* Whether (ka, ca) ranks before (kb, cb). */
static inline bool crypto_before(ulong ka, float ca, ulong kb, float cb) {
  return ca > cb || (ca == cb && ka < kb);
}

/* Folds `key` with coverage `a` into the pixel's ranks (has_key 0: only scales them). */
static void crypto_fold(__global ulong* keys_g, __global float* cov_g, size_t p, size_t pixels,
                        uint first, ulong key, uint has_key, float a) {
  ulong k[CRYPTO_RANKS];
  float c[CRYPTO_RANKS];
  const float keep = 1.0f - a;
  for (uint r = 0; r < CRYPTO_RANKS; ++r) {
    k[r] = first ? CRYPTO_NONE : keys_g[r * pixels + p];
    c[r] = first ? 0.0f : cov_g[r * pixels + p] * keep;
    if (!(c[r] > 0.0f)) { /* covered over entirely: the rank empties */
      k[r] = CRYPTO_NONE;
      c[r] = 0.0f;
    }
  }
  if (has_key && a > 0.0f) {
    uint at = CRYPTO_RANKS;
    for (uint r = 0; r < CRYPTO_RANKS; ++r)
      if (k[r] == key) at = r;
    if (at < CRYPTO_RANKS) {
      c[at] += a;
    } else if (crypto_before(key, a, k[CRYPTO_RANKS - 1], c[CRYPTO_RANKS - 1])) {
      at = CRYPTO_RANKS - 1;
      k[at] = key;
      c[at] = a;
    }
  }
  /* insertion sort: empty ranks (coverage 0, the largest key) sink below the filled ones */
  for (uint r = 1; r < CRYPTO_RANKS; ++r)
    for (uint s = r; s > 0 && crypto_before(k[s], c[s], k[s - 1], c[s - 1]); --s) {
      const ulong tk = k[s];
      const float tc = c[s];
      k[s] = k[s - 1];
      c[s] = c[s - 1];
      k[s - 1] = tk;
      c[s - 1] = tc;
    }
  for (uint r = 0; r < CRYPTO_RANKS; ++r) {
    keys_g[r * pixels + p] = k[r];
    cov_g[r * pixels + p] = c[r];
  }
}

/* The strand of pixel (x, y), or CRYPTO_NONE (see the top of the file). */
static ulong crypto_strand(__global const ulong* gbuf_g, int x, int y, int width, int height) {
  const size_t pixels = (size_t)width * (size_t)height;
  const size_t p = (size_t)y * (size_t)width + (size_t)x;
  __global const ulong* ids_g = gbuf_g + (size_t)CLH_LAYER_ID * pixels;
  const ulong own = ids_g[p];
  if (own != CLH_GBUF_EMPTY) return (ulong)clh_id_strand(own);
  const ulong centre = gbuf_g[p];
  const ulong word = centre != CLH_GBUF_EMPTY ? centre : gbuf_g[pixels + p];
  const uint code = word != CLH_GBUF_EMPTY ? clh_gbuf_depth(word) : 0u;
  for (int ring = 1; ring <= CLH_LINK_MAX_RADIUS; ++ring) {
    ulong best = CLH_GBUF_EMPTY;
    uint best_gap = 0xFFFFFFFFu;
    for (int dy = -ring; dy <= ring; ++dy)
      for (int dx = -ring; dx <= ring; ++dx) {
        if (max(abs(dx), abs(dy)) != ring) continue;
        const int qx = x + dx, qy = y + dy;
        if (qx < 0 || qy < 0 || qx >= width || qy >= height) continue;
        const ulong id = ids_g[(size_t)qy * (size_t)width + (size_t)qx];
        if (id == CLH_GBUF_EMPTY) continue;
        const uint d = clh_gbuf_depth(id);
        const uint gap = d > code ? d - code : code - d;
        if (gap < best_gap) {
          best_gap = gap;
          best = id;
        }
      }
    if (best != CLH_GBUF_EMPTY) return (ulong)clh_id_strand(best);
  }
  return CRYPTO_NONE;
}

/* Groom `groom_key`'s hair (result_g: the premultiplied RGBA its composite blended; gbuf_g:
 * its G-buffer with the identity layer) folded into both layers' ranks. */
__kernel void cryptomatte_groom(uint width, uint height, uint first, uint groom_key,
                                __global const float4* result_g, __global const ulong* gbuf_g,
                                __global ulong* groom_keys_g, __global float* groom_cov_g,
                                __global ulong* strand_keys_g, __global float* strand_cov_g) {
  const int x = (int)get_global_id(0), y = (int)get_global_id(1);
  if (x >= (int)width || y >= (int)height) return;
  const size_t pixels = (size_t)width * (size_t)height;
  const size_t p = (size_t)y * (size_t)width + (size_t)x;
  /* the alpha the hair layer folds in (aov.cl): a groom's coverage where it is alone */
  const float a = fmin(fmax(result_g[p].w, 0.0f), 1.0f);
  if (!first && !(a > 0.0f)) return; /* keeps every coverage as it is */
  crypto_fold(groom_keys_g, groom_cov_g, p, pixels, first, (ulong)groom_key, 1u, a);
  const ulong strand =
      a > 0.0f ? crypto_strand(gbuf_g, x, y, (int)width, (int)height) : CRYPTO_NONE;
  crypto_fold(strand_keys_g, strand_cov_g, p, pixels, first,
              ((ulong)groom_key << 32) | (strand & 0xFFFFFFFFUL), strand != CRYPTO_NONE, a);
}
