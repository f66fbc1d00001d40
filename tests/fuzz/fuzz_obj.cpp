// fuzz_obj.cpp — libFuzzer target for loadTriangleMesh (host/io/obj_mesh_io.cpp), the OBJ
// reader and its checks, with tinyobjloader compiled in (tinyobj_impl.cpp) so its parser is
// instrumented too.
//
// Any input must either be refused with a clhair::Error or read into a mesh that is safe
// to upload: whole triangles, every index naming a vertex, every coordinate finite, counts
// within the limits given; anything else (a crash, a sanitizer report, a broken invariant)
// is a finding. Small limits keep each run fast and exercise the limit checks.
#include <cmath>
#include <cstdint>
#include <string>

#include "clhair/error.h"
#include "clhair/triangle_mesh.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = clhair::fuzz::writeInput(data, size, "input.obj");
  clhair::MeshLimits limits;
  limits.maxTriangles = 100000;
  limits.maxFileBytes = 1 << 20;
  limits.maxBufferBytes = 4 << 20;
  clhair::TriangleMesh m;
  try {
    m = clhair::loadTriangleMesh(path, limits);
  } catch (const clhair::Error&) {
    return 0;
  }
  CLHAIR_FUZZ_CHECK(!m.indices.empty());
  CLHAIR_FUZZ_CHECK(m.indices.size() % 3 == 0);
  CLHAIR_FUZZ_CHECK(m.indices.size() / 3 <= limits.maxTriangles);
  CLHAIR_FUZZ_CHECK(m.positions.size() * clhair::kMeshVertexBytes <= limits.maxBufferBytes);
  for (std::uint32_t i : m.indices) CLHAIR_FUZZ_CHECK(i < m.positions.size());
  for (const auto& v : m.positions)
    CLHAIR_FUZZ_CHECK(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
  CLHAIR_FUZZ_CHECK(m.name == "input");
  return 0;
}
