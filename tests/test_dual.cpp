// test_dual.cpp — light scattered between fibres (dual scattering, kernels/common/hair_dual.h)
// and the fibre albedo behind a strand file's colour (clh_hair_sigma_a_from_albedo):
//   Dual.DeviceMatchesCpuCompile   bsdf_probe_dual on the device against the same header
//                                  compiled as C++ (host/groom/hair_bsdf_cpu.h)
//   Dual.NoHairAroundIsTheSingleFibre   tau = tau_b = 0 gives clh_hair_eval_cos back
//   Dual.StackSumsMatchLayerByLayer   the closed-form sums of the fibre stack (E[T_n], the
//                                  back scattering E[R_{1+m}] - a_B, n and m Poisson) against
//                                  the stack built one layer at a time and summed over n
//   Dual.StackBeginsWithZinkesTerms  for dark fibres R_inf - a_B is Zinke's A_1 + A_3; for
//                                  light ones it is more (the terms Zinke leave out)
//   Dual.GlobalPartCarriesThePoissonShare   the global part integrates over the sphere to
//                                  d_f (E[T_n] - e^{-tau}) times the fibre's albedo
//   Dual.BackLobeCarriesItsEnergy  the back lobe integrates to d_b (E[R_{1+m}] - a_B)
//   Dual.WhiteFurnaceInASlab       white fibres inside a slab of hair under a uniform white
//                                  sky: never brighter than the furnace's 1, never darker
//                                  than the shadowed single scattering
//   Dual.LightHairGainsSaturation  deeper in blonde hair the light is redder (the colour
//                                  multiple scattering gives light hair)
//   Dual.FileColourIsTheFibreAlbedo   sigma_a from a colour gives a fibre of that albedo
// Integrals are midpoint sums over (sin theta_i, phi), where f cos(theta_i) dw_i =
// f cos dtheta dphi ... written as (M Ñ) d(sin theta) dphi / cos theta: the sums below take
// f cos(theta_i) from the header and multiply by the solid angle of each cell.
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "cl/device_impl.h"
#include "groom/hair_bsdf_cpu.h"
#include "probe_kernel.h"
#include "test_util.h"

namespace clhair {
namespace {

namespace hb = cpu_bsdf;
constexpr double kPi = 3.14159265358979323846;
constexpr int kIn = 20;  // floats per probe record (bsdf_probe.cl)

struct Dir {
  float x, y, z;
};

hb::clh_v3 v3(Dir d) { return hb::clh_v3_make(d.x, d.y, d.z); }

Dir unit(double x, double y, double z) {
  const double l = std::sqrt(x * x + y * y + z * z);
  return {static_cast<float>(x / l), static_cast<float>(y / l), static_cast<float>(z / l)};
}

hb::clh_hair_material material(hb::clh_v3 sigma) {
  hb::clh_hair_material m;
  m.sigma_a = sigma;
  m.beta_m = 0.3f;
  m.beta_n = 0.3f;
  m.alpha = 2.0f * static_cast<float>(kPi) / 180.0f;
  m.eta = 1.55f;
  return m;
}

hb::clh_v3 melanin(float eu) { return hb::clh_hair_sigma_a_from_melanin(eu, 0.0f); }

// The fibre stack of hair_dual.h built one layer at a time (each passes a_f on and sends a_b
// back; adding a layer under a stack of reflectance R and transmittance T gives
// R + T^2 a_b / (1 - R a_b) and T a_f / (1 - R a_b)), with the header's hold of a_f + a_b at
// 0.995, and the expectations over n Poisson of mean tau summed term by term.
struct Stack {
  double af, ab;
  Stack(double f, double b) : af(f), ab(b) {
    if (f + b > 0.995) {
      af = f * 0.995 / (f + b);
      ab = b * 0.995 / (f + b);
    }
  }
  // reflectance and transmittance of n layers
  std::pair<double, double> layers(int n) const {
    double r = 0.0, t = 1.0;
    for (int k = 0; k < n; ++k) {
      const double d = 1.0 - r * ab;
      r += t * t * ab / d;
      t *= af / d;
    }
    return {r, t};
  }
  template <class F>
  static double poisson(double tau, F f) {
    double sum = 0.0, p = std::exp(-tau);
    for (int m = 0; m < 600; ++m) {
      sum += p * f(m);
      p *= tau / (m + 1);
    }
    return sum;
  }
  double through(double tau) const {
    return poisson(tau, [&](int m) { return layers(m).second; });
  }
  double back(double tauB) const {
    return poisson(tauB, [&](int m) { return layers(m + 1).first; }) - ab;
  }
};

struct Shaded {
  hb::clh_hair_view hv;
  hb::clh_hair_dual ds;
};

Shaded prepare(const hb::clh_hair_material& m, Dir t, Dir wo) {
  Shaded s;
  hb::clh_hair_prepare_to(&s.hv, &m, v3(t), v3(wo));
  hb::clh_hair_dual_prepare_to(&s.ds, &s.hv);
  return s;
}

hb::clh_v3 dual(const Shaded& s, Dir wi, float tau, float tauB) {
  return hb::clh_hair_dual_eval_cos(&s.hv, &s.ds, v3(wi), hb::clh_hair_eval_cos(&s.hv, v3(wi)), tau,
                                    tauB);
}

// Sum over a (sin theta, phi) grid about the world z axis of g(direction) dw, g returning rgb.
template <class G>
std::array<double, 3> sphereIntegral(G g, int nz = 180, int nphi = 360) {
  std::array<double, 3> sum{0.0, 0.0, 0.0};
  const double dw = (2.0 / nz) * (2.0 * kPi / nphi);  // d(cos) dphi
  for (int i = 0; i < nz; ++i) {
    const double z = -1.0 + (i + 0.5) * 2.0 / nz, r = std::sqrt(1.0 - z * z);
    for (int j = 0; j < nphi; ++j) {
      const double a = (j + 0.5) * 2.0 * kPi / nphi;
      const hb::clh_v3 v = g(unit(r * std::cos(a), r * std::sin(a), z));
      sum[0] += v.x * dw;
      sum[1] += v.y * dw;
      sum[2] += v.z * dw;
    }
  }
  return sum;
}

TEST(Dual, DeviceMatchesCpuCompile) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const hb::clh_v3 sigmas[] = {
      melanin(0.3f), melanin(1.3f), melanin(8.0f), hb::clh_v3_splat(0.0f),
      hb::clh_hair_sigma_a_from_albedo(hb::clh_v3_make(1.0f, 0.925f, 0.569f), 1.55f)};
  const float taus[] = {0.0f, 0.4f, 2.5f, 9.0f}, backs[] = {0.0f, 1.0f, 6.0f};
  std::vector<float> rec;
  std::vector<hb::clh_v3> expectF, expectP;
  std::vector<float> expectAo;
  const float mapTs[] = {-1.0f, 0.0f, 0.03f, 0.4f, 1.0f};  // the maps' mean transmittance
  for (int i = 0; i < 181; ++i) {                          // not a multiple of the work-group size
    const hb::clh_hair_material m = material(sigmas[i % 5]);
    const Dir t = unit(u(gen), u(gen), u(gen)), wo = unit(u(gen), u(gen), u(gen)),
              wi = unit(u(gen), u(gen), u(gen));
    const float tau = taus[i % 4], tauB = backs[(i / 4) % 3], ao = 0.05f + 0.95f * (i % 7) / 6.0f;
    float r[kIn] = {};
    r[0] = m.sigma_a.x;
    r[1] = m.sigma_a.y;
    r[2] = m.sigma_a.z;
    r[3] = m.beta_m;
    r[4] = m.beta_n;
    r[5] = m.alpha;
    r[6] = m.eta;
    r[7] = tau;
    r[11] = tauB;
    r[15] = ao;
    r[19] = mapTs[(i / 3) % 5];
    const Dir v[3] = {t, wo, wi};
    for (int k = 0; k < 3; ++k) {
      r[8 + 4 * k] = v[k].x;
      r[9 + 4 * k] = v[k].y;
      r[10 + 4 * k] = v[k].z;
    }
    rec.insert(rec.end(), r, r + kIn);
    const Shaded s = prepare(m, t, wo);
    expectF.push_back(dual(s, wi, tau, tauB));
    expectP.push_back(hb::clh_hair_dual_probe(&s.ds, ao));
    expectAo.push_back(hb::clh_hair_dual_probe_ao(ao, r[19]));
  }
  const cl_uint n = static_cast<cl_uint>(expectF.size());
  const cl_float4 canary = {{-123.0f, -456.0f, -789.0f, -1.0f}};
  const std::vector<cl_float4> out = test::runProbeKernel("bsdf_probe_dual", rec, n, 2, canary);
  auto near = [](float got, float want) {
    return std::isfinite(got) && std::fabs(got - want) <= 1e-6f + 2e-4f * std::fabs(want);
  };
  for (cl_uint i = 0; i < n; ++i) {
    const float ef[3] = {expectF[i].x, expectF[i].y, expectF[i].z};
    const float ep[3] = {expectP[i].x, expectP[i].y, expectP[i].z};
    for (int c = 0; c < 3; ++c) {
      EXPECT_TRUE(near(out[2 * i].s[c], ef[c]))
          << i << " light " << c << ": " << out[2 * i].s[c] << " vs " << ef[c];
      EXPECT_TRUE(near(out[2 * i + 1].s[c], ep[c]))
          << i << " probe " << c << ": " << out[2 * i + 1].s[c] << " vs " << ep[c];
    }
    EXPECT_TRUE(near(out[2 * i + 1].s[3], expectAo[i]))
        << i << " probe AO: " << out[2 * i + 1].s[3] << " vs " << expectAo[i];
  }
}

TEST(Dual, NoHairAroundIsTheSingleFibre) {
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const Shaded s = prepare(material(melanin(0.3f + 0.05f * i)), unit(u(gen), u(gen), u(gen)),
                             unit(u(gen), u(gen), u(gen)));
    const Dir wi = unit(u(gen), u(gen), u(gen));
    const hb::clh_v3 single = hb::clh_hair_eval_cos(&s.hv, v3(wi)), d = dual(s, wi, 0.0f, 0.0f);
    EXPECT_FLOAT_EQ(d.x, single.x);
    EXPECT_FLOAT_EQ(d.y, single.y);
    EXPECT_FLOAT_EQ(d.z, single.z);
    const hb::clh_v3 p = hb::clh_hair_dual_probe(&s.ds, 1.0f);
    EXPECT_EQ(p.x + p.y + p.z, 0.0f) << "an AO of 1 leaves nothing to give back";
  }
}

TEST(Dual, TheProbeAoIsRefinedByTheMapsBetweenTheTwoDepths) {
  const float w = CLH_DUAL_PROBE_MAP_WEIGHT;
  ASSERT_GT(w, 0.0f);
  ASSERT_LT(w, 1.0f);
  const float aos[] = {1e-4f, 0.01f, 0.1f, 0.35f, 0.7f, 0.99f, 1.0f};
  const float ts[] = {0.0f, 1e-5f, 0.02f, 0.2f, 0.5f, 0.9f, 1.0f};
  for (float ao : aos) {
    // no light with a map: the AO as baked, bit for bit
    EXPECT_EQ(hb::clh_hair_dual_probe_ao(ao, -1.0f), ao);
    float prev = 0.0f;
    for (float t : ts) {
      const float a = hb::clh_hair_dual_probe_ao(ao, t);
      const float tc = std::max(t, 1e-4f);
      // the depths blended: -ln a = (1 - w)(-ln ao) + w(-ln t)
      const double want = std::exp((1.0 - w) * std::log(double(ao)) + w * std::log(double(tc)));
      EXPECT_NEAR(a, want, 2e-3 * want) << "ao " << ao << " t " << t;
      EXPECT_GE(a, std::min(ao, tc) * (1.0f - 2e-3f)) << "ao " << ao << " t " << t;
      EXPECT_LE(a, std::max(ao, tc) * (1.0f + 2e-3f)) << "ao " << ao << " t " << t;
      EXPECT_LE(a, 1.0f) << "an AO above 1 would take light away in the term";
      EXPECT_GE(a, prev) << "more light through the maps never darkens the term";
      prev = a;
    }
    // the maps agree with the AO: nothing changes
    EXPECT_NEAR(hb::clh_hair_dual_probe_ao(ao, ao), ao, 2e-3f * ao);
  }
  // an open point: no map darkness and no AO leaves nothing to give back
  EXPECT_EQ(hb::clh_hair_dual_probe_ao(1.0f, 1.0f), 1.0f);
}

// The fibre's tangent and view of the energy tests: tilted fibre, oblique view.
const Dir kT = unit(0.2, 0.1, 1.0), kWo = unit(0.8, -0.3, 0.35);

TEST(Dual, StackSumsMatchLayerByLayer) {
  // a_f, a_b from dark hair to a fibre that absorbs nothing (held at a_f + a_b = 0.995)
  const std::pair<float, float> fibres[] = {{0.2f, 0.1f},    {0.5f, 0.3f}, {0.69f, 0.3f},
                                            {0.75f, 0.245f}, {0.7f, 0.3f}, {0.05f, 0.02f}};
  const std::size_t n = std::size(fibres);
  for (std::size_t i = 0; i < n; ++i) {
    // three fibres in the three channels, so dark and light channels share a stack
    const std::pair<float, float> f[3] = {fibres[i], fibres[(i + 1) % n], fibres[(i + 3) % n]};
    const hb::clh_dual_stack ds =
        hb::clh_dual_stack_make(hb::clh_v3_make(f[0].first, f[1].first, f[2].first),
                                hb::clh_v3_make(f[0].second, f[1].second, f[2].second));
    for (int c = 0; c < 3; ++c) {
      const auto [af, ab] = f[c];
      const Stack st(af, ab);
      auto channel = [c](hb::clh_v3 v) { return c == 0 ? v.x : c == 1 ? v.y : v.z; };
      for (float tau : {0.0f, 0.2f, 0.5f, 1.0f, 2.0f, 3.0f, 10.0f, 30.0f}) {
        const double t = st.through(tau), got = channel(hb::clh_dual_stack_through(&ds, tau));
        // the first two terms exact, the rest as one geometric tail: within 3 % of the sums
        EXPECT_NEAR(got, t, 0.03 * t + 1e-6) << "a_f " << af << " a_b " << ab << " tau " << tau;
        EXPECT_GE(got, std::exp(-tau * (1.0 - af)) - 1e-6) << "never below forward scattering";
        const double b = st.back(tau), gotB = channel(hb::clh_dual_stack_back(&ds, tau));
        EXPECT_NEAR(gotB, b, 0.05 * b + 1e-5) << "a_f " << af << " a_b " << ab << " tau_b " << tau;
      }
      EXPECT_NEAR(channel(hb::clh_dual_stack_back(&ds, 0.0f)), 0.0f, 1e-6f) << "nothing behind";
    }
  }
}

TEST(Dual, StackBeginsWithZinkesTerms) {
  auto zinke = [](double af, double ab) {
    const double d = 1.0 - af * af;
    return ab * af * af / d + ab * ab * ab * af * af / (d * d * d);
  };
  // brown: the higher terms are negligible
  auto rBack = [](float af, float ab) {
    return hb::clh_dual_stack_make(hb::clh_v3_splat(af), hb::clh_v3_splat(ab)).r_back.x;
  };
  EXPECT_NEAR(rBack(0.2f, 0.1f), zinke(0.2, 0.1), 1e-3 * zinke(0.2, 0.1) + 1e-6);
  // nearly white: Zinke's two terms are 70 % of it; below a_F, its limit at a_F + a_B = 1
  const float white = rBack(0.69f, 0.3f);
  EXPECT_GT(white, 1.3 * zinke(0.69, 0.3));
  EXPECT_LT(white, 0.69f);
}

TEST(Dual, GlobalPartCarriesThePoissonShare) {
  for (float eu : {0.0f, 0.3f, 1.3f}) {
    const Shaded s = prepare(material(melanin(eu)), kT, kWo);
    const float af[3] = {s.ds.a_f.x, s.ds.a_f.y, s.ds.a_f.z};
    const float ab[3] = {s.ds.a_b.x, s.ds.a_b.y, s.ds.a_b.z};
    const float alb[3] = {s.ds.albedo.x, s.ds.albedo.y, s.ds.albedo.z};
    for (float tau : {0.5f, 2.0f, 6.0f}) {
      const auto g = sphereIntegral([&](Dir wi) {
        const hb::clh_v3 single = hb::clh_hair_eval_cos(&s.hv, v3(wi));
        return hb::clh_v3_sub(dual(s, wi, tau, 0.0f), hb::clh_v3_scale(single, std::exp(-tau)));
      });
      for (int c = 0; c < 3; ++c) {
        const double want =
            CLH_DUAL_DF * (Stack(af[c], ab[c]).through(tau) - std::exp(-tau)) * alb[c];
        // 3 % of E[T_n] (the sums' approximation) on the part above e^-tau, 1 % the grid's
        const double tol = CLH_DUAL_DF * 0.03 * Stack(af[c], ab[c]).through(tau) * alb[c];
        EXPECT_NEAR(g[c], want, 0.01 * want + tol + 1e-5) << "eumelanin " << eu << " tau " << tau;
      }
    }
  }
}

TEST(Dual, BackLobeCarriesItsEnergy) {
  for (float eu : {0.0f, 0.3f, 1.3f}) {
    const Shaded s = prepare(material(melanin(eu)), kT, kWo);
    const float af[3] = {s.ds.a_f.x, s.ds.a_f.y, s.ds.a_f.z};
    const float ab[3] = {s.ds.a_b.x, s.ds.a_b.y, s.ds.a_b.z};
    for (float tauB : {0.3f, 3.0f}) {
      const auto g = sphereIntegral([&](Dir wi) {
        return hb::clh_v3_sub(dual(s, wi, 0.0f, tauB), hb::clh_hair_eval_cos(&s.hv, v3(wi)));
      });
      for (int c = 0; c < 3; ++c) {
        // the lobe's M is cut at the poles only by its own normalisation: 2 % covers the grid;
        // the stack's sum is within 5 % of the Poisson sum
        const double want = CLH_DUAL_DB * Stack(af[c], ab[c]).back(tauB);
        const double tol = 0.05 * want;
        EXPECT_NEAR(g[c], want, 0.02 * want + tol + 1e-4)
            << "eumelanin " << eu << " tau_b " << tauB;
        EXPECT_GT(want, 0.0);
      }
    }
  }
}

TEST(Dual, WhiteFurnaceInASlab) {
  // A slab of hair between z = 0 and z = -H (fibres lie in its plane), optical depth mu per
  // unit length: from a point at depth z0 a light direction w crosses mu z0 / w_z fibres
  // upward, mu (H - z0) / -w_z downward, and finds tau(-w) behind it. A uniform white sky
  // of radiance 1 lights it from every direction.
  const double mu = 40.0, H = 0.2;
  const hb::clh_hair_material white = material(hb::clh_v3_splat(0.0f));
  double most = 0.0;
  for (double z0 : {0.0, 0.005, 0.03, 0.1}) {
    auto tau = [&](Dir w) {
      const double d = w.z > 0.0f ? z0 / w.z : (H - z0) / -w.z;
      return static_cast<float>(std::min(mu * d, 80.0));
    };
    for (int k = 0; k < 4; ++k) {
      const double a = 0.7 * k;
      const Dir t = unit(std::cos(a), std::sin(a), 0.05);
      const Dir wo = unit(0.3 * k - 0.4, 0.2, 0.9);  // looking from above the slab
      const Shaded s = prepare(white, t, wo);
      const auto full = sphereIntegral(
          [&](Dir wi) {
            const Dir back{-wi.x, -wi.y, -wi.z};
            return dual(s, wi, tau(wi), tau(back));
          },
          120, 240);
      const auto shadowed = sphereIntegral(
          [&](Dir wi) {
            return hb::clh_v3_scale(hb::clh_hair_eval_cos(&s.hv, v3(wi)), std::exp(-tau(wi)));
          },
          120, 240);
      for (int c = 0; c < 3; ++c) {
        // the single fibre's furnace error is 0.6 % (docs/hair-shading.md §4)
        EXPECT_LE(full[c], 1.01) << "depth " << z0 << " frame " << k;
        EXPECT_GE(full[c], shadowed[c] - 1e-6) << "depth " << z0 << " frame " << k;
        most = std::max(most, full[c]);
      }
      if (z0 > 0.0) {
        EXPECT_GT(full[1], shadowed[1] * 1.05) << "inside, scattering adds light";
      }
    }
  }
  EXPECT_GT(most, 0.3);
}

TEST(Dual, LightHairGainsSaturation) {
  // R / B of the light a blonde fibre sends to the eye, lit from the side through tau fibres
  const Shaded s = prepare(material(melanin(0.3f)), kT, kWo);
  const Dir wi = unit(-0.5, 0.8, 0.2);
  double last = 0.0;
  for (float tau : {0.0f, 1.0f, 3.0f, 8.0f}) {
    const hb::clh_v3 f = dual(s, wi, tau, 2.0f);
    const double ratio = f.x / std::max(f.z, 1e-12f);
    EXPECT_GT(ratio, last) << "tau " << tau;
    last = ratio;
  }
  // and the global part is what does it: with it the light at tau 3 is redder than without
  const hb::clh_v3 direct = hb::clh_v3_scale(hb::clh_hair_eval_cos(&s.hv, v3(wi)), std::exp(-3.0f));
  const hb::clh_v3 f = dual(s, wi, 3.0f, 0.0f);
  EXPECT_GT(f.x / f.z, direct.x / direct.z * 1.2);
}

TEST(Dual, FileColourIsTheFibreAlbedo) {
  // The fibre's energies at theta_o = 0 sum to the colour it was made from, within 4 % (one
  // mean Fresnel and one mean path stand for the 4 panels) for colours the fibre can reach.
  const Dir t{0.0f, 0.0f, 1.0f}, wo{1.0f, 0.0f, 0.0f};
  for (float c : {0.08f, 0.15f, 0.3f, 0.5f, 0.569f, 0.75f, 0.925f, 1.0f}) {
    const hb::clh_v3 sigma = hb::clh_hair_sigma_a_from_albedo(hb::clh_v3_splat(c), 1.55f);
    EXPECT_GE(sigma.x, 0.0f);
    hb::clh_hair_view hv;
    const hb::clh_hair_material m = material(sigma);
    hb::clh_hair_prepare_to(&hv, &m, v3(t), v3(wo));
    const float albedo = hv.mass[0].x + hv.mass[1].x + hv.mass[2].x + hv.mass[3].x;
    EXPECT_NEAR(albedo, c, 0.04f * c + 0.005f) << "colour " << c;
  }
  // darker channels absorb more
  const hb::clh_v3 s =
      hb::clh_hair_sigma_a_from_albedo(hb::clh_v3_make(1.0f, 0.925f, 0.569f), 1.55f);
  EXPECT_LT(s.x, s.y);
  EXPECT_LT(s.y, s.z);
}

}  // namespace
}  // namespace clhair
