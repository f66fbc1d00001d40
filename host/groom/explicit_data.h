// explicit_data.h — a StrandGroom turned into the device tables of kernels/strands_explicit.cl.
//
// Order (once per groom, deterministic): strands are sorted along a Morton curve of their
// root positions and cut into chunks of kChunkStrands consecutive strands, then shuffled
// inside each chunk. A chunk plays the role of a hair-mesh bundle for LOD (Lipp §3.2): it is
// small on screen when its strands are (spatially coherent chunks keep culling and a
// per-region L), and because its strands are in random order the first N_LOD of them are a
// uniform sample of the chunk.
//
// Tables (all sizes pinned by static_asserts):
//   points         float4 per stored point, strand after strand in the new order:
//                  xyz object space, w = k / (n - 1) for point k of an n-point strand
//   strandOffsets  uint, strands + 1: strand s owns points [offsets[s], offsets[s + 1])
//   uv             uint per strand: unorm16 u | unorm16 v << 16 (only when the groom has root uv)
//   chunks         uint4 per chunk: x first strand, y strands drawn at full detail (its
//                  guides times 1 + children per guide), z LOD delta (float bits, Lipp
//                  Eq. 1), w its stored strands (guides); slot j draws child j / w of guide
//                  x + j % w (child 0: the guide), so the first N_LOD slots are every guide,
//                  then one child of each, and so on (host/groom/children.h)
//   chunkBounds    (below) cover the children too
//   chunkBounds    float4 pair per chunk: object-space AABB min (w: the chunk's width, the
//                  largest diagonal of its stored strands' points at five fractions of
//                  their length, root to tip: LOD's strands per pixel of width, lod.cl),
//                  max (w 0)
//   fileLook       float4 per stored point in the order of `points`, only when the groom
//                  draws per-point colours, thicknesses or transparencies of its file
//                  (AppearanceParams::useFile*): linear rgb (the appearance's root colour
//                  where the file has none) and w: with file thickness, the thickness
//                  (object units) times the opacity 1 - transparency; without, minus the
//                  opacity (the groom's width times it); uploaded after the points in the
//                  same buffer (kernels/strands_explicit.cl)
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "clhair/gpu_types.h"
#include "clhair/strand_groom.h"

namespace clhair {

constexpr std::uint32_t kChunkStrands = 64;

struct ExplicitData {
  std::vector<glm::vec4> points;
  std::vector<std::uint32_t> strandOffsets;
  std::vector<std::uint32_t> uv;            // empty when the groom has no root uv
  std::vector<std::uint32_t> sourceStrand;  // new order -> index in the StrandGroom
  std::vector<glm::uvec4> chunks;
  std::vector<glm::vec4> chunkBounds;  // 2 per chunk
  std::vector<glm::vec4> fileLook;     // empty, or per point (see above)
  bool fileColor = false, fileThickness = false, fileOpacity = false;
  float meanThickness = 0.0f;                  // object units, when fileThickness
  glm::vec3 boundsMin{0.0f}, boundsMax{0.0f};  // object space, all points
  std::uint64_t totalStrands = 0;              // stored strands (guides)
  std::uint64_t totalPoints = 0;
  // Children (host/groom/children.h): the device record (count 0: none; radius resolved),
  // the neighbour table of interpolated children, and the strands drawn at full detail.
  gpu::ClhChildrenGpu kids{};
  std::vector<std::uint32_t> neighbours;
  std::uint64_t drawnStrands = 0;             // totalStrands * (1 + kids.count)
  std::uint32_t chunkGuides = kChunkStrands;  // stored strands per chunk (the last: fewer)
};

// Expects a validated groom (validateStrandGroom). With children, a chunk takes
// chunkStrands / (1 + children per guide) stored strands (at least 1).
ExplicitData prepareExplicit(const StrandGroom& groom, std::uint32_t chunkStrands = kChunkStrands);

}  // namespace clhair
