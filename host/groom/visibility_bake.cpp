// visibility_bake.cpp — see visibility_bake.h.
#include "groom/visibility_bake.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>
#include <thread>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/vec4.hpp>

#include "clhair/error.h"
#include "clhair/visibility_sh.h"

namespace clhair {

namespace {

constexpr float kPi = 3.14159265358979323846f;

// A ray's context: Embree hands it to the curve filter, which counts the distinct strands
// the ray passes (a tube can report its entry and exit, and a ray can cross a strand at a
// joint of two segments) and rejects every hit so traversal continues.
struct CountContext {
  RTCIntersectContext base;  // first member: Embree passes &base
  const std::uint32_t* strandOfSegment = nullptr;
  std::uint32_t own = 0;  // the ray's own strand
  std::uint32_t seen[32];
  std::uint32_t count = 0;
};

void countStrands(const RTCFilterFunctionNArguments* args) {
  auto* c = reinterpret_cast<CountContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const std::uint32_t strand = c->strandOfSegment[RTCHitN_primID(args->hit, args->N, i)];
    // once the ray has counted kMaxEventsPerRay fibres its count is final: accepting the hit
    // shortens the ray to it, so only nearer candidates are still visited
    if (strand != c->own && c->count >= static_cast<std::uint32_t>(kMaxEventsPerRay)) continue;
    args->valid[i] = 0;  // otherwise reject: every fibre along the ray is counted
    if (strand == c->own) continue;
    const std::uint32_t n = std::min<std::uint32_t>(c->count, 32);
    bool found = false;
    for (std::uint32_t k = 0; k < n && !found; ++k) found = c->seen[k] == strand;
    if (found) continue;
    if (c->count < 32) c->seen[c->count] = strand;
    ++c->count;
  }
}

struct EmbreeScene {
  RTCDevice device = nullptr;
  RTCScene hair = nullptr, head = nullptr;
  ~EmbreeScene() {
    if (hair) rtcReleaseScene(hair);
    if (head) rtcReleaseScene(head);
    if (device) rtcReleaseDevice(device);
  }
  void check(const char* what) const {
    const RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE)
      throw Error(std::string("visibility bake: Embree failed while ") + what + " (error " +
                  std::to_string(static_cast<int>(e)) + ")");
  }
};

}  // namespace

void sphereDirections(std::uint32_t count, std::uint32_t seed, float* out) {
  // golden-angle spiral with equal-area z bands; the seed turns it about z and jitters z
  // within each band, so neighbouring points see different directions
  const float golden = kPi * (3.0f - std::sqrt(5.0f));
  const std::uint32_t h = gpu::clh_hash(seed);
  const float phi0 = 2.0f * kPi * gpu::clh_u01(h);
  const float jitter = gpu::clh_u01(gpu::clh_hash(h)) - 0.5f;
  for (std::uint32_t k = 0; k < count; ++k) {
    const float z =
        1.0f - (2.0f * (static_cast<float>(k) + 0.5f + 0.98f * jitter)) / static_cast<float>(count);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = phi0 + golden * static_cast<float>(k);
    out[3 * k] = r * std::cos(phi);
    out[3 * k + 1] = r * std::sin(phi);
    out[3 * k + 2] = z;
  }
}

void projectL1(const float* dirs, const float* values, std::uint32_t count, float out[4]) {
  double c[4] = {0.0, 0.0, 0.0, 0.0};
  for (std::uint32_t k = 0; k < count; ++k) {
    const double f = values[k];
    c[0] += f * CLH_SH_Y0;
    c[1] += f * CLH_SH_Y1 * dirs[3 * k + 1];
    c[2] += f * CLH_SH_Y1 * dirs[3 * k + 2];
    c[3] += f * CLH_SH_Y1 * dirs[3 * k];
  }
  const double w = count > 0 ? 4.0 * 3.14159265358979323846 / count : 0.0;
  for (int i = 0; i < 4; ++i) out[i] = static_cast<float>(c[i] * w);
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
  if (!(fibreRadius > 0.0f) || !std::isfinite(fibreRadius))
    throw Error("visibility bake: fibre radius " + std::to_string(fibreRadius) +
                " is not positive");
  if (triIndices.size() % 3 != 0)
    throw Error("visibility bake: occluder indices are not whole triangles");
  for (std::uint32_t i : triIndices)
    if (i >= triPositions.size()) throw Error("visibility bake: occluder index out of range");

  EmbreeScene es;
  es.device = rtcNewDevice(nullptr);
  if (!es.device) throw Error("visibility bake: Embree could not create a device");
  es.hair = rtcNewScene(es.device);
  es.head = rtcNewScene(es.device);
  es.check("creating the scenes");
  rtcSetSceneFlags(es.hair, RTC_SCENE_FLAG_ROBUST);

  // the strands as round linear curves; strandOf maps a segment to its strand
  std::vector<std::uint32_t> segFirst, strandOf, pointStrand(P);
  std::vector<unsigned char> flags;
  std::size_t at = 0;
  for (std::size_t st = 0; st < S; ++st) {
    const std::uint32_t n = s.pointCounts[st];
    if (at + n > P) throw Error("visibility bake: point counts exceed the exported points");
    for (std::uint32_t k = 0; k < n; ++k) {
      pointStrand[at + k] = static_cast<std::uint32_t>(st);
      if (k + 1 < n) {
        segFirst.push_back(static_cast<std::uint32_t>(at + k));
        strandOf.push_back(static_cast<std::uint32_t>(st));
        flags.push_back(
            static_cast<unsigned char>((k > 0 ? RTC_CURVE_FLAG_NEIGHBOR_LEFT : 0) |
                                       (k + 2 < n ? RTC_CURVE_FLAG_NEIGHBOR_RIGHT : 0)));
      }
    }
    at += n;
  }
  if (!segFirst.empty()) {
    RTCGeometry g = rtcNewGeometry(es.device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
    auto* vb = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 16, P));
    auto* ib = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, 4, segFirst.size()));
    auto* fb = static_cast<unsigned char*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_FLAGS, 0, RTC_FORMAT_UCHAR, 1, flags.size()));
    if (!vb || !ib || !fb) {
      rtcReleaseGeometry(g);
      es.check("allocating the strands");
      throw Error("visibility bake: Embree could not allocate the strands");
    }
    for (std::size_t i = 0; i < P; ++i) {
      vb[4 * i] = s.points[3 * i];
      vb[4 * i + 1] = s.points[3 * i + 1];
      vb[4 * i + 2] = s.points[3 * i + 2];
      vb[4 * i + 3] = fibreRadius;
    }
    std::copy(segFirst.begin(), segFirst.end(), ib);
    std::copy(flags.begin(), flags.end(), fb);
    rtcSetGeometryIntersectFilterFunction(g, countStrands);
    rtcCommitGeometry(g);
    rtcAttachGeometry(es.hair, g);
    rtcReleaseGeometry(g);
  }
  if (!triIndices.empty()) {
    RTCGeometry g = rtcNewGeometry(es.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, triPositions.size()));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, triIndices.size() / 3));
    if (!vb || !ib) {
      rtcReleaseGeometry(g);
      throw Error("visibility bake: Embree could not allocate the occluders");
    }
    for (std::size_t i = 0; i < triPositions.size(); ++i) {
      vb[3 * i] = triPositions[i].x;
      vb[3 * i + 1] = triPositions[i].y;
      vb[3 * i + 2] = triPositions[i].z;
    }
    std::copy(triIndices.begin(), triIndices.end(), ib);
    rtcCommitGeometry(g);
    rtcAttachGeometry(es.head, g);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(es.hair);
  rtcCommitScene(es.head);
  es.check("building the BVHs");

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
    for (std::uint32_t k = 0; k < K; ++k)
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
  const std::uint32_t R = o.raysPerPoint;
  auto work = [&] {
    std::vector<float> dirs(3 * R), values(R);
    std::uint64_t traced = 0, hit = 0, events = 0;
    for (std::size_t ci = next++; ci < cells.size(); ci = next++) {
      const std::uint32_t cell = cells[ci];
      float sum[4] = {0, 0, 0, 0};
      std::uint32_t n = 0;
      for (std::uint32_t k = 0; k < K; ++k) {
        const std::uint64_t key = chosen[std::size_t(cell) * K + k];
        if (key == ~0ull) continue;
        const auto i = static_cast<std::uint32_t>(key & 0xFFFFFFFFu);
        sphereDirections(R, i, dirs.data());
        for (std::uint32_t r = 0; r < R; ++r) {
          RTCRayHit rh{};
          rh.ray.org_x = s.points[3 * i];
          rh.ray.org_y = s.points[3 * i + 1];
          rh.ray.org_z = s.points[3 * i + 2];
          rh.ray.dir_x = dirs[3 * r];
          rh.ray.dir_y = dirs[3 * r + 1];
          rh.ray.dir_z = dirs[3 * r + 2];
          rh.ray.tnear = 0.0f;
          rh.ray.tfar = std::numeric_limits<float>::infinity();
          rh.ray.mask = 0xFFFFFFFFu;
          rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
          RTCIntersectContext hctx;
          rtcInitIntersectContext(&hctx);
          rtcIntersect1(es.head, &hctx, &rh);
          const bool head = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
          CountContext cc;
          rtcInitIntersectContext(&cc.base);
          cc.strandOfSegment = strandOf.data();
          cc.own = pointStrand[i];
          RTCRayHit hr{};
          hr.ray = rh.ray;
          hr.ray.tnear = 0.0f;
          hr.ray.tfar = head ? rh.ray.tfar : std::numeric_limits<float>::infinity();
          hr.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          hr.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
          rtcIntersect1(es.hair, &cc.base, &hr);  // the filter rejects (and counts) every hit
          float e = static_cast<float>(cc.count) + (head ? CLH_HAIR_MAX_SCATTER_EVENTS : 0.0f);
          e = std::min(e, kMaxEventsPerRay);
          if (e > 0.0f) {
            ++hit;
            events += static_cast<std::uint64_t>(e);
          }
          values[r] = e > 0.0f ? e : -CLH_HAIR_MAX_SCATTER_EVENTS;
        }
        float c[4];
        projectL1(dirs.data(), values.data(), R, c);
        for (int q = 0; q < 4; ++q) sum[q] += c[q];
        ++n;
        ++traced;
      }
      for (int q = 0; q < 4; ++q)
        bake.sh[std::size_t(cell) * CLH_VIS_COEFFS + q] = sum[q] / static_cast<float>(n);
    }
    pointsTraced += traced;
    raysHit += hit;
    eventSum += events;
  };
  const unsigned threads =
      o.threads > 0 ? o.threads : std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  es.check("tracing");
  // A G-buffer word's w is interpolated along its segment, so a strand with fewer points
  // than w cells reaches cells no sample point fell into: fill each (u, v) column's gaps by
  // linear interpolation between its baked cells along w (nearest beyond its ends).
  std::vector<char> baked(CLH_VIS_CELLS, 0);
  for (std::uint32_t c : cells) baked[c] = 1;
  for (std::uint32_t col = 0; col < CLH_VIS_AXIS * CLH_VIS_AXIS; ++col) {
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
  if (stats) {
    stats->cells = cells.size();
    stats->points = pointsTraced;
    stats->rays = pointsTraced * R;
    stats->meanEvents = raysHit > 0 ? static_cast<double>(eventSum) / raysHit : 0.0;
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
  const StrandSet strands = gi.mesh ? r.generateStrands(*gi.mesh) : r.generateStrands(*gi.strands);
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
