// fit_error.h — how far a fitted hair mesh's strands are from the strands it was fitted to.
//
// The mesh's strands are generated on the CPU with the generator's reference
// implementation (host/groom/reference.h: the same strands the strand kernel draws, which
// the test suite checks). For every measured input strand I, the distance to a generated
// strand G is the mean, over 17 points of I at equal arc length, of the distance to G's
// polyline (each point looks at the part of G within 15 % of its own length fraction, so a
// distance is never underestimated); I's error is the smallest such distance over the
// candidates: the generated strands nearest to I's root, middle and tip (8 each).
#pragma once

#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

#include "clhair/fit.h"
#include "clhair/hair_mesh.h"
#include "fit/fit_strands.h"

namespace clhair::fit {

struct GeneratedStrands {
  int points = 0;                     // per strand (the mesh's full-detail control points)
  std::vector<glm::vec3> data;        // strands * points
  std::vector<std::uint32_t> bundle;  // per strand
  std::size_t count() const { return bundle.size(); }
};

GeneratedStrands generateStrandsCpu(const HairMesh& mesh, int threads);

LengthStats lengthStats(std::vector<float> lengths);
std::vector<float> generatedLengths(const GeneratedStrands& g);

// Distance of every input strand in `measured` (indices) to its nearest generated strand,
// metres; the order follows `measured`.
std::vector<float> strandDistances(const FitStrands& input,
                                   const std::vector<std::size_t>& measured,
                                   const GeneratedStrands& generated, int threads);

// Mean and 95th percentile of `d` (metres), also in fibre widths.
FitDistance summarize(std::vector<float> d, float fibreWidth);

}  // namespace clhair::fit
