// chiang_reference.h — CPU reference of the Chiang et al. 2016 hair BSDF ("A Practical and
// Controllable Hair and Fur Model for Production Path Tracing"), in double precision,
// written for clarity rather than speed. It is the ground truth the real-time model of
// kernels/common/hair_bsdf.h is tested against (tests/test_bsdf.cpp).
//
// Inputs: a material (sigma_a per RGB channel, beta_m, beta_n, cuticle tilt alpha in
// radians, eta), a unit fibre tangent t and unit directions wo (to the eye) and wi (to the
// light), all in one world frame. Outputs: f(wo, wi) for a given offset h in [-1, 1] across
// the fibre, and the far-field (h-averaged) f̄ = ½ ∫ f dh used by a deferred renderer that
// stores no h.
//
// Conventions (those of pbrt-v4's HairBxDF, which describes the same model):
//   - theta is the angle to the plane normal to t: sin(theta) = dot(t, w).
//   - f includes the 1 / cos(theta_i) factor, so the reflected radiance is
//     L_o = ∫ f(wo, wi) L_i cos(theta_i) dw_i, and the energy of wo is
//     E(wo) = ∫ f cos(theta_i) dw_i = Σ_p (h-averaged A_p) when the M_p are normalised.
//   - Cuticle tilt is applied to theta_o: R uses theta_o - 2 alpha, TT theta_o + alpha,
//     TRT theta_o + 4 alpha (Chiang §4 / pbrt-v4); the p_max = 3 residual is untilted.
//   - M_p is d'Eon et al.'s Bessel form with Chiang's variances v_0 = (0.726 bm + 0.812 bm²
//     + 3.7 bm^20)², v_1 = v_0 / 4, v_2 = v_3 = 4 v_0; N_p is the logistic trimmed to
//     [-pi, pi] with s = sqrt(pi/8) (0.265 bn + 1.194 bn² + 5.372 bn^22) (Chiang Eq. 7-8).
//   - A_p uses the Fresnel factor at the entry point, eta' of Bravais and the absorption
//     T = exp(-sigma_a 2 cos(gamma_t) / cos(theta_t)); sigma_a is per unit fibre radius (the
//     fibre is a cylinder of radius 1, so a chord at offset h is 2 cos(gamma_t) long).
#pragma once

#include <array>

namespace clhair::ref {

using Rgb = std::array<double, 3>;

struct ChiangMaterial {
  Rgb sigmaA{0.0, 0.0, 0.0};
  double betaM = 0.3;
  double betaN = 0.3;
  double alpha = 0.0;  // cuticle tilt in radians
  double eta = 1.55;
};

// Angles of one direction pair in the fibre frame.
struct FibreAngles {
  double sinThetaO, cosThetaO, sinThetaI, cosThetaI;
  double phi;  // phi_i - phi_o in (-pi, pi]
};

// Frame terms from world-space vectors (t need not be exactly unit length).
FibreAngles fibreAngles(const double t[3], const double wo[3], const double wi[3]);

// Chiang's roughness mappings.
std::array<double, 4> longitudinalVariances(double betaM);
double logisticScale(double betaN);

// Modified Bessel function of the first kind, order 0, and its logarithm.
double besselI0(double x);
double logBesselI0(double x);

// Longitudinal scattering M_p (d'Eon et al. 2011, Chiang Eq. 3), normalised so that
// ∫ M_p cos(theta_i) dtheta_i = 1 over [-pi/2, pi/2].
double longitudinalM(double sinThetaI, double cosThetaI, double sinThetaO, double cosThetaO,
                     double v);

// M_p of lobe p (0..3) for a direction pair, with the cuticle tilt of that lobe applied.
double longitudinalTilted(const ChiangMaterial& m, int p, const FibreAngles& a);

// Unpolarised dielectric Fresnel reflectance for light arriving at cos(theta) from air.
double fresnelDielectric(double cosTheta, double eta);

// Attenuations A_0..A_3 for offset h (A_3: all p >= 3, Chiang Eq. 6).
std::array<Rgb, 4> attenuation(const ChiangMaterial& m, double sinThetaO, double h);

// Net azimuthal deflection Phi(p, h) = 2 p gamma_t - 2 gamma_o + p pi.
double deflection(int p, double gammaO, double gammaT);

// Trimmed logistic on [-pi, pi] (Chiang Eq. 10).
double trimmedLogistic(double x, double s);

// Per-lobe terms of f for one offset h: f = Σ_p M[p] * AN[p] / cos(theta_i).
struct Lobes {
  std::array<double, 4> M;  // longitudinal, p = 0..3
  std::array<Rgb, 4> AN;    // A_p N_p (p = 3: A_3 / (2 pi))
};
Lobes lobesAtH(const ChiangMaterial& m, const FibreAngles& a, double h);

// f(wo, wi) for offset h (includes 1 / cos(theta_i)).
Rgb evalAtH(const ChiangMaterial& m, const FibreAngles& a, double h);

// h-averaged azimuthal functions Ñ_p(phi) = ½ ∫ A_p N_p dh for p = 0..2, and the h-averaged
// residual energy Ā_3 in [3]. Gauss-Legendre over gamma_o (h = sin gamma_o), `panels` x 8
// nodes, which resolves the logistic down to beta_n = 0.2 with the default.
std::array<Rgb, 4> averagedAzimuthal(const ChiangMaterial& m, double sinThetaO, double phi,
                                     int panels = 48);
// h-averaged energies Ā_0..Ā_3 for one theta_o.
std::array<Rgb, 4> averagedAttenuation(const ChiangMaterial& m, double sinThetaO, int panels = 48);

// Far-field f̄(wo, wi) = ½ ∫ f dh, split per lobe: lobe[p] for p = 0..3 (lobe 3 is the
// residual), each including 1 / cos(theta_i); the sum is f̄.
std::array<Rgb, 4> evalAveragedLobes(const ChiangMaterial& m, const FibreAngles& a,
                                     int panels = 48);
Rgb evalAveraged(const ChiangMaterial& m, const FibreAngles& a, int panels = 48);

// sigma_a from melanin concentrations (Chiang Eq. 11, pbrt-v4's RGB coefficients).
Rgb sigmaAFromMelanin(double eumelanin, double pheomelanin);
// sigma_a giving approximately the multiple-scattered colour `c` for azimuthal roughness
// beta_n (Chiang Eq. 9, the inverse mapping fitted to path-traced fibre assemblies).
Rgb sigmaAFromColor(const Rgb& c, double betaN);

}  // namespace clhair::ref
