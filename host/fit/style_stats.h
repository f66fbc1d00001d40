// style_stats.h — statistics of the generator's random styling functions, which the
// styling fit inverts: measured once, deterministically, from the same hashes and
// interpolation the strand kernel uses (kernels/common/hair_style.h).
//
//   valueNoiseVariance      E[n^2] of one frizz noise channel (knots uniform in [-1, 1],
//                           smoothstep between them)
//   valueNoiseCorrelation   E[n(x) n(x + d)] / E[n^2] for d in knot spacings
//   clumpDistanceTimesFrequency  E|clump centre - uv| x clump_frequency for the jittered grid
#pragma once

namespace clhair::fit {

double valueNoiseVariance();
double valueNoiseCorrelation(double d);
// Knot spacings d (0..1.5) whose correlation is `c` (monotone inverse of the above).
double valueNoiseLagForCorrelation(double c);
double clumpDistanceTimesFrequency();

// What the per-strand least squares (style_residual.h) leaves of the generator's frizz: for
// a strand sampled at `points` evenly spaced w up to `rho`, frizz of unit amplitude at F
// cells per unit w, and the fit's other terms (clump shape; curl at f when `curl`), the
// leftover's energy over w >= 0.3 relative to sum w^4 * 2 E[n^2] (`energy`) and its
// correlation between points 1, 2, 4 and 8 apart (`corr`). Simulated with the generator's
// value noise.
struct FrizzLeftover {
  double energy = 1.0;
  double corr[4] = {1.0, 1.0, 1.0, 1.0};
};
FrizzLeftover frizzLeftover(double F, int points, double rho, double f, double shape, bool curl);

}  // namespace clhair::fit
