// style_fit.h — the generator's styling parameters estimated from the input strands.
//
// Every strand's residual against its bundle's base curve (style_residual.h) is fitted by
// least squares; the two nonlinear parameters shared by the groom are searched first on an
// even sample of strands: the curl frequency f (turns per unit w, a grid then golden-section
// refinement, kept only when it explains at least 10 % of the residual energy) and the clump
// shape exponent. With those fixed, every strand's six linear unknowns give:
//   curl amplitude   median of sqrt(a^2 + b^2)
//   curl helix       median of the e2 amplitude over the e1 amplitude (projected on the
//                    generator's phase relation), clamped to 0..1
//   phase jitter     the spread of phase between root neighbours: for the generator's
//                    uniform jitter J the median |phase difference| is 2 pi J (1 - 1/sqrt 2)
//   clump strength   -(d_i - d_j).(uv_i - uv_j) / |uv_i - uv_j|^2 over root neighbours (the
//                    pulls of one clump converge on one centre), trimmed least squares
//   clump frequency  from the mean distance to the clump centre, |d| / strength, against the
//                    generator's jittered grid (its mean distance times the frequency is a
//                    constant, computed once from the generator's own cell hash)
//   frizz            the leftover energy over w^4 and the value noise's variance, median;
//                    strands far above it are flyaways (their share and extra amplitude);
//                    the frequency from the leftover's lag-one correlation
//   length variation from the mean of length / full length (uniform lengths in 1 - v .. 1)
// Per-bundle values use the same estimators on the bundle's strands; the mesh takes the
// groom-wide ones (the format holds one style per groom).
#pragma once

#include <string>
#include <vector>

#include "clhair/fit.h"
#include "clhair/hair_mesh.h"
#include "fit/base_curve.h"
#include "fit/cage_layers.h"
#include "fit/fit_strands.h"

namespace clhair::fit {

struct StyleFitResult {
  FittedStyle global;
  std::vector<FittedStyle> perBundle;
  std::vector<float> bundlePhase;  // circular mean curl phase per bundle, radians
  std::vector<std::string> notes;
};

// `arcCurl`: the styling of an earlier fit, for the arc-length model (style_residual.h) and
// as the start of a narrower search (curl frequency within 0.1 turn, clump shape within a
// factor 1.5); null on the first fit.
StyleFitResult fitStyle(const FitStrands& strands, const StrandPlacement& place,
                        const HairMesh& mesh, const BaseCurves& base, const FittedStyle* arcCurl,
                        int threads);

// The strands with their fitted curl taken out (each strand's own amplitude, phase and
// helix at the groom's frequency; clumping and frizz stay) and resampled again, for fitting
// the layers to the base curves when the layers are too sparse to follow the curl.
FitStrands removeCurl(const FitStrands& strands, const StrandPlacement& place,
                      const BaseCurves& base, const FittedStyle& fitted, const FittedStyle* arcCurl,
                      int threads);

// Writes the groom-wide estimate into a mesh's StyleParams (ranges of the format).
void applyStyle(const FittedStyle& fitted, StyleParams& style);

}  // namespace clhair::fit
