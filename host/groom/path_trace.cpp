// path_trace.cpp — StrandTracer's path mode: a CPU path tracer through the grooms' round
// curves and the opaque scene, the reference with light scattered between fibres.
//
// Every path starts at the eye through the pixel (the R2 sub-pixel shifts of
// Renderer::renderReference, one per sample, so sample i of every pixel looks through the
// same point of it). At each scattering event it gathers every light by next-event
// estimation: a shadow ray to the light through the whole scene, blocked by any fibre or
// surface it meets (a fibre in the way is not a filter: the light that passes through it
// arrives along the paths that scatter at that fibre, which the continuation samples).
// Then the path continues in a direction drawn from the event's BSDF, with Russian
// roulette from the third event on:
// - at a fibre, the single-fibre BSDF of the shading pass (hair_bsdf_cpu.h: the same
//   h-averaged model, evaluated with the same material the shading kernel decodes from
//   the G-buffer word of that hit, a file colour's scale included), sampled lobe by lobe
//   (fibre_sampler.h: a lobe in proportion to its energy, theta_i from its M_p exactly,
//   phi from a table of its Ñ_p); the weight is f cos(theta_i) / pdf of that mixture.
//   Rays leaving a fibre start where the ray met it and skip the fibre
//   itself (SkipContext), so light sent through it (TT) leaves from its far side;
// - at an opaque surface, Lambert (albedo / pi), cosine-sampled.
// A continuation that leaves the scene brings back the ambient radiance (the scene's
// constant ambient as a uniform environment; the raster's baked AO stands for its
// occlusion); a camera ray that meets nothing sees the background colour.
// Each pixel's random numbers depend only on the seed, the pixel and the sample, so the
// image does not depend on the number of threads.
#include <atomic>
#include <cstring>
#include <limits>
#include <mutex>
#include <thread>

#include "groom/fibre_sampler.h"
#include "groom/hair_bsdf_cpu.h"
#include "groom/strand_tracer_impl.h"

namespace clhair {

namespace {

namespace hb = cpu_bsdf;
constexpr float kPiF = 3.14159265358979323846f;

// splitmix64 (Steele et al. 2014): a stream per pixel and sample
struct Rng {
  std::uint64_t s;
  float next() {
    s += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = s;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return static_cast<float>(z >> 40) * (1.0f / 16777216.0f);
  }
};

// Rays leaving a fibre at a point of its axis skip the fibre itself: its segment `prim` and
// the two beside it, and hits on the other segments lo..hi of its strand that lie within
// its radius (5 % margin) of the segment's line through the event (the way out of the
// fibre where segments are shorter than its width; a strand that curls back into the ray
// is hit).
struct SkipContext {
  RTCIntersectContext ctx;
  unsigned geom = RTC_INVALID_GEOMETRY_ID, lo = 0, hi = 0, prim = 0;
  float org[3] = {0.0f, 0.0f, 0.0f}, tangent[3] = {0.0f, 0.0f, 1.0f}, radius = 0.0f;
};

void skipOwnFibre(const RTCFilterFunctionNArguments* a) {
  const auto* c = reinterpret_cast<const SkipContext*>(a->context);
  for (unsigned i = 0; i < a->N; ++i) {
    if (a->valid[i] != -1) continue;
    const unsigned g = RTCHitN_geomID(a->hit, a->N, i);
    const unsigned p = RTCHitN_primID(a->hit, a->N, i);
    if (g != c->geom || p < c->lo || p > c->hi) continue;
    if (p + 1 >= c->prim && p <= c->prim + 1) {  // its segment and the two beside it
      a->valid[i] = 0;
      continue;
    }
    const float t = RTCRayN_tfar(a->ray, a->N, i);
    float d[3] = {RTCRayN_org_x(a->ray, a->N, i) + t * RTCRayN_dir_x(a->ray, a->N, i) - c->org[0],
                  RTCRayN_org_y(a->ray, a->N, i) + t * RTCRayN_dir_y(a->ray, a->N, i) - c->org[1],
                  RTCRayN_org_z(a->ray, a->N, i) + t * RTCRayN_dir_z(a->ray, a->N, i) - c->org[2]};
    const float along = d[0] * c->tangent[0] + d[1] * c->tangent[1] + d[2] * c->tangent[2];
    float off2 = 0.0f;
    for (int k = 0; k < 3; ++k) {
      const float e = d[k] - along * c->tangent[k];
      off2 += e * e;
    }
    if (off2 <= 1.1025f * c->radius * c->radius) a->valid[i] = 0;
  }
}

hb::clh_v3 v3(const float* p) { return hb::clh_v3_make(p[0], p[1], p[2]); }

// shade.cl's shade_material (and its file-colour override) for a G-buffer word. Returns
// whether the word holds a file colour, and then that colour in *fc.
bool materialOf(const gpu::ClhGroomGpu& g, bool fileColor, std::uint64_t word,
                hb::clh_hair_material* m, hb::clh_v3* fc) {
  using namespace gpu;
  const float u = clh_unorm_value(clh_gbuf_u(word), 6u), v = clh_unorm_value(clh_gbuf_v(word), 6u);
  const float w = clh_unorm_value(clh_gbuf_w(word), 6u);
  const clh_u32 key = clh_hash2(static_cast<clh_u32>(u * 63.0f + 0.5f),
                                static_cast<clh_u32>(v * 63.0f + 0.5f) ^ g.seed);
  const float vary = 1.0f + g.look[0] * (2.0f * clh_u01(key) - 1.0f);
  if (g.look[1] > 0.5f) {
    const float eu = (g.melanin[0] + (g.melanin[1] - g.melanin[0]) * w) * vary;
    const float pheo = (g.melanin[2] + (g.melanin[3] - g.melanin[2]) * w) * vary;
    m->sigma_a = hb::clh_hair_sigma_a_from_melanin(eu, pheo);
  } else {
    const hb::clh_v3 c = hb::clh_v3_make(g.root_color[0] + (g.tip_color[0] - g.root_color[0]) * w,
                                         g.root_color[1] + (g.tip_color[1] - g.root_color[1]) * w,
                                         g.root_color[2] + (g.tip_color[2] - g.root_color[2]) * w);
    m->sigma_a = hb::clh_v3_scale(hb::clh_hair_sigma_a_from_color(c, g.bsdf[1]), vary);
  }
  m->beta_m = g.bsdf[0];
  m->beta_n = g.bsdf[1];
  m->alpha = g.bsdf[2];
  m->eta = g.bsdf[3];
  if (!fileColor) return false;
  *fc = hb::clh_v3_make(clh_file_color_value(clh_gbuf_u(word)),
                        clh_file_color_value(clh_gbuf_v(word)),
                        clh_file_color_value(clh_gbuf_ao(word)));
  m->sigma_a = hb::clh_hair_sigma_a_from_albedo(*fc, g.bsdf[3]);
  return true;
}

// shade.cl's scale of a file-coloured fibre: its lobes keep the shapes of the absorption
// the colour maps to and are scaled so that their energies (the fibre's albedo at this
// view) sum to the file colour, per channel.
hb::clh_v3 fileColorTint(const hb::clh_hair_view& hv, hb::clh_v3 fc) {
  const hb::clh_v3 albedo = hb::clh_v3_add(hb::clh_v3_add(hv.mass[0], hv.mass[1]),
                                           hb::clh_v3_add(hv.mass[2], hv.mass[3]));
  return hb::clh_v3_make(fc.x / std::max(albedo.x, 1e-4f), fc.y / std::max(albedo.y, 1e-4f),
                         fc.z / std::max(albedo.z, 1e-4f));
}

// A unit vector about unit n, cosine-distributed.
hb::clh_v3 cosineAbout(hb::clh_v3 n, Rng& rng) {
  const float u1 = rng.next(), u2 = rng.next();
  const float r = std::sqrt(u1), phi = 2.0f * kPiF * u2;
  const hb::clh_v3 a =
      std::fabs(n.x) < 0.9f ? hb::clh_v3_make(1.0f, 0.0f, 0.0f) : hb::clh_v3_make(0.0f, 1.0f, 0.0f);
  hb::clh_v3 t = hb::clh_v3_sub(a, hb::clh_v3_scale(n, hb::clh_v3_dot(a, n)));
  t = hb::clh_v3_unit(t);
  const hb::clh_v3 b =
      hb::clh_v3_make(n.y * t.z - n.z * t.y, n.z * t.x - n.x * t.z, n.x * t.y - n.y * t.x);
  return hb::clh_v3_add(hb::clh_v3_add(hb::clh_v3_scale(t, r * std::cos(phi)),
                                       hb::clh_v3_scale(b, r * std::sin(phi))),
                        hb::clh_v3_scale(n, std::sqrt(std::max(0.0f, 1.0f - u1))));
}

void initRay(RTCRay& ray, hb::clh_v3 org, hb::clh_v3 dir, float tnear, float tfar) {
  ray.org_x = org.x;
  ray.org_y = org.y;
  ray.org_z = org.z;
  ray.dir_x = dir.x;
  ray.dir_y = dir.y;
  ray.dir_z = dir.z;
  ray.tnear = tnear;
  ray.tfar = tfar;
  ray.time = 0.0f;
  ray.mask = 0xFFFFFFFFu;
  ray.id = 0;
  ray.flags = 0;
}

}  // namespace

StrandTracer::PathImage StrandTracer::tracePaths(const PathSetup& ps) const {
  const Impl& r = *impl_;
  if (!r.pathMode || !r.committed)
    throw Error("StrandTracer::tracePaths: path mode, after commit()");
  if (ps.spp < 1 || ps.spp > 65536)
    throw Error("path reference: " + std::to_string(ps.spp) + " samples per pixel, need 1..65536");
  if (ps.maxEvents < 1) throw Error("path reference: at least one scattering event per path");
  const gpu::ClhViewGpu& view = ps.view;
  const std::uint32_t W = view.width, H = view.height;
  PathImage out;
  out.rgb.assign(3 * static_cast<std::size_t>(W) * H, 0.0f);
  out.depth.assign(static_cast<std::size_t>(W) * H, std::numeric_limits<float>::infinity());
  const float* m = view.world_to_view;
  const float inf = std::numeric_limits<float>::infinity();
  std::atomic<std::uint32_t> nextRow{0};
  std::atomic<std::uint64_t> rayTotal{0};
  std::mutex merge;

  // Light gathered at an event at `p` (skipping `skip`), for a BSDF value f cos per light
  // direction given by `eval`.
  auto gather = [&](hb::clh_v3 p, SkipContext& skip, std::uint64_t& rays, auto&& eval) {
    hb::clh_v3 sum = hb::clh_v3_splat(0.0f);
    for (const PathLight& l : ps.lights) {
      hb::clh_v3 L;
      float falloff = 1.0f, tfar = inf;
      if (l.point) {
        const hb::clh_v3 d = hb::clh_v3_sub(v3(l.pos), p);
        const float d2 = std::max(hb::clh_v3_dot(d, d), 1e-8f);
        const float dist = std::sqrt(d2);
        L = hb::clh_v3_scale(d, 1.0f / dist);
        falloff = 1.0f / d2;
        tfar = dist * (1.0f - 1e-5f);
      } else {
        L = v3(l.pos);
      }
      const hb::clh_v3 fc = eval(L);
      if (!(fc.x > 0.0f || fc.y > 0.0f || fc.z > 0.0f)) continue;
      RTCRay ray;
      initRay(ray, p, L, 0.0f, tfar);
      rtcOccluded1(r.scene, &skip.ctx, &ray);
      ++rays;
      if (ray.tfar < 0.0f) continue;  // blocked
      sum = hb::clh_v3_add(sum, hb::clh_v3_scale(hb::clh_v3_mul(v3(l.rgb), fc), falloff));
    }
    return sum;
  };

  auto work = [&] {
    std::uint64_t rays = 0;
    std::vector<double> escaped;
    SkipContext skip;
    rtcInitIntersectContext(&skip.ctx);
    skip.ctx.filter = skipOwnFibre;
    for (std::uint32_t y = nextRow++; y < H; y = nextRow++) {
      for (std::uint32_t x = 0; x < W; ++x) {
        const std::size_t idx = static_cast<std::size_t>(y) * W + x;
        double acc[3] = {0.0, 0.0, 0.0};
        for (int i = 0; i < ps.spp; ++i) {
          Rng rng{gpu::clh_hash3(ps.seed, static_cast<std::uint32_t>(idx),
                                 static_cast<std::uint32_t>(i)) *
                  0x100000001B3ull};
          // R2 shift (as renderReference), the first sample at the pixel centre
          const double g = 1.32471795724474602596;
          const float jx = static_cast<float>(std::fmod(0.5 + i / g, 1.0) - 0.5);
          const float jy = static_cast<float>(std::fmod(0.5 + i / (g * g), 1.0) - 0.5);
          hb::clh_v3 org = hb::clh_v3_splat(0.0f);
          hb::clh_v3 dir =
              hb::clh_v3_make((static_cast<float>(x) + 0.5f - jx - view.cx) / view.fx,
                              -(static_cast<float>(y) + 0.5f - jy - view.cy) / view.fy, 1.0f);
          float tnear = kNearZ;
          hb::clh_v3 thr = hb::clh_v3_splat(1.0f), L = hb::clh_v3_splat(0.0f);
          skip.geom = RTC_INVALID_GEOMETRY_ID;
          for (int event = 1;; ++event) {
            RTCRayHit rh;
            initRay(rh.ray, org, dir, tnear, inf);
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(r.scene, &skip.ctx, &rh);
            ++rays;
            const unsigned gid = rh.hit.geomID;
            if (gid == RTC_INVALID_GEOMETRY_ID) {
              const float* e = event == 1 ? ps.background : ps.ambient;
              const hb::clh_v3 in = hb::clh_v3_mul(thr, v3(e));
              L = hb::clh_v3_add(L, in);
              if (escaped.size() < static_cast<std::size_t>(event)) escaped.resize(event, 0.0);
              escaped[event - 1] += (in.x + in.y + in.z) / (3.0 * ps.spp);
              break;
            }
            if (event == 1) out.depth[idx] = std::min(out.depth[idx], rh.ray.tfar);
            const hb::clh_v3 wo = hb::clh_v3_unit(hb::clh_v3_scale(dir, -1.0f));
            hb::clh_v3 next;
            if (gid < r.grooms.size() && rh.hit.primID < r.grooms[gid].segFirst.size()) {
              const Impl::Groom& gr = r.grooms[gid];
              Impl::Hit h;
              h.geom = gid;
              h.prim = rh.hit.primID;
              h.u = rh.hit.u;
              h.t = rh.ray.tfar;
              const std::uint64_t word = r.wordAt(h, gr, gr.params);
              float tw[3];
              gpu::clh_oct_decode(gpu::clh_gbuf_oct(word), tw);
              const hb::clh_v3 T =
                  hb::clh_v3_unit(hb::clh_v3_make(m[0] * tw[0] + m[1] * tw[1] + m[2] * tw[2],
                                                  m[4] * tw[0] + m[5] * tw[1] + m[6] * tw[2],
                                                  m[8] * tw[0] + m[9] * tw[1] + m[10] * tw[2]));
              hb::clh_hair_material mat;
              hb::clh_v3 fc;
              const bool tinted = materialOf(gr.params, gr.fileColor, word, &mat, &fc);
              hb::clh_hair_view hv;
              hb::clh_hair_prepare_to(&hv, &mat, T, wo);
              const hb::clh_v3 tint = tinted ? fileColorTint(hv, fc) : hb::clh_v3_splat(1.0f);
              // the event where the ray met the fibre; rays leaving it skip the fibre
              const std::uint32_t a = gr.segFirst[h.prim];
              const float u = std::clamp(h.u, 0.0f, 1.0f);
              const float* pa = &gr.axis[4 * a];
              const float* pb = pa + 4;
              const hb::clh_v3 axisPoint =
                  hb::clh_v3_add(v3(pa), hb::clh_v3_scale(hb::clh_v3_sub(v3(pb), v3(pa)), u));
              org = hb::clh_v3_add(org, hb::clh_v3_scale(dir, rh.ray.tfar));
              skip.geom = gid;
              skip.prim = h.prim;
              skip.lo = gr.strandSeg[h.prim];
              skip.hi = h.prim;
              while (skip.hi + 1 < gr.segFirst.size() && gr.strandSeg[skip.hi + 1] == skip.lo)
                ++skip.hi;
              skip.org[0] = axisPoint.x;
              skip.org[1] = axisPoint.y;
              skip.org[2] = axisPoint.z;
              // the segment's own direction: its cone is what the ray leaves
              const hb::clh_v3 seg = hb::clh_v3_sub(v3(pb), v3(pa));
              const hb::clh_v3 axisDir = hb::clh_v3_dot(seg, seg) > 0.0f ? hb::clh_v3_unit(seg) : T;
              skip.tangent[0] = axisDir.x;
              skip.tangent[1] = axisDir.y;
              skip.tangent[2] = axisDir.z;
              skip.radius = std::max(pa[3] + (pb[3] - pa[3]) * u, 0.0f);
              tnear = 0.0f;
              L = hb::clh_v3_add(L, hb::clh_v3_mul(thr, gather(org, skip, rays, [&](hb::clh_v3 wi) {
                                                     return hb::clh_v3_mul(
                                                         tint, hb::clh_hair_eval_cos(&hv, wi));
                                                   })));
              if (event >= ps.maxEvents) break;
              const FibreSampler sampler(hv, tint);
              const float us[4] = {rng.next(), rng.next(), rng.next(), rng.next()};
              next = sampler.sample(us);
              const float pdf = sampler.pdf(next);
              if (!(pdf > 0.0f)) break;
              thr = hb::clh_v3_mul(thr, hb::clh_v3_scale(sampler.evalCos(next), 1.0f / pdf));
            } else {
              const float* alb = gid < r.opaque.size() ? r.opaque[gid].albedo : nullptr;
              if (!alb) break;
              hb::clh_v3 n = hb::clh_v3_make(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
              const float n2 = hb::clh_v3_dot(n, n);
              if (!(n2 > 0.0f)) break;
              n = hb::clh_v3_scale(n, 1.0f / std::sqrt(n2));
              if (hb::clh_v3_dot(n, dir) > 0.0f) n = hb::clh_v3_scale(n, -1.0f);
              const hb::clh_v3 p = hb::clh_v3_add(org, hb::clh_v3_scale(dir, rh.ray.tfar));
              const float eps = 2e-5f + 1e-5f * std::sqrt(hb::clh_v3_dot(p, p));
              org = hb::clh_v3_add(p, hb::clh_v3_scale(n, eps));
              skip.geom = RTC_INVALID_GEOMETRY_ID;
              tnear = 0.0f;
              const hb::clh_v3 albedo = v3(alb);
              L = hb::clh_v3_add(
                  L, hb::clh_v3_mul(thr, gather(org, skip, rays, [&](hb::clh_v3 wi) {
                                      return hb::clh_v3_scale(
                                          albedo, std::max(hb::clh_v3_dot(n, wi), 0.0f) / kPiF);
                                    })));
              if (event >= ps.maxEvents) break;
              next = cosineAbout(n, rng);
              thr = hb::clh_v3_mul(thr, albedo);
            }
            if (event >= ps.rouletteAfter) {
              const float q = std::min(std::max(thr.x, std::max(thr.y, thr.z)), 0.95f);
              if (!(q > 0.0f) || rng.next() >= q) break;
              thr = hb::clh_v3_scale(thr, 1.0f / q);
            }
            dir = next;
          }
          acc[0] += L.x;
          acc[1] += L.y;
          acc[2] += L.z;
        }
        for (int c = 0; c < 3; ++c) out.rgb[3 * idx + c] = static_cast<float>(acc[c] / ps.spp);
      }
    }
    rayTotal += rays;
    const std::lock_guard<std::mutex> lock(merge);
    if (out.escapedAfter.size() < escaped.size()) out.escapedAfter.resize(escaped.size(), 0.0);
    for (std::size_t k = 0; k < escaped.size(); ++k) out.escapedAfter[k] += escaped[k];
  };
  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned i = 1; i < threads; ++i) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  out.rays = rayTotal;
  return out;
}

}  // namespace clhair
