// visibility_bake.cpp — see visibility_bake.h.
#include "groom/visibility_bake.h"

#include <embree3/rtcore.h>

#include <sys/mman.h>
#include <time.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <mutex>
#include <string>
#include <thread>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/vec4.hpp>

#include "clhair/error.h"
#include "clhair/visibility_sh.h"
#include "groom/bake_scene.h"

namespace clhair {

namespace {

constexpr float kPi = 3.14159265358979323846f;

double clockSeconds(clockid_t id) {
  timespec t{};
  clock_gettime(id, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// The calling thread's time on a CPU and waiting on a run queue, in seconds, from
// /proc/thread-self/schedstat; {-1, -1} where the kernel does not keep it.
std::pair<double, double> threadSchedSeconds() {
  std::ifstream in("/proc/thread-self/schedstat");
  unsigned long long run = 0, wait = 0;
  if (!(in >> run >> wait)) return {-1.0, -1.0};
  return {1e-9 * static_cast<double>(run), 1e-9 * static_cast<double>(wait)};
}

}  // namespace

BakePhaseTimer::BakePhaseTimer(VisibilityBakeStats* stats)
    : stats_(stats),
      wall0_(clockSeconds(CLOCK_MONOTONIC)),
      cpu0_(clockSeconds(CLOCK_PROCESS_CPUTIME_ID)) {}

BakePhase& BakePhaseTimer::finish(const std::string& name) {
  const double wall = clockSeconds(CLOCK_MONOTONIC), cpu = clockSeconds(CLOCK_PROCESS_CPUTIME_ID);
  BakePhase p;
  p.name = name;
  p.wallSeconds = wall - wall0_;
  p.cpuSeconds = cpu - cpu0_;
  wall0_ = wall;
  cpu0_ = cpu;
  if (!stats_) return scratch_ = p;
  stats_->phases.push_back(p);
  return stats_->phases.back();
}

VisibilityBake bakeVisibility(const StrandSet& s, float fibreRadius,
                              const std::vector<glm::vec3>& triPositions,
                              const std::vector<std::uint32_t>& triIndices,
                              std::uint32_t groomStrands, const VisibilityBakeOptions& o,
                              VisibilityBakeStats* stats) {
  const std::size_t P = s.points.size() / 3, S = s.pointCounts.size();
  if (s.w.size() != P || s.uv.size() != 2 * S)
    throw Error("visibility bake: the exported strands have inconsistent array sizes");
  if (o.raysPerPoint == 0 || o.raysPerPoint > 4096 || o.pointsPerCell == 0 || o.pointsPerCell > 64)
    throw Error("visibility bake: " + std::to_string(o.raysPerPoint) + " rays per point and " +
                std::to_string(o.pointsPerCell) + " points per cell, need 1..4096 and 1..64");
  if (o.maxEvents == 0 || o.maxEvents > kMaxEventsLimit)
    throw Error("visibility bake: a cap of " + std::to_string(o.maxEvents) +
                " events per ray, need 1.." + std::to_string(kMaxEventsLimit));
  if (o.transmittance && o.directions != VisibilityBakeOptions::Directions::PerPoint)
    throw Error("visibility bake: the transmittance study traces per-point directions");
  if (o.cellStride == 0)
    throw Error("visibility bake: a cell stride of 0, need 1 or more (1: every cell)");
  if (!(fibreRadius > 0.0f) || !std::isfinite(fibreRadius))
    throw Error("visibility bake: fibre radius " + std::to_string(fibreRadius) +
                " is not positive");
  if (triIndices.size() % 3 != 0)
    throw Error("visibility bake: occluder indices are not whole triangles");
  for (std::uint32_t i : triIndices)
    if (i >= triPositions.size()) throw Error("visibility bake: occluder index out of range");

  BakePhaseTimer timer(stats);
  EmbreeScene es;
  std::vector<std::uint32_t> pointStrand, strandOf;
  buildBakeScene(es, s, fibreRadius, triPositions, triIndices, pointStrand, strandOf);
  timer.finish("segments");
  rtcCommitScene(es.hair);
  rtcCommitScene(es.head);
  es.check("building the BVHs");
  timer.finish("bvh");

  // each cell keeps the pointsPerCell points of smallest hash: key = hash << 32 | point
  const std::uint32_t K = o.pointsPerCell;
  std::vector<std::uint64_t> chosen(std::size_t(CLH_VIS_CELLS) * K, ~0ull);
  for (std::size_t i = 0; i < P; ++i) {
    const std::uint32_t st = pointStrand[i];
    const std::uint32_t cell = gpu::clh_vis_cell(gpu::clh_unorm_bits(s.uv[2 * st], 6u),
                                                 gpu::clh_unorm_bits(s.uv[2 * st + 1], 6u),
                                                 gpu::clh_unorm_bits(s.w[i], 6u));
    const std::uint64_t key =
        std::uint64_t(gpu::clh_hash2(static_cast<std::uint32_t>(i), 0x5ee1u)) << 32 | i;
    std::uint64_t* slot = &chosen[std::size_t(cell) * K];
    std::uint32_t worst = 0;
    for (std::uint32_t k = 1; k < K; ++k)
      if (slot[k] > slot[worst]) worst = k;
    if (key < slot[worst]) slot[worst] = key;
  }
  std::vector<std::uint32_t> cells;  // cells with at least one point
  for (std::uint32_t c = 0; c < CLH_VIS_CELLS; ++c)
    for (std::uint32_t k = 0; k < K && gpu::clh_hash2(c, 0xce115u) % o.cellStride == 0; ++k)
      if (chosen[std::size_t(c) * K + k] != ~0ull) {
        cells.push_back(c);
        break;
      }

  VisibilityBake bake;
  bake.strands = groomStrands;
  bake.raysPerPoint = o.raysPerPoint;
  bake.pointsPerCell = K;
  bake.maxScatterEvents = CLH_HAIR_MAX_SCATTER_EVENTS;
  bake.sh.assign(std::size_t(CLH_VIS_CELLS) * CLH_VIS_COEFFS, 0.0f);
  std::atomic<std::size_t> next{0};
  std::atomic<std::uint64_t> pointsTraced{0}, raysHit{0}, eventSum{0};
  std::mutex schedMutex;
  double waitSum = 0.0;
  bool waitKnown = true;
  timer.finish("samples");
  const std::uint32_t R = o.raysPerPoint;
  const auto maxEvents = static_cast<float>(o.maxEvents);
  std::vector<float> transmittance(
      o.transmittance ? std::size_t(kTransmittanceAbsorptions) * CLH_VIS_CELLS * R : 0, 0.0f);
  std::vector<float> fixedDirs(o.transmittance ? 3 * std::size_t(R) : 0);
  if (o.transmittance) fibonacciDirections(R, fixedDirs.data());
  auto work = [&] {
    const std::pair<double, double> sched0 = threadSchedSeconds();
    std::vector<float> cellDirs(3 * std::size_t(R) * K), dirs(3 * R), values(R);
    std::uint64_t traced = 0, hit = 0, events = 0;
    for (std::size_t ci = next++; ci < cells.size(); ci = next++) {
      const std::uint32_t cell = cells[ci];
      float sum[4] = {0, 0, 0, 0};
      // the cell's points in slot order (a slot is filled only after every one before it)
      std::uint64_t keys[64];
      const std::uint64_t* slots = &chosen[std::size_t(cell) * K];
      const auto n = static_cast<std::uint32_t>(std::find(slots, slots + K, ~0ull) - slots);
      std::copy_n(slots, n, keys);
      // PerCell: one stratified set of n x R directions for the cell, seeded by its point of
      // smallest hash, dealt out to its n points in turn (point k takes directions k, k + n,
      // ...), so the union of the cell's rays covers the sphere evenly; PerPoint: every point
      // its own set of R. Averaged over the points, both are the cell's L1 projection with
      // every ray weighing 4 pi / (n R).
      const bool perCell = o.directions == VisibilityBakeOptions::Directions::PerCell;
      if (perCell) {
        std::sort(keys, keys + n);
        sphereDirections(n * R, static_cast<std::uint32_t>(keys[0] & 0xFFFFFFFFu), cellDirs.data());
      }
      for (std::uint32_t k = 0; k < n; ++k) {
        const auto i = static_cast<std::uint32_t>(keys[k] & 0xFFFFFFFFu);
        if (perCell) {
          for (std::uint32_t r = 0; r < R; ++r)
            std::copy_n(&cellDirs[3 * (std::size_t(r) * n + k)], 3, &dirs[3 * r]);
        } else if (o.transmittance) {
          std::copy(fixedDirs.begin(), fixedDirs.end(), dirs.begin());
        } else {
          sphereDirections(R, i, dirs.data());
        }
        const float* org = &s.points[3 * std::size_t(i)];
        for (std::uint32_t r0 = 0; r0 < R; r0 += kPacket) {
          const std::uint32_t m = std::min<std::uint32_t>(kPacket, R - r0);
          alignas(64) int valid[kPacket];
          alignas(64) RTCRayHit16 rh;
          for (unsigned l = 0; l < kPacket; ++l) {
            const std::uint32_t r = r0 + std::min<std::uint32_t>(l, m - 1);
            valid[l] = l < m ? -1 : 0;
            rh.ray.org_x[l] = org[0];
            rh.ray.org_y[l] = org[1];
            rh.ray.org_z[l] = org[2];
            rh.ray.dir_x[l] = dirs[3 * r];
            rh.ray.dir_y[l] = dirs[3 * r + 1];
            rh.ray.dir_z[l] = dirs[3 * r + 2];
            rh.ray.tnear[l] = 0.0f;
            rh.ray.tfar[l] = std::numeric_limits<float>::infinity();
            rh.ray.time[l] = 0.0f;
            rh.ray.mask[l] = 0xFFFFFFFFu;
            rh.ray.id[l] = l;
            rh.ray.flags[l] = 0;
            rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
          }
          RTCIntersectContext hctx;
          rtcInitIntersectContext(&hctx);
          rtcIntersect16(valid, es.head, &hctx, &rh);
          CountContext cc;
          rtcInitIntersectContext(&cc.base);
          cc.strandOfSegment = strandOf.data();
          cc.own = pointStrand[i];
          bool head[kPacket];
          for (unsigned l = 0; l < kPacket; ++l) {
            head[l] = rh.hit.geomID[l] != RTC_INVALID_GEOMETRY_ID;
            // past this many fibres the ray's events are clamped to maxEvents (a ray toward
            // the head already holds its HAIR_MAX_SCATTER_EVENTS)
            const auto headEvents = static_cast<std::uint32_t>(CLH_HAIR_MAX_SCATTER_EVENTS);
            cc.cap[l] = !head[l]                   ? o.maxEvents
                        : o.maxEvents > headEvents ? o.maxEvents - headEvents
                                                   : 0u;
            cc.count[l] = 0;
          }
          // the hair in packets of 8 (measured faster than 16 or single rays here)
          for (unsigned h = 0; h < m; h += 8) {
            alignas(32) RTCRay8 r8;
            for (unsigned l = 0; l < 8; ++l) {
              r8.org_x[l] = rh.ray.org_x[h + l];
              r8.org_y[l] = rh.ray.org_y[h + l];
              r8.org_z[l] = rh.ray.org_z[h + l];
              r8.dir_x[l] = rh.ray.dir_x[h + l];
              r8.dir_y[l] = rh.ray.dir_y[h + l];
              r8.dir_z[l] = rh.ray.dir_z[h + l];
              r8.tnear[l] = 0.0f;
              r8.tfar[l] = rh.ray.tfar[h + l];  // the head's distance, or unbounded
              r8.time[l] = 0.0f;
              r8.mask[l] = 0xFFFFFFFFu;
              r8.id[l] = h + l;  // the filter's index into cc
              r8.flags[l] = 0;
            }
            rtcOccluded8(valid + h, es.hair, &cc.base, &r8);  // the filter counts the fibres
          }
          for (unsigned l = 0; l < m; ++l) {
            float e =
                static_cast<float>(cc.count[l]) + (head[l] ? CLH_HAIR_MAX_SCATTER_EVENTS : 0.0f);
            e = std::min(e, maxEvents);
            if (e > 0.0f) {
              ++hit;
              events += static_cast<std::uint64_t>(e);
            }
            values[r0 + l] = e > 0.0f ? e : -CLH_HAIR_MAX_SCATTER_EVENTS;
            for (std::uint32_t a = 0; a < kTransmittanceAbsorptions && o.transmittance; ++a)
              transmittance[(std::size_t(a) * CLH_VIS_CELLS + cell) * R + r0 + l] +=
                  std::exp(-kTransmittanceAbsorption[a] * e) / static_cast<float>(n);
          }
        }
        float c[4];
        projectL1(dirs.data(), values.data(), R, c);
        for (int q = 0; q < 4; ++q) sum[q] += c[q];
        ++traced;
      }
      for (int q = 0; q < 4; ++q)
        bake.sh[std::size_t(cell) * CLH_VIS_COEFFS + q] = sum[q] / static_cast<float>(n);
    }
    pointsTraced += traced;
    raysHit += hit;
    eventSum += events;
    const std::pair<double, double> sched1 = threadSchedSeconds();
    const std::lock_guard<std::mutex> lock(schedMutex);
    waitKnown = waitKnown && sched0.second >= 0.0 && sched1.second >= 0.0;
    waitSum += sched1.second - sched0.second;
  };
  const unsigned threads =
      o.threads > 0 ? o.threads : std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  es.check("tracing");
  BakePhase& trace = timer.finish("trace");
  trace.threads = threads;
  trace.waitSeconds = waitKnown ? waitSum : -1.0;
  // A G-buffer word's w is interpolated along its segment, so a strand with fewer points
  // than w cells reaches cells no sample point fell into: fill each (u, v) column's gaps by
  // linear interpolation between its baked cells along w (nearest beyond its ends). A bake
  // of a cell sample (cellStride > 1) leaves the rest zero.
  std::vector<char> baked(CLH_VIS_CELLS, 0);
  for (std::uint32_t c : cells) baked[c] = 1;
  const std::uint32_t columns = o.cellStride == 1 ? CLH_VIS_AXIS * CLH_VIS_AXIS : 0;
  for (std::uint32_t col = 0; col < columns; ++col) {
    const std::uint32_t base = col * CLH_VIS_AXIS;
    int prev = -1;
    for (int w = 0; w <= static_cast<int>(CLH_VIS_AXIS); ++w) {
      const bool end = w == static_cast<int>(CLH_VIS_AXIS);
      if (!end && !baked[base + w]) continue;
      const int from = prev < 0 ? 0 : prev + 1, to = end ? static_cast<int>(CLH_VIS_AXIS) : w;
      for (int g = from; g < to && (prev >= 0 || !end); ++g) {
        const float* a = &bake.sh[std::size_t(base + (prev >= 0 ? prev : w)) * CLH_VIS_COEFFS];
        const float* b = &bake.sh[std::size_t(base + (end ? prev : w)) * CLH_VIS_COEFFS];
        const float t = prev >= 0 && !end ? static_cast<float>(g - prev) / (w - prev) : 0.0f;
        for (std::uint32_t q = 0; q < CLH_VIS_COEFFS; ++q)
          bake.sh[std::size_t(base + g) * CLH_VIS_COEFFS + q] = a[q] + (b[q] - a[q]) * t;
      }
      if (!end) prev = w;
    }
  }
  timer.finish("fill");
  if (stats) {
    stats->cells = cells.size();
    stats->points = pointsTraced;
    stats->rays = pointsTraced * R;
    stats->meanEvents = raysHit > 0 ? static_cast<double>(eventSum) / raysHit : 0.0;
    stats->transmittance = std::move(transmittance);
  }
  return bake;
}

VisibilityBake bakeGroomVisibility(Renderer& r, const Scene& s, std::size_t groom,
                                   const VisibilityBakeOptions& options,
                                   VisibilityBakeStats* stats) {
  if (groom >= s.grooms.size())
    throw Error("bake-visibility: groom " + std::to_string(groom) +
                " does not exist, the scene has " + std::to_string(s.grooms.size()));
  const GroomInstance& gi = s.grooms[groom];
  BakePhaseTimer timer(stats);
  const StrandSet strands = gi.mesh ? r.generateStrands(*gi.mesh) : r.generateStrands(*gi.strands);
  timer.finish("strands");
  const glm::mat4 toObj = glm::inverse(gi.transform);
  const float scale = std::cbrt(std::fabs(glm::determinant(glm::mat3(gi.transform))));
  const float width =
      gi.mesh ? gi.mesh->appearance.strandWidth : gi.strands->appearance.strandWidth;
  const float radius = 0.5f * width / std::max(scale, 1e-20f);
  std::vector<glm::vec3> pos;
  std::vector<std::uint32_t> idx;
  auto add = [&](const glm::vec3& world) {
    pos.push_back(glm::vec3(toObj * glm::vec4(world, 1.0f)));
  };
  constexpr int kRings = 24, kSegments = 48;  // sphere tessellation: 1 % radial error
  for (const Sphere& sp : s.spheres) {
    const auto base = static_cast<std::uint32_t>(pos.size());
    for (int i = 0; i <= kRings; ++i) {
      const float th = kPi * static_cast<float>(i) / kRings;
      for (int j = 0; j < kSegments; ++j) {
        const float ph = 2.0f * kPi * static_cast<float>(j) / kSegments;
        add(sp.center + sp.radius * glm::vec3(std::sin(th) * std::cos(ph), std::cos(th),
                                              std::sin(th) * std::sin(ph)));
      }
    }
    for (int i = 0; i < kRings; ++i)
      for (int j = 0; j < kSegments; ++j) {
        const std::uint32_t a = base + i * kSegments + j,
                            b = base + i * kSegments + (j + 1) % kSegments;
        const std::uint32_t c = a + kSegments, d = b + kSegments;
        idx.insert(idx.end(), {a, c, b, b, c, d});
      }
  }
  for (const MeshInstance& m : s.meshes) {
    if (!m.mesh) continue;
    const auto base = static_cast<std::uint32_t>(pos.size());
    for (const glm::vec3& p : m.mesh->positions) add(glm::vec3(m.transform * glm::vec4(p, 1.0f)));
    for (std::uint32_t i : m.mesh->indices) idx.push_back(base + i);
  }
  const std::uint64_t groomStrands =
      gi.mesh ? static_cast<std::uint64_t>(gi.mesh->strandCount) : gi.strands->pointCounts.size();
  return bakeVisibility(strands, radius, pos, idx, static_cast<std::uint32_t>(groomStrands),
                        options, stats);
}

}  // namespace clhair
