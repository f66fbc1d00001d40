// style_fit.cpp — see style_fit.h.
#include "fit/style_fit.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <glm/geometric.hpp>

#include "fit/clump_fit.h"
#include "fit/parallel.h"
#include "fit/style_residual.h"
#include "fit/style_stats.h"

namespace clhair::fit {

namespace {

constexpr float kPi = 3.14159265358979323846f;
constexpr std::size_t kSearchStrands = 1500;
constexpr std::size_t kNeighbours = 4;  // root neighbours per strand for pair statistics
constexpr float kMaxCurlTurns = 20.0f;
constexpr float kCurlStep = 0.25f;
constexpr double kCurlSignificance = 0.5;  // share of residual energy the curl must explain
constexpr float kMinCurlTurns = 1.5f;
const float kShapes[] = {0.25f, 0.5f, 0.75f, 1.0f, 1.5f, 2.0f, 3.0f, 4.0f, 6.0f};

float median(std::vector<float> v) {
  if (v.empty()) return 0.0f;
  const std::size_t k = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

float wrapAngle(float a) {
  a = std::fmod(a + kPi, 2.0f * kPi);
  if (a < 0.0f) a += 2.0f * kPi;
  return a - kPi;
}

// Per-strand outcome of the final pass.
struct StrandStyle {
  bool valid = false;
  float amp = 0, helix = 0, phase = 0, frizz = 0, rho = 1;
  glm::vec2 uv{0.0f};
  double lag[kFrizzLagCount] = {};
};

// Golden-section minimum of fn on [lo, hi].
template <class Fn>
float goldenMin(Fn&& fn, float lo, float hi, int iters) {
  const float g = 0.6180339887f;
  float a = lo, b = hi, c = b - g * (b - a), d = a + g * (b - a);
  double fc = fn(c), fd = fn(d);
  for (int i = 0; i < iters; ++i) {
    if (fc < fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - g * (b - a);
      fc = fn(c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + g * (b - a);
      fd = fn(d);
    }
  }
  return 0.5f * (a + b);
}

// Estimates from a set of strands (all, or one bundle's) and their neighbour pairs.
// `frizzCal`: the groom-wide frizz frequency and the share of frizz energy the per-strand
// fit leaves (from the whole groom; a bundle reuses it).
FittedStyle estimate(const std::vector<StrandStyle>& st, const std::vector<ClumpSamples>& clumps,
                     const std::vector<int>& strands, const std::vector<std::pair<int, int>>& pairs,
                     float f, bool curl, const FrizzLeftover& frizzCal, float frizzF) {
  FittedStyle out;
  out.curlFrequency = curl ? f : 0.0f;
  out.frizzFrequency = frizzF;
  std::vector<float> fr, rhos;
  for (int i : strands)
    if (st[i].valid) {
      fr.push_back(st[i].frizz);
      rhos.push_back(st[i].rho);
    }
  if (fr.empty()) return out;
  // length variation: w of the tips uniform in (1 - v, 1), mean 1 - v / 2
  double m = 0.0;
  for (float r : rhos) m += r;
  m /= static_cast<double>(rhos.size());
  out.lengthVariation = static_cast<float>(std::clamp(2.0 * (1.0 - m), 0.0, 0.95));
  // frizz: the median strand; strands far above it are flyaways
  const float scale = static_cast<float>(1.0 / std::sqrt(std::max(frizzCal.energy, 1e-6)));
  const float base = median(fr);
  std::vector<float> dev;
  for (float v : fr) dev.push_back(std::fabs(v - base));
  const float flyCut = std::max(3.0f * base, base + 6.0f * median(dev));
  auto flyaway = [&](int i) { return flyCut > 0.0f && st[i].frizz > flyCut; };
  std::vector<float> fly;
  for (int i : strands)
    if (st[i].valid && flyaway(i)) fly.push_back(st[i].frizz);
  out.frizzAmplitude = base * scale;
  const double share = static_cast<double>(fly.size()) / static_cast<double>(fr.size());
  if (share >= 0.002) {
    out.flyawayFraction = static_cast<float>(share);
    out.flyawayAmplitude = std::max(0.0f, median(fly) - base) * scale;
  }
  auto calm = [&](int i) { return st[i].valid && !flyaway(i); };
  if (curl) {
    std::vector<float> amps;
    for (int i : strands)
      if (calm(i)) amps.push_back(st[i].amp);
    out.curlAmplitude = median(amps);
    std::vector<float> helix;
    for (int i : strands)
      if (calm(i) && st[i].amp > 0.5f * out.curlAmplitude) helix.push_back(st[i].helix);
    out.curlHelix = median(helix);
    std::vector<float> dphi;
    for (const auto& p : pairs) {
      if (!calm(p.first) || !calm(p.second)) continue;
      const StrandStyle &a = st[p.first], &b = st[p.second];
      if (a.amp > 0.5f * out.curlAmplitude && b.amp > 0.5f * out.curlAmplitude)
        dphi.push_back(std::fabs(wrapAngle(a.phase - b.phase)));
    }
    const float med = median(dphi);
    // triangular differences of a uniform jitter J: median |d| = 2 pi J (1 - 1/sqrt 2)
    out.curlPhaseJitter = dphi.empty()  ? 0.15f
                          : med > 1.45f ? 1.0f
                                        : std::clamp(med / (2.0f * kPi * 0.29289f), 0.0f, 1.0f);
  }
  // clumping, from neighbouring strands (clump_fit.h), away from flyaways
  std::vector<int> calmStrands;
  for (int i : strands)
    if (calm(i)) calmStrands.push_back(i);
  std::vector<std::pair<int, int>> calmPairs;
  for (const auto& p : pairs)
    if (calm(p.first) && calm(p.second)) calmPairs.push_back(p);
  const ClumpEstimate c = estimateClumping(clumps, calmStrands, calmPairs);
  out.clumpStrength = c.strength;
  out.clumpShape = c.shape;
  out.clumpFrequency = c.frequency;
  return out;
}

// The frizz frequency whose simulated leftover correlation matches the measured one, and
// that leftover's energy share.
float frizzFrequency(const double* measured, int points, double rho, float f, float shape,
                     bool curl, FrizzLeftover& cal) {
  constexpr int kGrid = 48;
  double bestErr = 1e300;
  float bestF = 6.0f;
  for (int k = 0; k <= kGrid; ++k) {
    const double F = 0.5 * std::pow(80.0, static_cast<double>(k) / kGrid);  // 0.5 .. 40 per w
    const FrizzLeftover sim = frizzLeftover(F, points, rho, f, shape, curl);
    double err = 0.0;
    for (int j = 0; j < 4; ++j) err += (sim.corr[j] - measured[j]) * (sim.corr[j] - measured[j]);
    if (err < bestErr) {
      bestErr = err;
      bestF = static_cast<float>(F);
      cal = sim;
    }
  }
  return bestF;
}

// Mean distance from a circle's centre of the chords of a polygon with `perTurn` sides
// inscribed in it, over the circle's radius.
float chordShrink(int points, float turns, float lengthVariation) {
  if (!(turns > 0.0f) || points < 2) return 1.0f;
  const double perTurn = (points - 1) / (turns * (1.0 - 0.5 * lengthVariation));
  if (perTurn < 3.0) return 1.0f;
  const double half = 3.14159265358979 / perTurn;  // half the angle a chord spans
  const double h = std::cos(half), c = std::sin(half);
  // mean of sqrt(h^2 + x^2) for x uniform in [-c, c]
  const double mean = 0.5 * (std::sqrt(h * h + c * c) + h * h / c * std::asinh(c / h));
  return static_cast<float>(mean);
}

}  // namespace

StyleFitResult fitStyle(const FitStrands& s, const StrandPlacement& pl, const HairMesh& mesh,
                        const BaseCurves& base, const FittedStyle* arcCurl, int threads) {
  StyleFitResult res;
  const std::size_t n = s.count();
  const int F = static_cast<int>(mesh.faces.size());

  // 1. the shared nonlinear parameters on an even sample
  std::vector<std::size_t> sample;
  const std::size_t step = std::max<std::size_t>(1, n / kSearchStrands);
  for (std::size_t i = 0; i < n; i += step)
    if (s.length[i] > 0.0f) sample.push_back(i);
  std::vector<StrandResidual> resid(sample.size());
  parallelFor(
      sample.size(), threads,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k)
          strandResidual(s, pl, base, sample[k], arcCurl, resid[k]);
      },
      16);
  {  // the searches ignore the tenth of strands furthest from their base (flyaways)
    std::vector<std::pair<double, std::size_t>> energy0(resid.size());
    for (std::size_t k = 0; k < resid.size(); ++k) {
      double e = 0.0;
      for (int j = 0; j < resid[k].points; ++j) e += glm::dot(resid[k].r[j], resid[k].r[j]);
      energy0[k] = {e, k};
    }
    std::sort(energy0.begin(), energy0.end());
    std::vector<StrandResidual> kept;
    for (std::size_t k = 0; k < energy0.size() * 9 / 10 || (kept.empty() && k < energy0.size());
         ++k)
      kept.push_back(resid[energy0[k].second]);
    resid.swap(kept);
  }
  auto energy = [&](float f, float shape) {
    std::vector<double> part(resid.size());
    parallelFor(
        resid.size(), threads,
        [&](std::size_t b, std::size_t e) {
          for (std::size_t k = b; k < e; ++k)
            part[k] = fitStrandStyle(resid[k], f, shape, false).energy;
        },
        64);
    double sum = 0.0;
    for (double v : part) sum += v;
    return sum;
  };
  float shape = 1.0f, f = 0.0f;
  bool curl = false;
  if (arcCurl) {
    // a refinement: the curl is known to be there (or not); search near the last values
    curl = arcCurl->curlFrequency > 0.0f;
    shape = arcCurl->clumpShape > 0.0f ? arcCurl->clumpShape : 1.0f;
    if (curl)
      f = goldenMin([&](float g) { return energy(g, shape); },
                    std::max(0.01f, arcCurl->curlFrequency - 0.1f), arcCurl->curlFrequency + 0.1f,
                    8);
    shape = goldenMin([&](float x) { return energy(f, x); }, shape / 1.5f, shape * 1.5f, 8);
  } else {
    std::vector<double> curve;
    double best = 1e300;
    for (float g = kCurlStep; g <= kMaxCurlTurns + 1e-3f; g += kCurlStep) {
      const double e = energy(g, shape);
      curve.push_back(e);
      if (e < best) {
        best = e;
        f = g;
      }
    }
    std::vector<double> sorted = curve;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double typical = sorted[sorted.size() / 2];
    // a curl explains most of the residual at one frequency and turns at least most of a
    // turn; below that a sinusoid only fits frizz or bending
    curl = typical > 0.0 && (typical - best) > kCurlSignificance * typical && f >= kMinCurlTurns;
    if (curl)
      f = goldenMin([&](float g) { return energy(g, shape); }, std::max(0.01f, f - kCurlStep),
                    f + kCurlStep, 14);
    else
      f = 0.0f;
    // clump shape with that frequency
    double bestShape = 1e300;
    int bi = 3;
    for (int k = 0; k < static_cast<int>(std::size(kShapes)); ++k) {
      const double e = energy(f, kShapes[k]);
      if (e < bestShape) {
        bestShape = e;
        bi = k;
      }
    }
    const float lo = kShapes[std::max(bi - 1, 0)];
    const float hi = kShapes[std::min(bi + 1, static_cast<int>(std::size(kShapes)) - 1)];
    shape = goldenMin([&](float x) { return energy(f, x); }, lo, hi, 10);
  }

  // 2. every strand with those fixed
  std::vector<StrandStyle> st(n);
  std::vector<ClumpSamples> clumps(n);
  const double noise2 = 2.0 * valueNoiseVariance();
  parallelFor(
      n, threads,
      [&](std::size_t b, std::size_t e) {
        auto r = std::make_unique<StrandResidual>();
        for (std::size_t i = b; i < e; ++i) {
          if (!(s.length[i] > 0.0f)) continue;
          strandResidual(s, pl, base, i, arcCurl, *r);
          if (r->points < 4) continue;
          const StrandFit fit = fitStrandStyle(*r, f, shape, true);
          StrandStyle& o = st[i];
          o.valid = true;
          const float a = fit.a, bb = fit.b;
          o.amp = std::sqrt(a * a + bb * bb);
          o.helix = o.amp > 0.0f ? (fit.d * a - fit.c * bb) / (o.amp * o.amp) : 0.0f;
          o.phase = std::atan2(-bb, a);
          o.frizz = fit.frizzW4 > 0.0
                        ? static_cast<float>(std::sqrt(fit.frizzEnergy / (fit.frizzW4 * noise2)))
                        : 0.0f;
          for (int j = 0; j < kFrizzLagCount; ++j) o.lag[j] = fit.lag[j];
          o.rho = r->rho;
          const auto& face = mesh.faces[pl.face[i]];
          const glm::vec2 t = pl.st[i];
          o.uv = (1 - t.x) * (1 - t.y) * mesh.uv[face[0]] + t.x * (1 - t.y) * mesh.uv[face[1]] +
                 t.x * t.y * mesh.uv[face[2]] + (1 - t.x) * t.y * mesh.uv[face[3]];
          clumpSamples(*r, fit, curl ? f : 0.0f, o.uv, clumps[i]);
        }
      },
      64);

  // 3. root neighbours within each bundle
  std::vector<std::vector<int>> members(F);
  for (std::size_t i = 0; i < n; ++i) members[pl.face[i]].push_back(static_cast<int>(i));
  std::vector<std::vector<std::pair<int, int>>> pairs(F);
  parallelFor(
      static_cast<std::size_t>(F), threads,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t fi = b; fi < e; ++fi) {
          const auto& m = members[fi];
          std::vector<std::pair<float, int>> near;
          for (std::size_t x = 0; x < m.size(); ++x) {
            near.clear();
            for (std::size_t y = 0; y < m.size(); ++y) {
              const glm::vec3 d = s.root(m[x]) - s.root(m[y]);
              const float d2 = glm::dot(d, d);
              if (x != y && d2 > 0.0f) near.push_back({d2, m[y]});
            }
            const std::size_t k = std::min<std::size_t>(kNeighbours, near.size());
            std::partial_sort(near.begin(), near.begin() + k, near.end());
            for (std::size_t j = 0; j < k; ++j)
              if (m[x] < near[j].second) pairs[fi].push_back({m[x], near[j].second});
          }
        }
      },
      4);
  std::vector<int> all;
  std::vector<std::pair<int, int>> allPairs;
  for (int fi = 0; fi < F; ++fi) {
    all.insert(all.end(), members[fi].begin(), members[fi].end());
    allPairs.insert(allPairs.end(), pairs[fi].begin(), pairs[fi].end());
  }
  // frizz frequency and calibration from the leftovers' correlation (all strands but the
  // tenth furthest out, so flyaways do not dominate), matched by simulation
  FrizzLeftover cal;
  float frizzF = 6.0f;
  {
    std::vector<std::pair<float, int>> byFrizz;
    double rho = 0.0;
    for (std::size_t i = 0; i < n; ++i)
      if (st[i].valid) {
        byFrizz.push_back({st[i].frizz, static_cast<int>(i)});
        rho += st[i].rho;
      }
    if (!byFrizz.empty()) {
      rho /= static_cast<double>(byFrizz.size());
      std::sort(byFrizz.begin(), byFrizz.end());
      double lag[kFrizzLagCount] = {};
      for (std::size_t k = 0; k < byFrizz.size() * 9 / 10; ++k)
        for (int j = 0; j < kFrizzLagCount; ++j) lag[j] += st[byFrizz[k].second].lag[j];
      if (lag[0] > 0.0) {
        double corr[4];
        for (int j = 0; j < 4; ++j) corr[j] = lag[j + 1] / lag[0];
        frizzF = frizzFrequency(corr, s.samples - 1, rho, f, shape, curl, cal);
      }
    }
  }
  res.global = estimate(st, clumps, all, allPairs, f, curl, cal, frizzF);
  // The input is a polyline: between its points a curl is cut short by the chords, so the
  // amplitude seen along it is the mean distance of a chord from the curl's axis. The
  // generator draws the same number of points, so the amplitude behind the input's is what
  // the mesh needs: divided by that mean for the input's segments per turn.
  const float shrink = chordShrink(s.medianPoints, f, res.global.lengthVariation);
  res.global.curlAmplitude /= shrink;
  res.perBundle.resize(F);
  res.bundlePhase.assign(F, 0.0f);
  for (int fi = 0; fi < F; ++fi) {
    res.perBundle[fi] = estimate(st, clumps, members[fi], pairs[fi], f, curl, cal, frizzF);
    res.perBundle[fi].curlAmplitude /= shrink;
    double cx = 0, cy = 0;
    for (int i : members[fi])
      if (st[i].valid) {
        cx += std::cos(st[i].phase);
        cy += std::sin(st[i].phase);
      }
    res.bundlePhase[fi] = static_cast<float>(std::atan2(cy, cx));
  }
  if (curl && res.global.curlHelix < -0.2f)
    res.notes.push_back("the curls turn left-handed about the hair (helix " +
                        std::to_string(res.global.curlHelix) +
                        "); the generator's helices turn one way only, so they are fitted as a "
                        "planar wave");
  return res;
}

}  // namespace clhair::fit
