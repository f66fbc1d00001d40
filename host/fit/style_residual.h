// style_residual.h — one input strand against its bundle's base curve, and the per-strand
// least squares that splits the difference into the generator's styling terms.
//
// A strand's resampled point k (k >= 1) lies at styling w_k = arc_k / full length. Its
// residual against the base curve at w_k is expressed in the generator's styling frame
// (e1: the u direction made perpendicular to the base tangent, e2 = tangent x e1); the
// component along the tangent (where the strand is early or late along the curve, not a
// styling offset) is dropped. The model, per point, for the two frame components:
//
//   r = w^shape (du d_u + dv d_v)                 clumping, d = strength x uv offset to
//                                                 the clump centre (2 unknowns)
//     + ramp(w) [a cos T + b sin T] e1            curl / wave, T = 2 pi f w
//     + ramp(w) [c cos T + d sin T] e2            (4 unknowns)
//
// with ramp the generator's smoothstep over the first 15 % of w. For a given curl
// frequency f and clump shape it is linear in its six unknowns; the normal equations are
// solved with a tiny ridge. What is left over is frizz (and whatever the model lacks).
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "clhair/fit.h"
#include "fit/base_curve.h"
#include "fit/cage_layers.h"
#include "fit/fit_strands.h"

namespace clhair::fit {

struct StrandResidual {
  int points = 0;  // entries used (resampled points 1..M-1 that reach the base curve)
  float w[kFitSamples];
  glm::vec2 r[kFitSamples];   // residual: (e1, e2) components
  glm::vec2 du[kFitSamples];  // du in the frame: (du.e1, du.e2)
  glm::vec2 dv[kFitSamples];
  float ramp[kFitSamples];
  glm::vec3 e1[kFitSamples], e2[kFitSamples];  // the styling frame
  float dw = 0.0f;                             // mean spacing of w between consecutive points
  float rho = 1.0f;  // where the strand ends along its base curve (w of its tip, <= 1)
};

// With `curl` the points' w come from the arc-length model (arc_model.h) for that curl;
// without, w is arc length over the strand's full length (place.fullLength).
void strandResidual(const FitStrands& strands, const StrandPlacement& place, const BaseCurves& base,
                    std::size_t strand, const FittedStyle* curl, StrandResidual& out);

constexpr int kFrizzLagCount = 5;
constexpr int kFrizzLags[kFrizzLagCount] = {0, 1, 2, 4, 8};

struct StrandFit {
  glm::vec2 delta{0.0f};             // clump: strength x uv offset
  float a = 0, b = 0, c = 0, d = 0;  // curl coefficients
  double energy = 0.0;               // residual energy after the fit
  double total = 0.0;                // residual energy before it
  // frizz, over w >= 0.3: the leftover's energy, sum w^4, and the sums of products of
  // points kFrizzLags[j] apart (lag[0]: the energy again)
  double frizzEnergy = 0.0, frizzW4 = 0.0;
  double lag[kFrizzLagCount] = {};
};

// Fits the six unknowns for curl frequency f (turns per unit w) and clump shape.
StrandFit fitStrandStyle(const StrandResidual& r, float f, float shape, bool leftover);

}  // namespace clhair::fit
