// groom_data.h — a HairMesh turned into the device records of gpu_types.h.
//
// prepareGroom computes what the kernels read but the file does not hold: the consistent
// per-vertex styling directions u and v of every layer (Bhokare Eq. 1-3: area-weighted
// averages of the per-triangle linear maps from uv to object space), default tangents
// flags, w and AO, the per-bundle strand counts (spread by scalp-face area) and LOD
// offsets, and conservative object-space bounds including the largest styling offset.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "clhair/gpu_types.h"
#include "clhair/hair_mesh.h"

namespace clhair {

struct GroomData {
  std::vector<gpu::ClhMeshVertex> vertices;  // layer-major, layerCount * vertexCount
  std::vector<gpu::ClhBundle> bundles;
  std::uint32_t maxBundleStrands = 0;
  std::uint64_t totalStrands = 0;
  glm::vec3 boundsMin{0.0f};  // object space, including styling
  glm::vec3 boundsMax{0.0f};
  float styleMargin = 0.0f;  // largest styling displacement, object units
};

GroomData prepareGroom(const HairMesh& mesh);

// Fills the mesh-, style- and appearance-derived fields of the per-groom record (counts,
// styling, colours); view-dependent fields are left to the renderer.
void fillGroomParams(const HairMesh& mesh, const GroomData& data, gpu::ClhGroomGpu& params);

// Control points without LOD, as configured (2^k + 1, at least the layer count).
std::uint32_t fullDetailControlPoints(const HairMesh& mesh);

}  // namespace clhair
