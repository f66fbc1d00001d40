// test_bsdf.cpp — the hair BSDF: the real-time device model (kernels/common/hair_bsdf.h via
// kernels/bsdf_probe.cl) against the double-precision Chiang 2016 reference
// (tests/reference/chiang_reference.cpp), and invariants of both.
//
//  BsdfReference.*  the reference alone: white furnace (energy = 1 without absorption, <= 1
//                   with), h-averaged reciprocity where it holds exactly, and how far it is
//                   off where it does not (cuticle tilt, theta_o-dependent A_p / N_p).
//  BsdfFit.*        device model vs the h-averaged reference on jittered (theta_i, phi) grids
//                   for many wo and six materials; errors are measured on reflected energy
//                   (f cos(theta_i) dw), per lobe and over solid-angle bins.
//  BsdfFurnace.*    energy of the device model including its diffuse term is <= 1.
// The device helpers are tested in test_bsdf_device.cpp, the aggregated BCSDF of a LOD strand
// in test_bsdf_aggregate.cpp; what the three share is bsdf_support.h.
// Fixed seeds throughout; record counts are not multiples of the work-group size and a
// canary after the outputs catches out-of-bounds writes. docs/hair-shading.md quotes the
// numbers these tests print.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "bsdf_support.h"

namespace clhair {
namespace {

using namespace bsdf_test;

// ---------------------------------------------------------------------------------------
// Reference invariants
// ---------------------------------------------------------------------------------------

TEST(BsdfReference, AveragedMatchesExplicitHIntegral) {
  // evalAveraged (M factored out) equals a brute-force ½ ∫ f(h) dh of evalAtH.
  Rng rng(5);
  const ChiangMaterial m = material(1.0, 0.3);
  for (int i = 0; i < 20; ++i) {
    Frame f = randomFrame(rng);
    Vec3 wo = f.dir(2 * rng.u() - 1, 0.0), wi = f.dir(2 * rng.u() - 1, 2 * kPi * rng.u());
    const double t[3] = {f.t.x, f.t.y, f.t.z}, o[3] = {wo.x, wo.y, wo.z}, w[3] = {wi.x, wi.y, wi.z};
    const FibreAngles a = ref::fibreAngles(t, o, w);
    const Rgb avg = ref::evalAveraged(m, a, 64);
    Rgb brute{0, 0, 0};
    const int n = 20000;
    for (int k = 0; k < n; ++k) {  // midpoint rule in gamma_o
      const double g = -0.5 * kPi + kPi * (k + 0.5) / n;
      const Rgb fh = ref::evalAtH(m, a, std::sin(g));
      for (int c = 0; c < 3; ++c) brute[c] += 0.5 * fh[c] * std::cos(g) * kPi / n;
    }
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(avg[c], brute[c], 1e-6 + 1e-4 * brute[c]);
  }
}

// ∫ f̄ cos(theta_i) dw_i on a fine grid for one theta_o.
double referenceEnergy(const ChiangMaterial& m, double thetaO, int nT, int nP, double* perLobe) {
  Rng rng(17);
  Grid g = makeGrid(nT, nP, rng);
  const double sinO = std::sin(thetaO);
  auto f = referenceOnGrid(m, sinO, g);
  double e = 0;
  for (int p = 0; p < 4; ++p) perLobe[p] = 0;
  for (size_t k = 0; k < f.size(); ++k) {
    const double cosI = std::sqrt(std::max(0.0, 1 - g.sinT[k] * g.sinT[k]));
    for (int p = 0; p < 4; ++p) {
      const double v = lum(f[k][p]) * cosI * g.cellWeight(k);
      perLobe[p] += v;
      e += v;
    }
  }
  return e;
}

TEST(BsdfReference, WhiteFurnace) {
  // sigma_a = 0: Σ_p A_p = 1 for every h, so the energy is 1 up to the normalisation of the
  // tilted M_p and the quadrature. With absorption it must stay below 1.
  std::string report;
  double worstWhite = 0;
  for (double bm : {0.2, 0.4, 0.6}) {
    for (double th : {0.0, 30.0, 60.0, 80.0}) {
      ChiangMaterial white = material(0.0, bm);
      double lobes[4];
      const double e = referenceEnergy(white, deg(th), 160, 96, lobes);
      worstWhite = std::max(worstWhite, std::fabs(e - 1));
      EXPECT_NEAR(e, 1.0, 0.015) << "beta_m " << bm << " theta_o " << th;
      ChiangMaterial light = material(0.3, bm), dark = material(6.0, bm);
      const double el = referenceEnergy(light, deg(th), 96, 64, lobes);
      const double ed = referenceEnergy(dark, deg(th), 96, 64, lobes);
      EXPECT_LE(el, 1.0 + 0.01);
      EXPECT_LE(ed, el + 0.01);
      char buf[160];
      std::snprintf(buf, sizeof buf, "bm %.1f th %2.0f: white %.4f light %.4f dark %.4f\n", bm, th,
                    e, el, ed);
      report += buf;
    }
  }
  std::printf("reference furnace (luminance):\n%s", report.c_str());
  RecordProperty("reference_white_furnace_max_dev", std::to_string(worstWhite));
}

TEST(BsdfReference, ReciprocityWhereExact) {
  // Without tilt and with |theta_i| = |theta_o|, M_p is symmetric and A_p, N_p see the same
  // sin² theta; Ñ_p is even in phi. So the h-averaged f̄ is exactly reciprocal, and per h,
  // f(wi, wo, h) = f(wo, wi, -h).
  Rng rng(23);
  ChiangMaterial m = material(1.3, 0.35, 0.3, 0.0);
  for (int i = 0; i < 200; ++i) {
    Frame f = randomFrame(rng);
    const double s = 2 * rng.u() - 1, sign = rng.u() < 0.5 ? -1.0 : 1.0;
    Vec3 wo = f.dir(s, 2 * kPi * rng.u()), wi = f.dir(sign * s, 2 * kPi * rng.u());
    const double t[3] = {f.t.x, f.t.y, f.t.z}, o[3] = {wo.x, wo.y, wo.z}, w[3] = {wi.x, wi.y, wi.z};
    const FibreAngles a = ref::fibreAngles(t, o, w), b = ref::fibreAngles(t, w, o);
    const Rgb fa = ref::evalAveraged(m, a, 32), fb = ref::evalAveraged(m, b, 32);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(fa[c], fb[c], 1e-9 + 1e-9 * fa[c]);
    const double h = 2 * rng.u() - 1;
    const Rgb ha = ref::evalAtH(m, a, h), hb = ref::evalAtH(m, b, -h);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(ha[c], hb[c], 1e-9 + 1e-9 * ha[c]);
  }
}

TEST(BsdfReference, ReciprocityViolationIsBounded) {
  // In general pairs Chiang's model is not reciprocal: A_p and N_p depend on theta_o only,
  // and the tilt shifts theta_o. Measure the energy-weighted asymmetry
  //   Σ |f̄(wo,wi) - f̄(wi,wo)| / Σ (f̄(wo,wi) + f̄(wi,wo)) / 2
  // over random pairs, without and with a 2 degree tilt, and keep it bounded (documented).
  for (double alpha : {0.0, 2.0}) {
    Rng rng(29);
    ChiangMaterial m = material(1.3, 0.3, 0.3, alpha);
    double num = 0, den = 0;
    for (int i = 0; i < 400; ++i) {
      Frame f = randomFrame(rng);
      Vec3 wo = f.dir(2 * rng.u() - 1, 0.0), wi = f.dir(2 * rng.u() - 1, 2 * kPi * rng.u());
      const double t[3] = {f.t.x, f.t.y, f.t.z}, o[3] = {wo.x, wo.y, wo.z},
                   w[3] = {wi.x, wi.y, wi.z};
      const FibreAngles a = ref::fibreAngles(t, o, w), b = ref::fibreAngles(t, w, o);
      // weight by the product cos_i cos_o, symmetric in the pair
      const double wgt = a.cosThetaI * a.cosThetaO;
      const double fa = lum(ref::evalAveraged(m, a, 24)), fb = lum(ref::evalAveraged(m, b, 24));
      num += wgt * std::fabs(fa - fb);
      den += wgt * 0.5 * (fa + fb);
    }
    const double asym = num / den;
    std::printf("reference reciprocity: alpha %.0f deg, energy-weighted asymmetry %.4f\n", alpha,
                asym);
    RecordProperty(alpha == 0.0 ? "asymmetry_alpha0" : "asymmetry_alpha2", std::to_string(asym));
    EXPECT_LT(asym, 0.25);
  }
}

TEST(BsdfReference, SigmaAMappings) {
  const Rgb s = ref::sigmaAFromMelanin(1.0, 0.5);
  EXPECT_NEAR(s[0], 0.419 + 0.5 * 0.187, 1e-12);
  EXPECT_NEAR(s[2], 1.37 + 0.5 * 1.05, 1e-12);
  // darker colour -> more absorption, white -> none
  const Rgb a = ref::sigmaAFromColor({0.8, 0.5, 0.2}, 0.3);
  EXPECT_LT(a[0], a[1]);
  EXPECT_LT(a[1], a[2]);
  EXPECT_NEAR(ref::sigmaAFromColor({1, 1, 1}, 0.3)[0], 0.0, 1e-12);
}

// ---------------------------------------------------------------------------------------
// Device model vs reference
// ---------------------------------------------------------------------------------------

struct LobeErr {
  double absDiff[5] = {0, 0, 0, 0, 0};  // R, TT, TRT, spec sum, total (diffuse vs p=3)
  double refSum[5] = {0, 0, 0, 0, 0};
  double rtSum[5] = {0, 0, 0, 0, 0};
};

TEST(BsdfFit, MatchesAveragedReference) {
  // Error measure: relative L1 error of reflected energy, Σ |f_rt - f_ref| cos dw over all
  // sampled (wo, wi) / Σ f_ref cos dw, per lobe and for R+TT+TRT, on luminance. Also the
  // worst relative error of solid-angle bins (8 theta_i x 6 phi, per wo) that hold at least
  // 2% of that wo's specular energy. Tolerances are those of a real-time fit: see
  // docs/hair-shading.md for the achieved numbers.
  const int nWo = 24, nT = 64, nP = 48;
  std::string report;
  for (const Case& cs : fitCases()) {
    Rng rng(101);
    LobeErr e;
    double worstBin = 0, energyErrMax = 0;
    std::vector<double> sampleErr;  // |Δf| / f_ref of significant samples
    std::vector<float> recs;
    std::vector<std::vector<std::array<Rgb, 4>>> refs;
    std::vector<Grid> grids;
    for (int o = 0; o < nWo; ++o) {
      Frame f = randomFrame(rng);
      // theta_o spread over [-85, 85] degrees, stratified
      const double sinO = std::sin(deg(-85.0 + 170.0 * (o + rng.u()) / nWo));
      const Vec3 wo = f.dir(sinO, 0.0);
      grids.push_back(makeGrid(nT, nP, rng));
      const Grid& g = grids.back();
      refs.push_back(referenceOnGrid(cs.m, sinO, g));
      for (size_t k = 0; k < g.sinT.size(); ++k) {
        float r[kIn];
        putRecord(r, cs.m, f.t, wo, f.dir(g.sinT[k], g.phi(k)));
        recs.insert(recs.end(), r, r + kIn);
      }
    }
    const auto out = runProbe(recs);
    size_t idx = 0;
    for (int o = 0; o < nWo; ++o) {
      const Grid& g = grids[o];
      double binRef[8][6] = {}, binRt[8][6] = {}, specRef = 0, specRt = 0, peak = 0;
      auto cosOf = [&](size_t k) { return std::sqrt(std::max(0.0, 1 - g.sinT[k] * g.sinT[k])); };
      for (size_t k = 0; k < g.sinT.size(); ++k) {
        const auto& rf = refs[o][k];
        peak = std::max(peak, (lum(rf[0]) + lum(rf[1]) + lum(rf[2])) * cosOf(k));
      }
      for (size_t k = 0; k < g.sinT.size(); ++k, ++idx) {
        const cl_float4* r = &out[idx * kOut];
        const double cosI = r[0].s[3], w = cosI * g.cellWeight(k);
        const double rt[4] = {lum(r[0]), lum(r[1]), lum(r[2]), lum(r[3])};
        const double rf[4] = {lum(refs[o][k][0]), lum(refs[o][k][1]), lum(refs[o][k][2]),
                              lum(refs[o][k][3])};
        for (int p = 0; p < 3; ++p) {
          e.absDiff[p] += w * std::fabs(rt[p] - rf[p]);
          e.refSum[p] += w * rf[p];
          e.rtSum[p] += w * rt[p];
        }
        const double sRt = rt[0] + rt[1] + rt[2], sRf = rf[0] + rf[1] + rf[2];
        e.absDiff[3] += w * std::fabs(sRt - sRf);
        e.refSum[3] += w * sRf;
        e.rtSum[3] += w * sRt;
        e.absDiff[4] += w * std::fabs(sRt + rt[3] - sRf - rf[3]);
        e.refSum[4] += w * (sRf + rf[3]);
        e.rtSum[4] += w * (sRt + rt[3]);
        // per-sample error on reflected radiance f cos(theta_i), each side with its own cosine
        if (sRf * cosOf(k) > 0.05 * peak) {
          sampleErr.push_back(std::fabs(sRt * cosI / (sRf * cosOf(k)) - 1));
        }
        const int bi = std::min(7, static_cast<int>((g.sinT[k] + 1) * 4));
        const int bj = std::min(5, static_cast<int>(g.phi(k) / kPi * 6));
        binRef[bi][bj] += w * sRf;
        binRt[bi][bj] += w * sRt;
        specRef += w * sRf;
        specRt += w * sRt;
      }
      for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 6; ++j)
          if (binRef[i][j] > 0.02 * specRef)
            worstBin = std::max(worstBin, std::fabs(binRt[i][j] / binRef[i][j] - 1));
      energyErrMax = std::max(energyErrMax, std::fabs(specRt / specRef - 1));
    }
    double rel[5];
    for (int p = 0; p < 5; ++p) rel[p] = e.absDiff[p] / e.refSum[p];
    std::sort(sampleErr.begin(), sampleErr.end());
    const double p95 = sampleErr[sampleErr.size() * 95 / 100], pmax = sampleErr.back();
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "%-12s L1 R %.3f TT %.3f TRT %.3f spec %.3f total %.3f | bin %.3f | "
                  "energy %.3f | sample p95 %.3f max %.3f\n",
                  cs.name, rel[0], rel[1], rel[2], rel[3], rel[4], worstBin, energyErrMax, p95,
                  pmax);
    report += buf;
    RecordProperty(std::string(cs.name) + "_spec_L1", std::to_string(rel[3]));
    // real-time tolerances (luminance, energy-weighted)
    EXPECT_LT(rel[0], 0.04) << cs.name << " R";
    EXPECT_LT(rel[1], 0.04) << cs.name << " TT";
    EXPECT_LT(rel[2], 0.08) << cs.name << " TRT";
    EXPECT_LT(rel[3], 0.04) << cs.name << " R+TT+TRT";
    EXPECT_LT(rel[4], 0.10) << cs.name << " total (diffuse replaces the p=3 lobe)";
    EXPECT_LT(worstBin, 0.08) << cs.name << " solid-angle bins";
    EXPECT_LT(energyErrMax, 0.03) << cs.name << " specular energy per wo";
    EXPECT_LT(p95, 0.12) << cs.name << " 95th percentile of per-sample error (f cos > 5% of peak)";
    EXPECT_LT(pmax, 0.25) << cs.name << " worst per-sample error (f cos > 5% of peak)";
  }
  std::printf(
      "device fit vs h-averaged reference (luminance; L1 and bins energy-weighted; "
      "samples with f cos > 5%% of the peak of their wo):\n%s",
      report.c_str());
}

TEST(BsdfFit, EnvironmentTerms) {
  // spec_weight = Ā_R + Ā_TRT must match the reference's h-averaged energies; the GGX
  // roughness must grow with beta_m and stay in (0, 1].
  std::vector<float> recs;
  std::vector<ChiangMaterial> mats;
  std::vector<double> sinOs;
  for (double bm : {0.2, 0.3, 0.45, 0.6})
    for (double th : {0.0, 40.0, 75.0}) {
      ChiangMaterial m = material(0.8, bm);
      Frame f{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}};
      const double s = std::sin(deg(th));
      float r[kIn];
      putRecord(r, m, f.t, f.dir(s, 0), f.dir(-s, 0.3));
      recs.insert(recs.end(), r, r + kIn);
      mats.push_back(m);
      sinOs.push_back(s);
    }
  const auto out = runProbe(recs);
  for (size_t i = 0; i < mats.size(); ++i) {
    const auto ab = ref::averagedAttenuation(mats[i], sinOs[i], 32);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(out[i * kOut + 5].s[c], ab[0][c] + ab[2][c], 0.02 * (ab[0][c] + ab[2][c]));
    EXPECT_NEAR(out[i * kOut + 3].s[3], ab[3][1], 1e-4 + 0.05 * ab[3][1]);  // diffuse albedo
    const float alpha = out[i * kOut + 5].s[3];
    EXPECT_GT(alpha, 0.0f);
    EXPECT_LE(alpha, 1.0f);
    // The GGX roughness is defined by matching mean cosines about the mirror direction
    // (theta_i = -theta_o, phi = 0): compare with the reference R+TRT lobes' mean cosine.
    Rng rng(59);
    Grid g = makeGrid(96, 64, rng);
    const auto f = referenceOnGrid(mats[i], sinOs[i], g);
    const double sinO = sinOs[i], cosO = std::sqrt(1 - sinO * sinO);
    double num = 0, den = 0;
    for (size_t k = 0; k < f.size(); ++k) {
      const double cosI = std::sqrt(std::max(0.0, 1 - g.sinT[k] * g.sinT[k]));
      const double w = (lum(f[k][0]) + lum(f[k][2])) * cosI * g.cellWeight(k);
      num += w * (-g.sinT[k] * sinO + cosI * cosO * std::cos(g.phi(k)));
      den += w;
    }
    const double a2 = static_cast<double>(alpha) * alpha, c = 1 - a2;
    const double muGgx = c < 1e-6 ? 0.0 : 2 * (1 / c + a2 * std::log(a2) / (c * c)) - 1;
    std::printf("env bm %.2f sin_o %.2f: ggx alpha %.3f, mean cos ggx %.3f ref %.3f\n",
                mats[i].betaM, sinO, alpha, muGgx, num / den);
    EXPECT_NEAR(muGgx, num / den, 0.12) << "beta_m " << mats[i].betaM << " sin_o " << sinO;
    if (i >= 3) {
      EXPECT_GT(alpha, out[(i - 3) * kOut + 5].s[3] - 1e-4f) << "monotone in beta_m";
    }
  }
}

TEST(BsdfFurnace, DeviceEnergyAtMostOne) {
  // ∫ f cos(theta_i) dw_i of the device model INCLUDING its diffuse term, per channel, on a
  // jittered grid: <= 1 + 1% (quadrature) for every wo, and ~1 for sigma_a = 0.
  const int nT = 128, nP = 72;
  std::string report;
  struct Mat {
    const char* name;
    ChiangMaterial m;
  };
  const Mat mats[] = {{"white_bm0.2", material(0, 0.2)},
                      {"white_bm0.6", material(0, 0.6)},
                      {"light_bm0.3", material(0.3, 0.3)},
                      {"dark_bm0.3", material(6.0, 0.3)}};
  const double thetas[] = {0.0, 30.0, 60.0, 80.0};
  std::vector<float> recs;
  Rng rng(7);
  std::vector<Grid> grids;
  for (const Mat& mt : mats)
    for (double th : thetas) {
      Frame f = randomFrame(rng);
      grids.push_back(makeGrid(nT, nP, rng));
      const Grid& g = grids.back();
      const Vec3 wo = f.dir(std::sin(deg(th)), 0.0);
      for (size_t k = 0; k < g.sinT.size(); ++k) {
        float r[kIn];
        putRecord(r, mt.m, f.t, wo, f.dir(g.sinT[k], g.phi(k)));
        recs.insert(recs.end(), r, r + kIn);
      }
    }
  const auto out = runProbe(recs);
  size_t idx = 0, gi = 0;
  for (const Mat& mt : mats)
    for (double th : thetas) {
      const Grid& g = grids[gi++];
      double e[3] = {0, 0, 0};
      for (size_t k = 0; k < g.sinT.size(); ++k, ++idx) {
        const cl_float4* r = &out[idx * kOut];
        const double w = r[0].s[3] * g.cellWeight(k);
        for (int c = 0; c < 3; ++c) e[c] += w * r[4].s[c];  // the one-call full f
      }
      char buf[128];
      std::snprintf(buf, sizeof buf, "%-12s th %2.0f: %.4f %.4f %.4f\n", mt.name, th, e[0], e[1],
                    e[2]);
      report += buf;
      for (int c = 0; c < 3; ++c) {
        EXPECT_LE(e[c], 1.01) << mt.name << " theta_o " << th;
        if (mt.m.sigmaA[c] == 0.0) {
          EXPECT_NEAR(e[c], 1.0, 0.02) << mt.name << " theta_o " << th;
        }
      }
    }
  std::printf("device furnace (R,G,B):\n%s", report.c_str());
}

}  // namespace
}  // namespace clhair
