// clump_fit.h — the generator's clumping measured between neighbouring strands.
//
// Clumping pulls the strands of one clump toward the clump's centre by strength * w^shape
// of their uv offset to it (mapped to object space by the styling directions du, dv), so
// two neighbours of one clump are pulled together by strength * w^shape * J (uv_i - uv_j).
// Each strand's residual against its base curve, less its own fitted curl, is sampled at a
// few w; for root neighbours the difference of those samples projected on J (uv_i - uv_j)
// gives -strength * w^shape at each w. The median over all neighbour pairs (pairs that
// straddle two clumps are pulled apart instead, a minority) gives a profile over w, and a
// straight line through its logarithm gives the strength (at w = 1) and the shape. The mean
// distance to the clump centre, which sets the frequency, comes from each strand's own
// samples against strength * w^shape * J.
#pragma once

#include <utility>
#include <vector>

#include <glm/vec2.hpp>

#include "fit/style_residual.h"

namespace clhair::fit {

constexpr int kClumpBins = 6;

struct ClumpSamples {
  bool valid = false;
  glm::vec2 uv{0.0f};
  glm::vec2 q[kClumpBins];   // residual less the fitted curl, in the styling frame
  glm::vec2 du[kClumpBins];  // du and dv in the styling frame
  glm::vec2 dv[kClumpBins];
};

// Samples strand residual `r` (fitted with curl frequency f into `fit`) at the bins.
void clumpSamples(const StrandResidual& r, const StrandFit& fit, float f, const glm::vec2& uv,
                  ClumpSamples& out);

struct ClumpEstimate {
  float strength = 0.0f, shape = 1.5f, frequency = 0.0f;
};

// From the strands `strands` and neighbour pairs `pairs` (indices into `samples`).
ClumpEstimate estimateClumping(const std::vector<ClumpSamples>& samples,
                               const std::vector<int>& strands,
                               const std::vector<std::pair<int, int>>& pairs);

}  // namespace clhair::fit
