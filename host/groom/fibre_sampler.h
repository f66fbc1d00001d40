// fibre_sampler.h — importance sampling of the real-time hair BSDF (kernels/common/hair_bsdf.h,
// compiled for the CPU by hair_bsdf_cpu.h) for the path-traced reference's continuation at
// a fibre, with the exact density of what it draws.
//
// The BSDF is separable per lobe (docs/hair-shading.md §2):
//   f cos(theta_i) dw = Σ_{p=R,TT,TRT} M_p(theta_i) Ñ_p(phi) cos(theta_i) dtheta dphi
//                       + Ā_3 / pi² cos(theta_i) dw,
// M_p normalised over cos(theta_i) dtheta_i, ∫Ñ_p dphi ≈ Ā_p (hv.mass[p]). The sampler
// - picks a lobe with probability c_p ∝ the luminance of tint ⊙ Ā_p, floored at kLobeFloor
//   of the total for every lobe with energy;
// - draws theta_i from M_p exactly (d'Eon et al. 2013, as pbrt-v4's HairBxDF::Sample_f:
//   cos T = 1 + v ln(u + (1 - u) e^{-2/v}), rotated about the lobe's tilted theta_o);
// - draws phi from a piecewise-constant table of the lobe's own Ñ_p (luminance, kBins bins
//   over |phi| in [0, pi], mixed with kUniform of the uniform density so that every
//   direction can be drawn; Ñ_p is even in phi, so the sign is drawn apart);
// - for the diffuse lobe: phi uniform, theta_i with density cos² (sin theta_i is the first
//   coordinate of a uniform point in the unit disk).
// pdf() is the mixture's density in solid angle (dw = cos theta dtheta dphi):
//   Σ_p c_p M_p(theta_i) T_p(phi) + c_d cos(theta_i) / pi²,
// so f cos / pdf is the unbiased weight of a sampled direction.
//
// The tint is the per-channel scale a file-coloured fibre's BSDF carries (shade.cl scales
// the lobes so that their energies sum to the file colour); 1 otherwise.
#pragma once

#include "groom/hair_bsdf_cpu.h"

namespace clhair {

class FibreSampler {
 public:
  static constexpr int kBins = 16;          // azimuthal bins over |phi| in [0, pi]
  static constexpr float kUniform = 0.05f;  // share of the uniform density in each table
  static constexpr float kLobeFloor = 0.02f;

  explicit FibreSampler(const cpu_bsdf::clh_hair_view& hv,
                        cpu_bsdf::clh_v3 tint = cpu_bsdf::clh_v3_splat(1.0f));

  // A unit direction wi drawn from four uniform numbers in [0, 1).
  cpu_bsdf::clh_v3 sample(const float u[4]) const;
  // The density of sample() at unit wi, in solid angle.
  float pdf(cpu_bsdf::clh_v3 wi) const;
  // f cos(theta_i) of the tinted BSDF at wi (the numerator of a sample's weight).
  cpu_bsdf::clh_v3 evalCos(cpu_bsdf::clh_v3 wi) const;
  // c_p for p = R, TT, TRT, diffuse.
  float lobeProbability(int p) const { return c_[p]; }

 private:
  const cpu_bsdf::clh_hair_view& hv_;
  cpu_bsdf::clh_v3 tint_;
  cpu_bsdf::clh_v3 b_;  // t × n: phi = atan2(wi·b, wi·n)
  float c_[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  float cdf_[3][kBins + 1] = {};  // per specular lobe, the mixed table's CDF over the bins
  float dens_[3][kBins] = {};     // its density in phi over [-pi, pi] (both signs)
};

}  // namespace clhair
