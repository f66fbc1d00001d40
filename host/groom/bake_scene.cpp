// bake_scene.cpp — see bake_scene.h.
#include "groom/bake_scene.h"

#include <sys/mman.h>

#include <algorithm>
#include <limits>
#include <utility>

namespace clhair {

void countStrands(const RTCFilterFunctionNArguments* args) {
  auto* c = reinterpret_cast<CountContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const std::uint32_t lane = RTCRayN_id(args->ray, args->N, i) % kPacket;
    const std::uint32_t strand = c->strandOfSegment[RTCHitN_primID(args->hit, args->N, i)];
    std::uint32_t& count = c->count[lane];
    if (strand != c->own && count >= c->cap[lane]) continue;  // accept: the count is final
    args->valid[i] = 0;  // otherwise reject: every fibre along the ray is counted
    if (strand == c->own) continue;
    const std::uint32_t* seen = c->seen[lane];
    bool found = false;
    for (std::uint32_t k = 0; k < count && !found; ++k) found = seen[k] == strand;
    if (found) continue;
    c->seen[lane][count++] = strand;
  }
}

void buildBakeScene(EmbreeScene& es, const StrandSet& s, float fibreRadius,
                    const std::vector<glm::vec3>& triPositions,
                    const std::vector<std::uint32_t>& triIndices,
                    std::vector<std::uint32_t>& pointStrand, std::vector<std::uint32_t>& strandOf) {
  const std::size_t P = s.points.size() / 3, S = s.pointCounts.size();
  es.device = rtcNewDevice("hugepages=1");  // the BVH nodes on huge pages (fewer TLB misses)
  if (!es.device) throw Error("visibility bake: Embree could not create a device");
  es.hair = rtcNewScene(es.device);
  es.head = rtcNewScene(es.device);
  es.check("creating the scenes");
  rtcSetSceneFlags(es.hair, RTC_SCENE_FLAG_ROBUST);

  // Every segment is its own round linear curve (two vertices, no neighbour flags: the
  // union of the cones and end spheres is the same tube, and a strand is counted once
  // whichever of its segments a ray meets), and the segments are stored in Morton order of
  // their midpoints, so the segments of a BVH leaf lie together in memory: a leaf's vertex
  // gather, where most of the tracing time went, touches a few cache lines instead of one
  // per strand. strandOf maps a segment (Embree's primID) to its strand.
  pointStrand.assign(P, 0);
  std::vector<std::uint32_t> firstPoint(S);
  std::size_t at = 0;
  for (std::size_t st = 0; st < S; ++st) {
    const std::uint32_t n = s.pointCounts[st];
    if (at + n > P) throw Error("visibility bake: point counts exceed the exported points");
    firstPoint[st] = static_cast<std::uint32_t>(at);
    for (std::uint32_t k = 0; k < n; ++k) pointStrand[at + k] = static_cast<std::uint32_t>(st);
    at += n;
  }
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (std::size_t i = 0; i < P; ++i) {
    const glm::vec3 p(s.points[3 * i], s.points[3 * i + 1], s.points[3 * i + 2]);
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;  // (Morton code, first point)
  for (std::size_t st = 0; st < S; ++st) {
    const std::uint32_t n = s.pointCounts[st];
    for (std::uint32_t k = 0; k + 1 < n; ++k) {
      const std::size_t i = firstPoint[st] + k;
      std::uint32_t c[3];
      for (int d = 0; d < 3; ++d) {
        const float m = 0.5f * (s.points[3 * i + d] + s.points[3 * i + 3 + d]);
        const float t = hi[d] > lo[d] ? (m - lo[d]) / (hi[d] - lo[d]) : 0.0f;
        c[d] = static_cast<std::uint32_t>(std::clamp(t, 0.0f, 1.0f) * 1048575.0f);
      }
      std::uint64_t code = 0;
      for (int bit = 19; bit >= 0; --bit)
        for (int d = 0; d < 3; ++d) code = code << 1 | ((c[d] >> bit) & 1u);
      keyed.emplace_back(code, static_cast<std::uint32_t>(i));
    }
  }
  std::sort(keyed.begin(), keyed.end());
  strandOf.assign(keyed.size(), 0);
  for (std::size_t g = 0; g < keyed.size(); ++g) strandOf[g] = pointStrand[keyed[g].second];
  if (!keyed.empty()) {
    const std::size_t V = 2 * keyed.size();
    RTCGeometry g = rtcNewGeometry(es.device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
    // the vertices in our own allocation, 2 MiB aligned and advised onto huge pages
    constexpr std::size_t kHuge = std::size_t(2) << 20;
    const std::size_t bytes = (16 * V + kHuge - 1) / kHuge * kHuge;
    es.vertices = static_cast<float*>(std::aligned_alloc(kHuge, bytes));
    if (!es.vertices) {
      rtcReleaseGeometry(g);
      throw Error("visibility bake: out of memory for " + std::to_string(V) + " vertices");
    }
    madvise(es.vertices, bytes, MADV_HUGEPAGE);  // a hint: without it only slower
    float* vb = es.vertices;
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, vb, 0, 16, V);
    auto* ib = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, 4, keyed.size()));
    if (!ib) {
      rtcReleaseGeometry(g);
      es.check("allocating the strands");
      throw Error("visibility bake: Embree could not allocate the strands");
    }
    for (std::size_t q = 0; q < keyed.size(); ++q) {
      const std::size_t i = keyed[q].second;
      for (std::size_t e = 0; e < 2; ++e) {
        float* v = vb + 4 * (2 * q + e);
        v[0] = s.points[3 * (i + e)];
        v[1] = s.points[3 * (i + e) + 1];
        v[2] = s.points[3 * (i + e) + 2];
        v[3] = fibreRadius;
      }
      ib[q] = static_cast<unsigned>(2 * q);
    }
    rtcSetGeometryOccludedFilterFunction(g, countStrands);
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
}

}  // namespace clhair
