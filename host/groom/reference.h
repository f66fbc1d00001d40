// reference.h — a CPU reference of strand generation, written for clarity.
//
// It follows the same specification as kernels/strands.cl (docs/hair-mesh-format.md) one
// step after another for a single strand: root sample, per-layer bilinear samples,
// finite-difference layer tangents, cubic Hermite base spline resampled to C points,
// styling in the frame of the consistent u direction, then tangents from neighbours with
// Bhokare's end-point rule (Eq. 5-6). Tests compare the kernel's output against it.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "clhair/gpu_types.h"
#include "groom/blue_noise.h"
#include "groom/groom_data.h"

namespace clhair {

struct ReferenceStrand {
  std::vector<glm::vec3> points;    // object space
  std::vector<glm::vec3> tangents;  // unit
  std::vector<float> w;             // styling w
  glm::vec2 uv{0.0f};
};

ReferenceStrand referenceStrand(const GroomData& data, const gpu::ClhGroomGpu& params,
                                const RootSets& roots, std::uint32_t bundle,
                                std::uint32_t localIndex, std::uint32_t controlPoints);

}  // namespace clhair
