// fit_strands.h — the input of the fitter: every strand resampled to kFitSamples points at
// equal arc length, with its length, and the checks that refuse input nothing can be
// fitted to.
//
// Point k of strand i lies at arc length k / (M - 1) * length[i] along the original
// polyline (M = samples). atArc() reads a strand at any arc length by linear interpolation
// between those points; before the root it gives the root, past the tip it continues
// straight along the last segment.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

#include "clhair/strand_groom.h"

namespace clhair::fit {

struct FitStrands {
  int samples = 0;
  std::vector<glm::vec3> points;  // count() * samples
  std::vector<float> length;      // arc length per strand
  float fibreWidth = 0.0f;
  double medianLength = 0.0;
  int medianPoints = 0;  // points per strand in the input (the median strand)

  std::size_t count() const { return length.size(); }
  const glm::vec3* strand(std::size_t i) const { return points.data() + i * samples; }
  const glm::vec3& root(std::size_t i) const { return points[i * samples]; }
  glm::vec3 atArc(std::size_t i, float arc) const;
  // Position at `fraction` (0..1) of the strand's own length.
  glm::vec3 atFraction(std::size_t i, float fraction) const;
};

// Validates the groom (one clhair::Error line for non-finite points, bad counts, no strand
// longer than zero), then resamples. `fibreWidth` 0: from the groom (median thickness, else
// appearance.strandWidth).
FitStrands prepareFitStrands(const StrandGroom& groom, int samples, float fibreWidth, int threads);

// Resamples every strand of `s` again at equal arc length along its own (changed) points,
// updating the lengths.
void resampleInPlace(FitStrands& s, int threads);

}  // namespace clhair::fit
