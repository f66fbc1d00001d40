// curl_detect.h — a curl found on the input strands alone, before there is any cage, and
// the strands smoothed over one turn of it.
//
// On an even sample of strands, each strand's points (in arc-length fraction u) are fitted
// by a cubic per coordinate (its bending) plus a sinusoid of f turns per strand length with
// free 3D coefficients; the f on a grid that removes the most energy summed over the sample
// is the curl, when it removes at least half of what the cubic leaves and clearly more than
// a typical f does. A first cage fitted to the strands smoothed by a moving average over one
// turn holds their bending but not their curl, so the styling fit that follows sees all of
// the curl.
#pragma once

#include "fit/fit_strands.h"

namespace clhair::fit {

// Turns per strand length, or 0 when the strands do not curl.
float detectCurlTurns(const FitStrands& strands, int threads);

// Every strand averaged over a centred window of one turn (narrowing at the ends, so the
// root and tip stay put), then resampled at equal arc length.
FitStrands smoothOverTurn(const FitStrands& strands, float turns, int threads);

}  // namespace clhair::fit
