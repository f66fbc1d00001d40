// chiang_reference.cpp — the double-precision Chiang et al. 2016 hair BSDF declared in
// chiang_reference.h. Every function maps to one equation of the paper (or of d'Eon et al.
// 2011 for M_p); see the header for conventions. Compiled into clhair_tests
// (tests/CMakeLists.txt).
#include "reference/chiang_reference.h"

#include <algorithm>
#include <cmath>

namespace clhair::ref {

namespace {

constexpr double kPi = 3.14159265358979323846;

double safeSqrt(double x) { return std::sqrt(std::max(0.0, x)); }
double safeAsin(double x) { return std::asin(std::clamp(x, -1.0, 1.0)); }
double sqr(double x) { return x * x; }

// 8-point Gauss-Legendre nodes and weights on [-1, 1].
constexpr double kGlX[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                            -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                            0.7966664774136267,  0.9602898564975363};
constexpr double kGlW[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                            0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                            0.2223810344533745, 0.1012285362903763};

// Calls fn(h, weight) for a Gauss-Legendre rule of ½ ∫_{-1}^{1} dh, integrated over
// gamma_o = asin(h) so the sqrt behaviour of the integrand at |h| -> 1 is smooth.
template <typename Fn>
void forEachH(int panels, Fn&& fn) {
  const double width = kPi / panels;
  for (int k = 0; k < panels; ++k) {
    const double g0 = -0.5 * kPi + k * width;
    for (int j = 0; j < 8; ++j) {
      const double g = g0 + 0.5 * width * (kGlX[j] + 1.0);
      // ½ dh = ½ cos(gamma) dgamma
      fn(std::sin(g), 0.5 * std::cos(g) * 0.5 * width * kGlW[j]);
    }
  }
}

double wrapPi(double x) {
  x = std::fmod(x + kPi, 2.0 * kPi);
  if (x < 0) x += 2.0 * kPi;
  return x - kPi;
}

// Tilted sin/cos(theta_o) for lobe p (pbrt-v4 convention, Chiang §4).
void tiltedThetaO(int p, double alpha, double sinThetaO, double cosThetaO, double* s, double* c) {
  const double shift = p == 0 ? -2.0 * alpha : p == 1 ? alpha : p == 2 ? 4.0 * alpha : 0.0;
  *s = sinThetaO * std::cos(shift) + cosThetaO * std::sin(shift);
  *c = std::fabs(cosThetaO * std::cos(shift) - sinThetaO * std::sin(shift));
}

}  // namespace

FibreAngles fibreAngles(const double t[3], const double wo[3], const double wi[3]) {
  const double tl = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
  const double u[3] = {t[0] / tl, t[1] / tl, t[2] / tl};
  FibreAngles a{};
  a.sinThetaO = std::clamp(u[0] * wo[0] + u[1] * wo[1] + u[2] * wo[2], -1.0, 1.0);
  a.sinThetaI = std::clamp(u[0] * wi[0] + u[1] * wi[1] + u[2] * wi[2], -1.0, 1.0);
  a.cosThetaO = safeSqrt(1 - sqr(a.sinThetaO));
  a.cosThetaI = safeSqrt(1 - sqr(a.sinThetaI));
  // projections onto the normal plane; phi from a frame (n, b = t x n) with n along wo_perp
  double po[3], pi[3];
  for (int k = 0; k < 3; ++k) {
    po[k] = wo[k] - a.sinThetaO * u[k];
    pi[k] = wi[k] - a.sinThetaI * u[k];
  }
  double lo = std::sqrt(po[0] * po[0] + po[1] * po[1] + po[2] * po[2]);
  if (lo < 1e-12) {  // wo along t: any normal will do
    const double ax[3] = {std::fabs(u[0]) < 0.9 ? 1.0 : 0.0, std::fabs(u[0]) < 0.9 ? 0.0 : 1.0,
                          0.0};
    const double d = ax[0] * u[0] + ax[1] * u[1] + ax[2] * u[2];
    for (int k = 0; k < 3; ++k) po[k] = ax[k] - d * u[k];
    lo = std::sqrt(po[0] * po[0] + po[1] * po[1] + po[2] * po[2]);
  }
  const double n[3] = {po[0] / lo, po[1] / lo, po[2] / lo};
  const double b[3] = {u[1] * n[2] - u[2] * n[1], u[2] * n[0] - u[0] * n[2],
                       u[0] * n[1] - u[1] * n[0]};
  const double x = pi[0] * n[0] + pi[1] * n[1] + pi[2] * n[2];
  const double y = pi[0] * b[0] + pi[1] * b[1] + pi[2] * b[2];
  a.phi = (x == 0.0 && y == 0.0) ? 0.0 : std::atan2(y, x);
  return a;
}

std::array<double, 4> longitudinalVariances(double betaM) {
  const double v0 = sqr(0.726 * betaM + 0.812 * sqr(betaM) + 3.7 * std::pow(betaM, 20));
  return {v0, 0.25 * v0, 4.0 * v0, 4.0 * v0};
}

double logisticScale(double betaN) {
  return std::sqrt(kPi / 8.0) * (0.265 * betaN + 1.194 * sqr(betaN) + 5.372 * std::pow(betaN, 22));
}

double besselI0(double x) {
  // power series Σ (x²/4)^k / (k!)², converged to double precision for the |x| < 30 used
  const double q = 0.25 * x * x;
  double term = 1.0, sum = 1.0;
  for (int k = 1; k < 200; ++k) {
    term *= q / (static_cast<double>(k) * k);
    sum += term;
    if (term < 1e-17 * sum) break;
  }
  return sum;
}

double logBesselI0(double x) {
  x = std::fabs(x);
  if (x < 30.0) return std::log(besselI0(x));
  // asymptotic expansion: I0(x) ~ e^x / sqrt(2 pi x) (1 + 1/(8x) + 9/(128x²) + 225/(3072x³))
  const double r = 1.0 / x;
  return x - 0.5 * std::log(2 * kPi * x) +
         std::log1p(r / 8 + 9 * r * r / 128 + 225 * r * r * r / 3072);
}

double longitudinalM(double sinThetaI, double cosThetaI, double sinThetaO, double cosThetaO,
                     double v) {
  // M = exp(-b) I0(a) / (2 v sinh(1/v)),  a = cos_i cos_o / v,  b = sin_i sin_o / v,
  // evaluated in log space: 2 v sinh(1/v) = v e^{1/v} (1 - e^{-2/v}).
  const double a = cosThetaI * cosThetaO / v;
  const double b = sinThetaI * sinThetaO / v;
  const double logM = logBesselI0(a) - b - 1.0 / v - std::log(v) - std::log1p(-std::exp(-2.0 / v));
  return std::exp(logM);
}

double longitudinalTilted(const ChiangMaterial& m, int p, const FibreAngles& a) {
  double so, co;
  tiltedThetaO(p, m.alpha, a.sinThetaO, a.cosThetaO, &so, &co);
  return longitudinalM(a.sinThetaI, a.cosThetaI, so, co, longitudinalVariances(m.betaM)[p]);
}

double fresnelDielectric(double cosTheta, double eta) {
  cosTheta = std::clamp(cosTheta, 0.0, 1.0);
  const double sin2T = (1 - sqr(cosTheta)) / sqr(eta);
  if (sin2T >= 1) return 1.0;
  const double cosT = safeSqrt(1 - sin2T);
  const double rParl = (eta * cosTheta - cosT) / (eta * cosTheta + cosT);
  const double rPerp = (cosTheta - eta * cosT) / (cosTheta + eta * cosT);
  return 0.5 * (sqr(rParl) + sqr(rPerp));
}

std::array<Rgb, 4> attenuation(const ChiangMaterial& m, double sinThetaO, double h) {
  const double cosThetaO = safeSqrt(1 - sqr(sinThetaO));
  const double cosGammaO = safeSqrt(1 - h * h);
  // Fresnel at the entry point (Chiang §4: the same f for every interface of the path)
  const double f = fresnelDielectric(cosThetaO * cosGammaO, m.eta);
  // refraction: theta_t from Snell, gamma_t from Bravais' eta' (Marschner et al. 2003)
  const double sinThetaT = sinThetaO / m.eta;
  const double cosThetaT = safeSqrt(1 - sqr(sinThetaT));
  const double etaP = safeSqrt(sqr(m.eta) - sqr(sinThetaO)) / std::max(cosThetaO, 1e-12);
  const double sinGammaT = h / etaP;
  const double cosGammaT = safeSqrt(1 - sqr(sinGammaT));
  std::array<Rgb, 4> ap{};
  for (int c = 0; c < 3; ++c) {
    const double T = std::exp(-m.sigmaA[c] * (2.0 * cosGammaT / cosThetaT));
    ap[0][c] = f;
    ap[1][c] = sqr(1 - f) * T;
    ap[2][c] = ap[1][c] * T * f;
    ap[3][c] = ap[2][c] * f * T / (1 - T * f);  // geometric series over p >= 3 (Eq. 6)
  }
  return ap;
}

double deflection(int p, double gammaO, double gammaT) {
  return 2.0 * p * gammaT - 2.0 * gammaO + p * kPi;
}

double trimmedLogistic(double x, double s) {
  auto logistic = [s](double y) {
    y = std::fabs(y);
    const double e = std::exp(-y / s);
    return e / (s * sqr(1 + e));
  };
  auto cdf = [s](double y) { return 1.0 / (1.0 + std::exp(-y / s)); };
  return logistic(x) / (cdf(kPi) - cdf(-kPi));
}

Lobes lobesAtH(const ChiangMaterial& m, const FibreAngles& a, double h) {
  const auto v = longitudinalVariances(m.betaM);
  const double s = logisticScale(m.betaN);
  const double etaP = safeSqrt(sqr(m.eta) - sqr(a.sinThetaO)) / std::max(a.cosThetaO, 1e-12);
  const double gammaO = safeAsin(h);
  const double gammaT = safeAsin(h / etaP);
  const auto ap = attenuation(m, a.sinThetaO, h);
  Lobes l{};
  for (int p = 0; p < 4; ++p) {
    double so, co;
    tiltedThetaO(p, m.alpha, a.sinThetaO, a.cosThetaO, &so, &co);
    l.M[p] = longitudinalM(a.sinThetaI, a.cosThetaI, so, co, v[p]);
    const double n = p < 3 ? trimmedLogistic(wrapPi(a.phi - deflection(p, gammaO, gammaT)), s)
                           : 1.0 / (2.0 * kPi);
    for (int c = 0; c < 3; ++c) l.AN[p][c] = ap[p][c] * n;
  }
  return l;
}

Rgb evalAtH(const ChiangMaterial& m, const FibreAngles& a, double h) {
  const Lobes l = lobesAtH(m, a, h);
  const double inv = 1.0 / std::max(a.cosThetaI, 1e-12);
  Rgb f{0, 0, 0};
  for (int p = 0; p < 4; ++p)
    for (int c = 0; c < 3; ++c) f[c] += l.M[p] * l.AN[p][c] * inv;
  return f;
}

std::array<Rgb, 4> averagedAzimuthal(const ChiangMaterial& m, double sinThetaO, double phi,
                                     int panels) {
  const double s = logisticScale(m.betaN);
  const double cosThetaO = safeSqrt(1 - sqr(sinThetaO));
  const double etaP = safeSqrt(sqr(m.eta) - sqr(sinThetaO)) / std::max(cosThetaO, 1e-12);
  std::array<Rgb, 4> out{};
  forEachH(panels, [&](double h, double w) {
    const double gammaO = safeAsin(h);
    const double gammaT = safeAsin(h / etaP);
    const auto ap = attenuation(m, sinThetaO, h);
    for (int p = 0; p < 3; ++p) {
      const double n = trimmedLogistic(wrapPi(phi - deflection(p, gammaO, gammaT)), s);
      for (int c = 0; c < 3; ++c) out[p][c] += w * ap[p][c] * n;
    }
    for (int c = 0; c < 3; ++c) out[3][c] += w * ap[3][c];
  });
  return out;
}

std::array<Rgb, 4> averagedAttenuation(const ChiangMaterial& m, double sinThetaO, int panels) {
  std::array<Rgb, 4> out{};
  forEachH(panels, [&](double h, double w) {
    const auto ap = attenuation(m, sinThetaO, h);
    for (int p = 0; p < 4; ++p)
      for (int c = 0; c < 3; ++c) out[p][c] += w * ap[p][c];
  });
  return out;
}

std::array<Rgb, 4> evalAveragedLobes(const ChiangMaterial& m, const FibreAngles& a, int panels) {
  // M_p does not depend on h, so ½ ∫ f dh = Σ_p M_p Ñ_p / cos(theta_i) exactly.
  const auto v = longitudinalVariances(m.betaM);
  const auto nbar = averagedAzimuthal(m, a.sinThetaO, a.phi, panels);
  const double inv = 1.0 / std::max(a.cosThetaI, 1e-12);
  std::array<Rgb, 4> out{};
  for (int p = 0; p < 4; ++p) {
    double so, co;
    tiltedThetaO(p, m.alpha, a.sinThetaO, a.cosThetaO, &so, &co);
    const double M = longitudinalM(a.sinThetaI, a.cosThetaI, so, co, v[p]);
    const double n = p < 3 ? 1.0 : 1.0 / (2.0 * kPi);
    for (int c = 0; c < 3; ++c) out[p][c] = M * nbar[p][c] * n * inv;
  }
  return out;
}

Rgb evalAveraged(const ChiangMaterial& m, const FibreAngles& a, int panels) {
  const auto l = evalAveragedLobes(m, a, panels);
  Rgb f{0, 0, 0};
  for (int p = 0; p < 4; ++p)
    for (int c = 0; c < 3; ++c) f[c] += l[p][c];
  return f;
}

Rgb sigmaAFromMelanin(double eumelanin, double pheomelanin) {
  const Rgb eu{0.419, 0.697, 1.37}, pheo{0.187, 0.4, 1.05};
  Rgb s{};
  for (int c = 0; c < 3; ++c) s[c] = eumelanin * eu[c] + pheomelanin * pheo[c];
  return s;
}

Rgb sigmaAFromColor(const Rgb& col, double bn) {
  const double d = 5.969 - 0.215 * bn + 2.532 * sqr(bn) - 10.73 * std::pow(bn, 3) +
                   5.574 * std::pow(bn, 4) + 0.245 * std::pow(bn, 5);
  Rgb s{};
  for (int c = 0; c < 3; ++c) s[c] = sqr(std::log(std::clamp(col[c], 1e-4, 1.0)) / d);
  return s;
}

}  // namespace clhair::ref
