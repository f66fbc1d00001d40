// test_fibre_sampler.cpp — the path reference's lobe sampler of the hair BSDF
// (host/groom/fibre_sampler.h) on its own, for white, blonde and brown fibres, three
// longitudinal roughnesses and views from grazing below to grazing above:
// - its pdf integrates to 1 over the sphere (quadrature);
// - the directions it draws follow its pdf (a chi-square test of a histogram over
//   sin(theta_i) x phi against the pdf integrated over each cell);
// - for white fibres the weights f cos / pdf stay under twice the fibre's albedo (the
//   mixture sampler it replaced reached 7), most lie above half of it, and they average to
//   the albedo.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#include "groom/fibre_sampler.h"
#include "groom/hair_bsdf_cpu.h"

namespace clhair {
namespace {

namespace hb = cpu_bsdf;
constexpr double kPi = 3.14159265358979323846;

struct Case {
  const char* name;
  float eumelanin, betaM, thetaO;
};

// The fibre along y, seen from wo at theta_o above its normal plane.
struct Fibre {
  hb::clh_hair_material mat{};
  hb::clh_hair_view hv{};
  explicit Fibre(const Case& c) {
    mat.sigma_a = hb::clh_hair_sigma_a_from_melanin(c.eumelanin, 0.0f);
    mat.beta_m = c.betaM;
    mat.beta_n = 0.3f;
    mat.alpha = 0.035f;
    mat.eta = 1.55f;
    const hb::clh_v3 t = hb::clh_v3_make(0.0f, 1.0f, 0.0f);
    const hb::clh_v3 wo = hb::clh_v3_unit(
        hb::clh_v3_make(std::cos(c.thetaO) * 0.8f, std::sin(c.thetaO), std::cos(c.thetaO) * 0.6f));
    hb::clh_hair_prepare_to(&hv, &mat, t, wo);
  }
};

std::vector<Case> cases() {
  std::vector<Case> out;
  const struct {
    const char* name;
    float eu;
  } fibres[] = {{"white", 0.0f}, {"blonde", 0.3f}, {"brown", 1.3f}};
  for (const auto& f : fibres)
    for (float bm : {0.1f, 0.3f, 0.6f})
      for (float to : {-1.45f, -0.6f, 0.0f, 0.4f, 1.3f}) out.push_back({f.name, f.eu, bm, to});
  return out;
}

// A direction from (sin theta, phi) in the fibre's frame (t, n, b = t x n).
hb::clh_v3 direction(const hb::clh_hair_view& hv, double s, double phi) {
  const hb::clh_v3 t = hv.t, n = hv.n;
  const hb::clh_v3 b =
      hb::clh_v3_make(t.y * n.z - t.z * n.y, t.z * n.x - t.x * n.z, t.x * n.y - t.y * n.x);
  const float c = static_cast<float>(std::sqrt(std::max(0.0, 1.0 - s * s)));
  const hb::clh_v3 across = hb::clh_v3_add(hb::clh_v3_scale(n, static_cast<float>(std::cos(phi))),
                                           hb::clh_v3_scale(b, static_cast<float>(std::sin(phi))));
  return hb::clh_v3_add(hb::clh_v3_scale(t, static_cast<float>(s)), hb::clh_v3_scale(across, c));
}

// Uniform floats in [0, 1) from a fixed seed.
struct Uniform {
  std::mt19937 rng;
  explicit Uniform(std::uint32_t seed) : rng(seed) {}
  float next() { return static_cast<float>(rng() >> 8) * (1.0f / 16777216.0f); }
};

// The azimuthal cells: the sampler's bins, on both signs of phi. Over one of them the pdf
// does not depend on phi, so the integrals below need quadrature in theta only.
constexpr int kPhiCells = 2 * FibreSampler::kBins;
double phiCellMid(int j) { return -kPi + (j + 0.5) * 2.0 * kPi / kPhiCells; }

TEST(FibreSampler, PdfIntegratesToOneOverTheSphere) {
  // midpoint rule in theta (4000 nodes: 10 or more across the narrowest lobe, TT at
  // beta_m 0.1, whose longitudinal deviation is 0.04) and one node per azimuthal bin
  double worst = 0.0;
  for (const Case& c : cases()) {
    const Fibre f(c);
    const FibreSampler s(f.hv);
    const int nt = 4000;
    double sum = 0.0;
    for (int i = 0; i < nt; ++i) {
      const double th = -0.5 * kPi + (i + 0.5) * kPi / nt;
      for (int j = 0; j < kPhiCells; ++j)
        sum += s.pdf(direction(f.hv, std::sin(th), phiCellMid(j))) * std::cos(th);
    }
    sum *= (kPi / nt) * (2.0 * kPi / kPhiCells);
    worst = std::max(worst, std::fabs(sum - 1.0));
    EXPECT_NEAR(sum, 1.0, 2e-3) << c.name << " beta_m " << c.betaM << " theta_o " << c.thetaO;
  }
  std::printf("pdf integral: worst |1 - integral| %.2e over %zu cases\n", worst, cases().size());
}

TEST(FibreSampler, SamplesFollowThePdf) {
  // 400 000 directions per case into 24 bands of sin(theta) x the 32 azimuthal cells; the
  // expected count of a cell is N times the pdf integrated over it (50 nodes per band).
  // Cells expecting fewer than 5 are pooled. A fixed seed; the bound is the chi-square's
  // mean plus 6 of its standard deviations, which a correct sampler exceeds with
  // probability far below 1e-6 and a wrong lobe weight, theta or table breaks by far.
  const int bands = 24, sub = 50, N = 400000;
  std::size_t index = 0;
  for (const Case& c : cases()) {
    if (++index % 3 != 1) continue;  // every third case: 15 of 45, all fibres and views
    const Fibre f(c);
    const FibreSampler s(f.hv);
    std::vector<double> expected(bands * kPhiCells, 0.0);
    for (int i = 0; i < bands; ++i)
      for (int k = 0; k < sub; ++k) {
        const double sn = -1.0 + (i + (k + 0.5) / sub) * 2.0 / bands;
        for (int j = 0; j < kPhiCells; ++j)
          expected[i * kPhiCells + j] += s.pdf(direction(f.hv, sn, phiCellMid(j))) *
                                         (2.0 / bands / sub) * (2.0 * kPi / kPhiCells) * N;
      }
    std::vector<double> observed(expected.size(), 0.0);
    Uniform u(7u + static_cast<std::uint32_t>(index));
    for (int n = 0; n < N; ++n) {
      const float us[4] = {u.next(), u.next(), u.next(), u.next()};
      const hb::clh_v3 wi = s.sample(us);
      const double sn = std::clamp(static_cast<double>(hb::clh_v3_dot(f.hv.t, wi)), -1.0, 1.0);
      const hb::clh_v3 t = f.hv.t, nn = f.hv.n;
      const hb::clh_v3 b = hb::clh_v3_make(t.y * nn.z - t.z * nn.y, t.z * nn.x - t.x * nn.z,
                                           t.x * nn.y - t.y * nn.x);
      const double phi = std::atan2(hb::clh_v3_dot(wi, b), hb::clh_v3_dot(wi, nn));
      const int i = std::clamp(static_cast<int>((sn + 1.0) * 0.5 * bands), 0, bands - 1);
      const int j =
          std::clamp(static_cast<int>((phi + kPi) / (2.0 * kPi) * kPhiCells), 0, kPhiCells - 1);
      observed[i * kPhiCells + j] += 1.0;
    }
    double chi2 = 0.0, poolE = 0.0, poolO = 0.0, totalE = 0.0;
    int cells = 0;
    for (std::size_t k = 0; k < expected.size(); ++k) {
      totalE += expected[k];
      if (expected[k] < 5.0) {
        poolE += expected[k];
        poolO += observed[k];
        continue;
      }
      chi2 += (observed[k] - expected[k]) * (observed[k] - expected[k]) / expected[k];
      ++cells;
    }
    if (poolE > 0.0) {
      chi2 += (poolO - poolE) * (poolO - poolE) / std::max(poolE, 1.0);
      ++cells;
    }
    const double dof = cells - 1;
    EXPECT_NEAR(totalE, N, 2e-3 * N) << c.name;
    EXPECT_LT(chi2, dof + 6.0 * std::sqrt(2.0 * dof))
        << c.name << " beta_m " << c.betaM << " theta_o " << c.thetaO << ": chi2 " << chi2
        << " over " << dof << " degrees of freedom";
  }
}

TEST(FibreSampler, WhiteFibreWeightsStayNearTheAlbedo) {
  // sigma_a = 0: every lobe is the fibre's own (no colour), so f cos / pdf varies only by
  // how far each lobe's table departs from its Ñ_p and by the lobe probabilities' floor.
  // The weights average to the fibre's albedo, the integral of f cos (quadrature: 1000
  // nodes in theta, 96 in phi); none exceeds twice it (the tail that slows a path
  // tracer's convergence) and at most 5 % fall under half of it (directions drawn from a
  // table's uniform share where the lobe is small, which carry little light).
  double hi = 0.0, lowShare = 0.0;
  for (const Case& c : cases()) {
    if (c.eumelanin != 0.0f) continue;
    const Fibre f(c);
    const FibreSampler s(f.hv);
    double albedo = 0.0;
    const int nt = 1000, np = 96;
    for (int i = 0; i < nt; ++i) {
      const double th = -0.5 * kPi + (i + 0.5) * kPi / nt;
      for (int j = 0; j < np; ++j) {
        const hb::clh_v3 fc =
            s.evalCos(direction(f.hv, std::sin(th), -kPi + (j + 0.5) * 2.0 * kPi / np));
        albedo += fc.y * std::cos(th);
      }
    }
    albedo *= (kPi / nt) * (2.0 * kPi / np);
    Uniform u(99u);
    const int N = 100000;
    double mean = 0.0, wmax = 0.0;
    int low = 0;
    for (int n = 0; n < N; ++n) {
      const float us[4] = {u.next(), u.next(), u.next(), u.next()};
      const hb::clh_v3 wi = s.sample(us);
      const double w = s.evalCos(wi).y / s.pdf(wi);
      mean += w / N;
      wmax = std::max(wmax, w);
      low += w < 0.5 * albedo;
    }
    hi = std::max(hi, wmax / albedo);
    lowShare = std::max(lowShare, static_cast<double>(low) / N);
    EXPECT_NEAR(mean, albedo, 0.005 * albedo) << "beta_m " << c.betaM << " theta_o " << c.thetaO;
    EXPECT_LE(wmax, 2.0 * albedo) << "beta_m " << c.betaM << " theta_o " << c.thetaO;
    EXPECT_LE(low, N / 20) << "beta_m " << c.betaM << " theta_o " << c.thetaO;
  }
  std::printf("white fibres: weights at most %.3f x the albedo, at most %.2f %% under half of it\n",
              hi, 100.0 * lowShare);
}

}  // namespace
}  // namespace clhair
