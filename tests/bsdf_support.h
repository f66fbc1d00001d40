// bsdf_support.h — what the hair BSDF tests share (test_bsdf.cpp, test_bsdf_device.cpp,
// test_bsdf_aggregate.cpp): fibre frames from a portable random stream, the Chiang reference's
// materials, records of the probe kernels (kernels/bsdf_probe.cl) and their runner, and the
// jittered (theta_i, phi) grids the reference is integrated on.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "cl/device_impl.h"
#include "probe_kernel.h"
#include "reference/chiang_reference.h"
#include "test_util.h"

namespace clhair {
namespace bsdf_test {

using ref::ChiangMaterial;
using ref::FibreAngles;
using ref::Rgb;

constexpr double kPi = 3.14159265358979323846;
constexpr int kIn = 20;  // floats per probe record (bsdf_probe.cl)
constexpr int kOut = 6;  // float4 per probe result

inline double deg(double d) { return d * kPi / 180.0; }

struct Vec3 {
  double x, y, z;
};
inline Vec3 operator*(double s, Vec3 v) { return {s * v.x, s * v.y, s * v.z}; }
inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline Vec3 normalized(Vec3 v) { return (1.0 / std::sqrt(dot(v, v))) * v; }

// Portable uniform [0, 1) from mt19937 (distributions are not portable across libraries).
struct Rng {
  std::mt19937 gen;
  explicit Rng(unsigned seed) : gen(seed) {}
  double u() { return static_cast<double>(gen() >> 8) * (1.0 / 16777216.0); }
};

// A fibre frame: tangent t and a normal basis (n, b); directions from (sin theta, phi).
struct Frame {
  Vec3 t, n, b;
  Vec3 dir(double sinTheta, double phi) const {
    const double c = std::sqrt(std::max(0.0, 1 - sinTheta * sinTheta));
    return sinTheta * t + (c * std::cos(phi)) * n + (c * std::sin(phi)) * b;
  }
};

inline Frame randomFrame(Rng& rng) {
  const double z = 2 * rng.u() - 1, a = 2 * kPi * rng.u(), r = std::sqrt(1 - z * z);
  Vec3 t{r * std::cos(a), r * std::sin(a), z};
  Vec3 ax = std::fabs(t.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  Vec3 n = normalized(ax + (-dot(ax, t)) * t);
  return {t, n, cross(t, n)};
}

struct Case {
  const char* name;
  ChiangMaterial m;
};

inline ChiangMaterial material(double eumelanin, double betaM, double betaN = 0.3,
                               double alphaDeg = 2.0) {
  ChiangMaterial m;
  m.sigmaA = ref::sigmaAFromMelanin(eumelanin, 0.0);
  m.betaM = betaM;
  m.betaN = betaN;
  m.alpha = deg(alphaDeg);
  m.eta = 1.55;
  return m;
}

// Materials of the fit test: light (blond, eumelanin 0.3) and dark (eumelanin 6) hair with
// beta_m 0.2-0.6 at beta_n 0.3, plus beta_n 0.2 and 0.5; alpha 2 degrees, eta 1.55.
inline std::vector<Case> fitCases() {
  return {{"light_bm0.2", material(0.3, 0.2)},      {"light_bm0.4", material(0.3, 0.4)},
          {"light_bm0.6", material(0.3, 0.6)},      {"dark_bm0.2", material(6.0, 0.2)},
          {"dark_bm0.4", material(6.0, 0.4)},       {"dark_bm0.6", material(6.0, 0.6)},
          {"light_bn0.2", material(0.3, 0.3, 0.2)}, {"light_bn0.5", material(0.3, 0.3, 0.5)}};
}

inline void putRecord(float* r, const ChiangMaterial& m, Vec3 t, Vec3 wo, Vec3 wi) {
  for (int k = 0; k < kIn; ++k) r[k] = 0.0f;
  for (int c = 0; c < 3; ++c) r[c] = static_cast<float>(m.sigmaA[c]);
  r[3] = static_cast<float>(m.betaM);
  r[4] = static_cast<float>(m.betaN);
  r[5] = static_cast<float>(m.alpha);
  r[6] = static_cast<float>(m.eta);
  const Vec3 v[3] = {t, wo, wi};
  for (int k = 0; k < 3; ++k) {
    r[8 + 4 * k] = static_cast<float>(v[k].x);
    r[9 + 4 * k] = static_cast<float>(v[k].y);
    r[10 + 4 * k] = static_cast<float>(v[k].z);
  }
}

// Runs bsdf_probe_eval over `records` (kIn floats each); returns kOut float4 per record.
inline const cl_float4 kCanary = {{-123.0f, -456.0f, -789.0f, -1.0f}};

inline std::vector<cl_float4> runProbe(const std::vector<float>& records) {
  return test::runProbeKernel("bsdf_probe_eval", records,
                              static_cast<cl_uint>(records.size() / kIn), kOut, kCanary);
}

inline double lum(const Rgb& c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }
inline double lum(const cl_float4& c) {
  return 0.2126 * c.s[0] + 0.7152 * c.s[1] + 0.0722 * c.s[2];
}

// A jittered (theta_i, phi) grid over the sphere, uniform in theta_i so the narrow
// longitudinal lobes near grazing angles are resolved; phi in [0, pi] only because every
// h-averaged lobe is even in phi (the solid-angle weight counts both signs). Cell k is
// (row k / nPhi, column k % nPhi); phi is jittered per column so the reference's
// h-integral Ñ_p(phi) is computed once per column.
struct Grid {
  int nTheta, nPhi;
  std::vector<double> sinT;    // per cell
  std::vector<double> phiCol;  // per column
  double phi(size_t k) const { return phiCol[k % nPhi]; }
  // solid angle of cell k: cos(theta) dtheta dphi, x2 for the mirrored -phi half
  double cellWeight(size_t k) const {
    return std::sqrt(std::max(0.0, 1 - sinT[k] * sinT[k])) * (kPi / nTheta) * (kPi / nPhi) * 2.0;
  }
};

inline Grid makeGrid(int nTheta, int nPhi, Rng& rng) {
  Grid g{nTheta, nPhi, {}, {}};
  for (int j = 0; j < nPhi; ++j) g.phiCol.push_back(kPi * (j + rng.u()) / nPhi);
  for (int i = 0; i < nTheta; ++i)
    for (int j = 0; j < nPhi; ++j) g.sinT.push_back(std::sin(kPi * ((i + rng.u()) / nTheta - 0.5)));
  return g;
}

// Reference lobes f̄_p (p = 0..3, including 1/cos theta_i) on a grid for one wo: the
// products ref::evalAveragedLobes forms, with Ñ_p (a function of theta_o and phi only)
// computed once per phi column.
inline std::vector<std::array<Rgb, 4>> referenceOnGrid(const ChiangMaterial& m, double sinO,
                                                       const Grid& g) {
  std::vector<std::array<Rgb, 4>> nbar(g.nPhi);
  for (int j = 0; j < g.nPhi; ++j) nbar[j] = ref::averagedAzimuthal(m, sinO, g.phiCol[j], 32);
  std::vector<std::array<Rgb, 4>> out(g.sinT.size());
  for (size_t k = 0; k < g.sinT.size(); ++k) {
    FibreAngles a{};
    a.sinThetaO = sinO;
    a.cosThetaO = std::sqrt(1 - sinO * sinO);
    a.sinThetaI = g.sinT[k];
    a.cosThetaI = std::sqrt(std::max(0.0, 1 - g.sinT[k] * g.sinT[k]));
    a.phi = g.phi(k);
    const auto& nb = nbar[k % g.nPhi];
    for (int p = 0; p < 4; ++p) {
      const double M = ref::longitudinalTilted(m, p, a);
      const double w = (p < 3 ? 1.0 : 1.0 / (2 * kPi)) / std::max(a.cosThetaI, 1e-12);
      for (int c = 0; c < 3; ++c) out[k][p][c] = M * nb[p][c] * w;
    }
  }
  return out;
}

}  // namespace bsdf_test
}  // namespace clhair
