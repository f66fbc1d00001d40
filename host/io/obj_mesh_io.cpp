// obj_mesh_io.cpp — Wavefront OBJ triangle meshes (include/clhair/triangle_mesh.h).
//
// The file is read into memory once (its size checked first), scanned line by line for
// what tinyobjloader accepts silently — it reads a missing or non-numeric coordinate
// ("v 1 2", "v nan 0 0") as 0 and keeps face indices past the end — and for the counts
// that size the device buffers, and only then handed to tinyobjloader, which splits
// polygons into triangles. The result is checked again (indices, finite numbers) before it
// is returned, so a TriangleMesh from here is always safe to upload.
#include <tiny_obj_loader.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "clhair/error.h"
#include "clhair/triangle_mesh.h"
#include "io/json_util.h"
#include "io/regular_file.h"

namespace clhair {

namespace {

std::string mib(std::uint64_t bytes) {
  return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB";
}

// One whitespace-separated token from `p` (advanced past it); empty at the end of the line.
std::string nextToken(const char*& p, const char* end) {
  while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
  const char* b = p;
  while (p < end && *p != ' ' && *p != '\t' && *p != '\r') ++p;
  return std::string(b, p);
}

struct ScanResult {
  std::uint64_t vertices = 0;
  std::uint64_t triangles = 0;
};

// The checks tinyobjloader does not make, and the counts, in one pass over the text.
ScanResult scanObj(const std::string& text, const MeshLimits& limits, const std::string& label) {
  ScanResult r;
  std::uint64_t line = 0, maxIndex = 0, maxIndexLine = 0;
  const char* p = text.data();
  const char* const end = p + text.size();
  auto fail = [&](const std::string& what) {
    throw Error(label + ": line " + std::to_string(line) + ": " + what);
  };
  while (p < end) {
    ++line;
    const char* eol =
        static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
    if (!eol) eol = end;
    const char* q = p;
    const std::string key = nextToken(q, eol);
    if (key == "v") {
      int n = 0;
      for (std::string t = nextToken(q, eol); !t.empty() && n < 3; t = nextToken(q, eol), ++n) {
        errno = 0;
        char* stop = nullptr;
        const double v = std::strtod(t.c_str(), &stop);
        if (stop != t.c_str() + t.size())
          fail("vertex " + std::to_string(r.vertices + 1) + " has a non-numeric coordinate \"" +
               t.substr(0, 32) + "\"");
        if (!std::isfinite(v) || std::fabs(v) > std::numeric_limits<float>::max())
          fail("vertex " + std::to_string(r.vertices + 1) + " has a non-finite coordinate (" +
               t.substr(0, 32) + ")");
      }
      if (n < 3)
        fail("vertex " + std::to_string(r.vertices + 1) + " has " + std::to_string(n) +
             " coordinates, need 3 (is the file truncated?)");
      ++r.vertices;
    } else if (key == "f") {
      std::uint64_t n = 0;
      for (std::string t = nextToken(q, eol); !t.empty(); t = nextToken(q, eol), ++n) {
        const std::string first = t.substr(0, t.find('/'));
        errno = 0;
        char* stop = nullptr;
        const long long idx = std::strtoll(first.c_str(), &stop, 10);
        if (first.empty() || stop != first.c_str() + first.size() || errno == ERANGE || idx == 0)
          fail("face vertex \"" + t.substr(0, 32) +
               "\" is not a vertex index (1-based, or negative: relative)");
        if (idx < 0 && static_cast<std::uint64_t>(-(idx + 1)) >= r.vertices)
          fail("face index " + std::to_string(idx) + " is out of range: only " +
               std::to_string(r.vertices) + " vertices come before it");
        if (idx > 0 && static_cast<std::uint64_t>(idx) > maxIndex) {
          maxIndex = static_cast<std::uint64_t>(idx);
          maxIndexLine = line;
        }
      }
      if (n < 3)
        fail("face has " + std::to_string(n) +
             " vertices, need at least 3 (is the file truncated?)");
      r.triangles += n - 2;
      if (r.triangles > limits.maxTriangles)
        fail("more than " + std::to_string(limits.maxTriangles) + " triangles; the limit is " +
             std::to_string(limits.maxTriangles) + " (decimate the mesh)");
    }
    p = eol < end ? eol + 1 : end;
  }
  if (maxIndex > r.vertices) {
    line = maxIndexLine;
    fail("face index " + std::to_string(maxIndex) + " is out of range: the file has " +
         std::to_string(r.vertices) + " vertices");
  }
  if (r.triangles == 0) throw Error(label + ": holds no faces (\"f\" lines): nothing to draw");
  const std::uint64_t vertexBytes = r.vertices * kMeshVertexBytes,
                      triangleBytes = r.triangles * kMeshTriangleBytes;
  if (vertexBytes > limits.maxBufferBytes || triangleBytes > limits.maxBufferBytes)
    throw Error(label + ": " + std::to_string(r.vertices) + " vertices and " +
                std::to_string(r.triangles) + " triangles need " +
                mib(std::max(vertexBytes, triangleBytes)) + " in one buffer; the device allows " +
                mib(limits.maxBufferBytes));
  return r;
}

}  // namespace

void validateTriangleMesh(const TriangleMesh& mesh, const std::string& where,
                          const MeshLimits& limits) {
  if (mesh.indices.empty()) throw Error(where + ": holds no triangles: nothing to draw");
  if (mesh.indices.size() % 3 != 0)
    throw Error(where + ": " + std::to_string(mesh.indices.size()) +
                " vertex indices are not whole triangles");
  const std::uint64_t triangles = mesh.indices.size() / 3;
  if (triangles > limits.maxTriangles)
    throw Error(where + ": " + std::to_string(triangles) + " triangles; the limit is " +
                std::to_string(limits.maxTriangles) + " (decimate the mesh)");
  if (mesh.positions.size() > std::numeric_limits<std::uint32_t>::max() ||
      mesh.positions.size() * kMeshVertexBytes > limits.maxBufferBytes ||
      triangles * kMeshTriangleBytes > limits.maxBufferBytes)
    throw Error(where + ": " + std::to_string(mesh.positions.size()) + " vertices and " +
                std::to_string(triangles) +
                " triangles do not fit the device's largest allocation (" +
                mib(limits.maxBufferBytes) + ")");
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::vec3& v = mesh.positions[i];
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      throw Error(where + ": vertex " + std::to_string(i + 1) + " has a non-finite coordinate");
  }
  for (std::size_t i = 0; i < mesh.indices.size(); ++i)
    if (mesh.indices[i] >= mesh.positions.size())
      throw Error(where + ": triangle " + std::to_string(i / 3) + " names vertex " +
                  std::to_string(mesh.indices[i] + 1) + " of " +
                  std::to_string(mesh.positions.size()));
}

TriangleMesh loadTriangleMesh(const std::string& path, const MeshLimits& limits,
                              const std::string& labelIn) {
  const std::string label = labelIn.empty() ? path : labelIn;
  const std::string ext = lowerExtension(path);
  if (ext == ".ply")
    throw Error(label +
                ": PLY meshes are not supported; convert it to OBJ (e.g. with Blender or MeshLab)");
  if (ext != ".obj") throw Error(label + ": expected a Wavefront .obj mesh, not \"" + ext + "\"");
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw Error(label + ": \"" + path + "\" does not exist");
  RegularFile file(path, "OBJ mesh");
  if (file.size() > limits.maxFileBytes)
    throw Error(label + ": the file is " + mib(file.size()) + ", more than the " +
                mib(limits.maxFileBytes) + " an OBJ mesh may be (decimate the mesh)");
  std::string text = file.readAll(limits.maxFileBytes);
  const std::size_t nul = text.find('\0');
  if (nul != std::string::npos)
    throw Error(label + ": holds binary data (a zero byte at offset " + std::to_string(nul) +
                "); expected a text OBJ file");
  const ScanResult counts = scanObj(text, limits, label);

  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromString(text, "", config)) {
    std::string err = reader.Error();
    while (!err.empty() && (err.back() == '\n' || err.back() == '.')) err.pop_back();
    for (char& c : err)
      if (c == '\n') c = ' ';
    throw Error(label + ": " + (err.empty() ? std::string("cannot be parsed") : err));
  }
  std::string().swap(text);
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  TriangleMesh mesh;
  mesh.name = std::filesystem::path(path).stem().string();
  if (attrib.vertices.size() != 3 * counts.vertices)
    throw Error(label + ": read " + std::to_string(attrib.vertices.size() / 3) +
                " vertices where the file has " + std::to_string(counts.vertices));
  mesh.positions.resize(counts.vertices);
  for (std::size_t i = 0; i < mesh.positions.size(); ++i)
    mesh.positions[i] =
        glm::vec3(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
  mesh.indices.reserve(3 * counts.triangles);
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    std::size_t at = 0;
    for (unsigned char fv : shape.mesh.num_face_vertices) {
      if (fv == 3 && at + 3 <= shape.mesh.indices.size())
        for (int k = 0; k < 3; ++k) {
          const int idx = shape.mesh.indices[at + k].vertex_index;
          if (idx < 0 || static_cast<std::uint64_t>(idx) >= counts.vertices)
            throw Error(label + ": a face names vertex " + std::to_string(idx + 1) + " of " +
                        std::to_string(counts.vertices));
          mesh.indices.push_back(static_cast<std::uint32_t>(idx));
        }
      at += fv;
    }
  }
  validateTriangleMesh(mesh, label, limits);
  return mesh;
}

}  // namespace clhair
