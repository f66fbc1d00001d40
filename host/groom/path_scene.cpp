// path_scene.cpp — the opaque scene of StrandTracer's path mode (strand_tracer.h): analytic
// spheres and triangle meshes as Lambertian Embree geometries, each with its albedo under
// its geometry id.
#include <algorithm>
#include <string>

#include "clhair/error.h"
#include "groom/strand_tracer_impl.h"

namespace clhair {

namespace {

// Commits an opaque Lambertian geometry, attaches it to the scene and records its albedo
// under its geometry id.
void attachOpaque(StrandTracer::Impl& r, RTCGeometry geom, const char* what,
                  const float albedo[3]) {
  rtcCommitGeometry(geom);
  const unsigned id = rtcAttachGeometry(r.scene, geom);
  rtcReleaseGeometry(geom);
  r.check(what);
  if (r.opaque.size() <= id) r.opaque.resize(id + 1);
  r.opaque[id].present = true;
  std::copy(albedo, albedo + 3, r.opaque[id].albedo);
}

}  // namespace

void StrandTracer::addSphere(const float centre[3], float radius, const float albedo[3]) {
  Impl& r = *impl_;
  if (!r.pathMode || r.committed)
    throw Error("StrandTracer::addSphere: path mode, before commit()");
  RTCGeometry geom = rtcNewGeometry(r.device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  r.check("creating a sphere");
  auto* vb = static_cast<float*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 16, 1));
  if (!vb) {
    rtcReleaseGeometry(geom);
    throw Error("Embree: allocating a sphere failed");
  }
  vb[0] = centre[0];
  vb[1] = centre[1];
  vb[2] = centre[2];
  vb[3] = radius;
  attachOpaque(r, geom, "adding a sphere", albedo);
}

void StrandTracer::addTriangles(const std::vector<float>& positions,
                                const std::vector<std::uint32_t>& indices, const float albedo[3]) {
  Impl& r = *impl_;
  if (!r.pathMode || r.committed)
    throw Error("StrandTracer::addTriangles: path mode, before commit()");
  const std::size_t V = positions.size() / 3, T = indices.size() / 3;
  if (T == 0) return;
  for (std::uint32_t i : indices)
    if (i >= V) throw Error("path reference: a triangle index is past the mesh's vertices");
  RTCGeometry geom = rtcNewGeometry(r.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  r.check("creating triangles");
  auto* vb = static_cast<float*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, V));
  auto* ib = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, T));
  if (!vb || !ib) {
    rtcReleaseGeometry(geom);
    throw Error("Embree: allocating " + std::to_string(T) + " triangles failed");
  }
  std::copy(positions.begin(), positions.begin() + 3 * V, vb);
  std::copy(indices.begin(), indices.begin() + 3 * T, ib);
  attachOpaque(r, geom, "adding triangles", albedo);
}

}  // namespace clhair
