// triangle_mesh.h — opaque triangle meshes (a groom's head, a body, props) read from
// Wavefront OBJ files and drawn into the scene's depth buffer with the analytic spheres
// and planes (kernels/mesh.cl).
//
// A TriangleMesh is positions plus three vertex indices per triangle; polygons are split
// into triangles when read. Every index is < positions.size() and every coordinate is
// finite. Materials, texture coordinates and normals in the file are ignored: a mesh has one
// colour per scene entry and is shaded with normals averaged from its triangles.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace clhair {

struct TriangleMesh {
  std::string name;                    // the file's stem
  std::vector<glm::vec3> positions;    // object space
  std::vector<std::uint32_t> indices;  // 3 per triangle, each < positions.size()
};

// Limits on a mesh file. The triangle cap keeps the one-work-item-per-triangle raster and
// the host's normal pass within a frame's budget; 10 M triangles is far beyond any head
// mesh (scans are decimated to 50-500 k). The byte cap bounds the text read into memory.
constexpr std::uint64_t kMaxMeshTriangles = 10'000'000;
constexpr std::uint64_t kMaxMeshFileBytes = 1ull << 30;
// Device bytes per vertex (position and normal, a float4 each) and per triangle (uint4).
constexpr std::uint64_t kMeshVertexBytes = 16;
constexpr std::uint64_t kMeshTriangleBytes = 16;

struct MeshLimits {
  std::uint64_t maxTriangles = kMaxMeshTriangles;
  std::uint64_t maxFileBytes = kMaxMeshFileBytes;
  std::uint64_t maxBufferBytes = 2ull << 30;  // pass the device's largest allocation
};

// Reads an OBJ file (tinyobjloader) and checks it before anything is uploaded: the file
// exists and is text, every `v` line holds three finite numbers (a `v` line cut short is a
// truncated file), every face has at least three vertices whose indices (1-based, or
// negative: relative to the vertices so far) name existing vertices, the mesh has at least
// one triangle, and the counts stay within `limits` (counted before the file is parsed).
// `.ply` files are refused with a hint to convert them. Errors are one line starting with
// `label` (the path when empty), with the line number where there is one.
TriangleMesh loadTriangleMesh(const std::string& path, const MeshLimits& limits = MeshLimits{},
                              const std::string& label = "");

// The same checks on a mesh built in memory; throws clhair::Error naming `where`.
void validateTriangleMesh(const TriangleMesh& mesh, const std::string& where,
                          const MeshLimits& limits = MeshLimits{});

}  // namespace clhair
