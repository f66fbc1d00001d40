// fit_strands.cpp — see fit_strands.h.
#include "fit/fit_strands.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "clhair/error.h"
#include "fit/parallel.h"

namespace clhair::fit {

glm::vec3 FitStrands::atArc(std::size_t i, float arc) const {
  const glm::vec3* p = strand(i);
  const float len = length[i];
  if (!(len > 0.0f) || arc <= 0.0f) return p[0];
  if (arc > len) {  // past the tip: straight on along the last segment
    const glm::vec3 d = p[samples - 1] - p[samples - 2];
    const float l = glm::length(d);
    return l > 0.0f ? p[samples - 1] + d * ((arc - len) / l) : p[samples - 1];
  }
  const float x = std::min(arc / len, 1.0f) * static_cast<float>(samples - 1);
  const int k = std::min(static_cast<int>(x), samples - 2);
  const float t = x - static_cast<float>(k);
  return p[k] + (p[k + 1] - p[k]) * t;
}

glm::vec3 FitStrands::atFraction(std::size_t i, float fraction) const {
  return atArc(i, fraction * length[i]);
}

namespace {

// Resamples one polyline of n points to m points at equal arc length.
void resample(const glm::vec3* in, std::size_t n, int m, glm::vec3* out, float& lengthOut) {
  double total = 0.0;
  for (std::size_t k = 1; k < n; ++k) total += glm::length(in[k] - in[k - 1]);
  lengthOut = static_cast<float>(total);
  if (!(total > 0.0)) {
    for (int j = 0; j < m; ++j) out[j] = in[0];
    return;
  }
  std::size_t seg = 1;
  double before = 0.0;  // arc length at in[seg - 1]
  double segLen = glm::length(in[1] - in[0]);
  for (int j = 0; j < m; ++j) {
    const double target = total * static_cast<double>(j) / static_cast<double>(m - 1);
    while (seg + 1 < n && before + segLen < target) {
      before += segLen;
      ++seg;
      segLen = glm::length(in[seg] - in[seg - 1]);
    }
    const double t = segLen > 0.0 ? std::clamp((target - before) / segLen, 0.0, 1.0) : 0.0;
    out[j] = in[seg - 1] + (in[seg] - in[seg - 1]) * static_cast<float>(t);
  }
  out[m - 1] = in[n - 1];
}

}  // namespace

FitStrands prepareFitStrands(const StrandGroom& groom, int samples, float fibreWidth, int threads) {
  const std::string where = groom.name.empty() ? std::string("strands") : groom.name;
  validateStrandGroom(groom, where);
  FitStrands s;
  s.samples = samples;
  const std::size_t n = groom.pointCounts.size();
  std::vector<std::size_t> first(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) first[i + 1] = first[i] + groom.pointCounts[i];
  s.points.resize(n * static_cast<std::size_t>(samples));
  s.length.resize(n);
  parallelFor(n, threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      resample(groom.points.data() + first[i], groom.pointCounts[i], samples,
               s.points.data() + i * samples, s.length[i]);
  });
  std::vector<float> lengths = s.length;
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  s.medianLength = lengths[lengths.size() / 2];
  std::vector<std::uint32_t> counts = groom.pointCounts;
  std::nth_element(counts.begin(), counts.begin() + counts.size() / 2, counts.end());
  s.medianPoints = static_cast<int>(counts[counts.size() / 2]);
  const float longest = *std::max_element(s.length.begin(), s.length.end());
  if (!(longest > 0.0f))
    throw Error(where + ": every strand has zero length (all its points coincide); " +
                "nothing to fit a hair mesh to");
  if (s.medianLength <= 0.0) s.medianLength = longest;
  if (fibreWidth > 0.0f) {
    s.fibreWidth = fibreWidth;
  } else if (!groom.thickness.empty()) {
    std::vector<float> t = groom.thickness;
    std::nth_element(t.begin(), t.begin() + t.size() / 2, t.end());
    s.fibreWidth = t[t.size() / 2] > 0.0f ? t[t.size() / 2] : groom.appearance.strandWidth;
  } else {
    s.fibreWidth = groom.appearance.strandWidth;
  }
  return s;
}

void resampleInPlace(FitStrands& s, int threads) {
  parallelFor(s.count(), threads, [&](std::size_t b, std::size_t e) {
    std::vector<glm::vec3> copy(s.samples);
    for (std::size_t i = b; i < e; ++i) {
      glm::vec3* p = s.points.data() + i * s.samples;
      std::copy(p, p + s.samples, copy.begin());
      resample(copy.data(), copy.size(), s.samples, p, s.length[i]);
    }
  });
}

}  // namespace clhair::fit
