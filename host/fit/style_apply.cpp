// style_apply.cpp — what the fitted styling does to the fit (style_fit.h): the fitted curl
// taken out of the strands (the layers then hold the base curves alone), and the fitted
// values clamped into the mesh's StyleParams.
#include <algorithm>
#include <cmath>
#include <memory>

#include "fit/fit_strands.h"
#include "fit/parallel.h"
#include "fit/style_fit.h"
#include "fit/style_residual.h"
#include "fit/style_stats.h"

namespace clhair::fit {

FitStrands removeCurl(const FitStrands& s, const StrandPlacement& pl, const BaseCurves& base,
                      const FittedStyle& fitted, const FittedStyle* arcCurl, int threads) {
  FitStrands out = s;
  if (!(fitted.curlAmplitude > 0.0f && fitted.curlFrequency > 0.0f)) return out;
  const float f = fitted.curlFrequency;
  parallelFor(
      s.count(), threads,
      [&](std::size_t b, std::size_t e) {
        auto r = std::make_unique<StrandResidual>();
        for (std::size_t i = b; i < e; ++i) {
          if (!(s.length[i] > 0.0f)) continue;
          strandResidual(s, pl, base, i, arcCurl, *r);
          if (r->points < 4) continue;
          const StrandFit fit = fitStrandStyle(*r, f, fitted.clumpShape, false);
          glm::vec3* p = out.points.data() + i * s.samples;
          for (int k = 0; k < r->points; ++k) {
            const float th = 6.28318530718f * f * r->w[k];
            const float cs = std::cos(th) * r->ramp[k], sn = std::sin(th) * r->ramp[k];
            p[k + 1] -= (fit.a * cs + fit.b * sn) * r->e1[k] + (fit.c * cs + fit.d * sn) * r->e2[k];
          }
        }
      },
      64);
  resampleInPlace(out, threads);
  return out;
}

void applyStyle(const FittedStyle& f, StyleParams& s) {
  s.curlAmplitude = std::max(0.0f, f.curlAmplitude);
  s.curlFrequency = std::clamp(f.curlFrequency, 0.0f, 1000.0f);
  s.curlHelix = std::clamp(f.curlHelix, 0.0f, 1.0f);
  s.curlPhaseJitter = std::clamp(f.curlPhaseJitter, 0.0f, 1.0f);
  s.clumpStrength = std::clamp(f.clumpStrength, 0.0f, 1.0f);
  s.clumpFrequency = f.clumpFrequency > 0.0f ? std::min(f.clumpFrequency, 10000.0f) : 10.0f;
  s.clumpShape = std::clamp(f.clumpShape, 0.01f, 16.0f);
  s.frizzAmplitude = std::max(0.0f, f.frizzAmplitude);
  s.frizzFrequency = std::clamp(f.frizzFrequency, 0.0f, 1000.0f);
  s.flyawayFraction = std::clamp(f.flyawayFraction, 0.0f, 1.0f);
  s.flyawayAmplitude = std::max(0.0f, f.flyawayAmplitude);
  s.lengthVariation = std::clamp(f.lengthVariation, 0.0f, 0.95f);
}

}  // namespace clhair::fit
