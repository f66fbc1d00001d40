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
// maps arc length to w. Without a curl the map is the base curve's own arc length.
#pragma once

#include <glm/vec2.hpp>

#include "clhair/fit.h"
#include "fit/base_curve.h"

namespace clhair::fit {

constexpr int kArcSteps = 32;

struct ArcMap {
  float arc[kArcSteps + 1];  // a(j / kArcSteps)
  // w at arc length `a` (clamped to 0..1; beyond the end: 1 + the excess over the end speed)
  float wAt(float a) const;
  float full() const { return arc[kArcSteps]; }
  float arcAt(float w) const;  // a(w), w clamped to 0..1
};

ArcMap arcMap(const BaseCurves& base, int face, const glm::vec2& st, const FittedStyle& curl);

}  // namespace clhair::fit
