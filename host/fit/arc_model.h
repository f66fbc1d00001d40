// arc_model.h — where along its base curve a curly strand is, from how far along the
// strand it is.
//
// The generator places a strand's points uniformly in the styling coordinate w, but curls
// lengthen the strand unevenly: not at all at the root (the curl ramps in over the first
// 15 % of w), then by a constant factor. So arc length along an input strand is not
// proportional to w. With the fitted curl (amplitude A, frequency f, helix h) the expected
// speed of a strand at w is sqrt(|B'(w)|^2 + (2 pi f A ramp(w))^2 (1 + h^2) / 2) (B the
// base curve; the curl's own derivative is across B' and the cross terms average out over
// the phase); its integral a(w), tabulated at kArcSteps + 1 points and inverted linearly,
// maps arc length to w. The input is a polyline, so the curl's part is that of its chords:
// 2 A ramp sin(pi f dw) / dw for points dw apart in w. Without a curl the map is the base
// curve's own arc length.
// strandW then refines that guess for each point of a strand by projection onto the curve.
#pragma once

#include <glm/vec2.hpp>

#include "clhair/fit.h"
#include "fit/base_curve.h"
#include "fit/fit_strands.h"

namespace clhair::fit {

constexpr int kArcSteps = 32;

struct ArcMap {
  float arc[kArcSteps + 1];  // a(j / kArcSteps)
  // w at arc length `a` (clamped to 0..1; beyond the end: 1 + the excess over the end speed)
  float wAt(float a) const;
  float full() const { return arc[kArcSteps]; }
  float arcAt(float w) const;  // a(w), w clamped to 0..1
};

// `points`: the input strands' points per strand (their polylines cut the curl short by
// chords: each of the (points - 1) segments spans 2 pi f / (points - 1) of a turn).
ArcMap arcMap(const BaseCurves& base, int face, const glm::vec2& st, const FittedStyle& curl,
              int points);

// The styling w of every resampled point of strand i (samples values, w[0] = 0): the arc
// model's guess refined by projecting the point onto the base curve (Gauss-Newton on
// (x - B(w)) . B'(w) = 0; styling offsets lie across the curve, so the projection finds
// the w the generator used, whatever the sampling of the input). Non-decreasing; values
// past the base curve's end are extrapolated in arc length. Returns the tip's w.
float strandW(const FitStrands& strands, std::size_t i, int face, const glm::vec2& st,
              const BaseCurves& base, const FittedStyle& curl, float* w);

}  // namespace clhair::fit
