// fit_error.cpp — see fit_error.h.
#include "fit/fit_error.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "fit/parallel.h"
#include "fit/point_grid.h"
#include "groom/blue_noise.h"
#include "groom/groom_data.h"
#include "groom/reference.h"

namespace clhair::fit {

namespace {

constexpr int kProbe = 17;        // points of an input strand
constexpr int kPerProbe = 8;      // candidates from each of root, middle, tip
constexpr float kWindow = 0.15f;  // part of G searched around a point's length fraction

float pointSegment2(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 ab = b - a;
  const float l2 = glm::dot(ab, ab);
  const float t = l2 > 0.0f ? std::clamp(glm::dot(p - a, ab) / l2, 0.0f, 1.0f) : 0.0f;
  const glm::vec3 d = a + t * ab - p;
  return glm::dot(d, d);
}

}  // namespace

GeneratedStrands generateStrandsCpu(const HairMesh& mesh, int threads) {
  GroomData data = prepareGroom(mesh);
  gpu::ClhGroomGpu params{};
  fillGroomParams(mesh, data, params);
  std::uint32_t rootSize = 1024;
  while (rootSize < data.maxBundleStrands) rootSize <<= 1;
  const RootSets roots = makeRootSets(rootSize);
  params.root_set_size = roots.size();
  const std::uint32_t C = fullDetailControlPoints(mesh);
  GeneratedStrands g;
  g.points = static_cast<int>(C);
  g.bundle.resize(data.totalStrands);
  std::vector<std::uint32_t> local(data.totalStrands);
  for (std::size_t b = 0; b < data.bundles.size(); ++b)
    for (std::uint32_t j = 0; j < data.bundles[b].strand_count; ++j) {
      g.bundle[data.bundles[b].first_strand + j] = static_cast<std::uint32_t>(b);
      local[data.bundles[b].first_strand + j] = j;
    }
  g.data.resize(static_cast<std::size_t>(data.totalStrands) * C);
  parallelFor(
      g.count(), threads,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          const ReferenceStrand r = referenceStrand(data, params, roots, g.bundle[i], local[i], C);
          std::copy(r.points.begin(), r.points.end(),
                    g.data.begin() + static_cast<std::ptrdiff_t>(i * C));
        }
      },
      64);
  return g;
}

LengthStats lengthStats(std::vector<float> v) {
  LengthStats s;
  s.strands = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  double sum = 0.0;
  for (float x : v) sum += x;
  auto q = [&](double f) {
    return static_cast<double>(v[static_cast<std::size_t>(f * (v.size() - 1) + 0.5)]);
  };
  s.mean = sum / static_cast<double>(v.size());
  s.min = v.front();
  s.max = v.back();
  s.p05 = q(0.05);
  s.median = q(0.5);
  s.p95 = q(0.95);
  return s;
}

std::vector<float> generatedLengths(const GeneratedStrands& g) {
  std::vector<float> out(g.count());
  for (std::size_t i = 0; i < g.count(); ++i) {
    const glm::vec3* p = g.data.data() + i * g.points;
    double l = 0.0;
    for (int k = 1; k < g.points; ++k) l += glm::length(p[k] - p[k - 1]);
    out[i] = static_cast<float>(l);
  }
  return out;
}

std::vector<float> strandDistances(const FitStrands& in, const std::vector<std::size_t>& measured,
                                   const GeneratedStrands& g, int threads) {
  const int C = g.points;
  const std::size_t G = g.count();
  std::vector<float> out(measured.size(), 0.0f);
  if (G == 0) return out;
  std::vector<glm::vec3> roots(G), mids(G), tips(G);
  for (std::size_t i = 0; i < G; ++i) {
    roots[i] = g.data[i * C];
    mids[i] = g.data[i * C + C / 2];
    tips[i] = g.data[i * C + C - 1];
  }
  const PointGrid gr(std::move(roots)), gm(std::move(mids)), gt(std::move(tips));
  parallelFor(
      measured.size(), threads,
      [&](std::size_t b, std::size_t e) {
        std::vector<std::pair<float, std::uint32_t>> near;
        std::vector<std::uint32_t> cand;
        glm::vec3 probe[kProbe];
        for (std::size_t m = b; m < e; ++m) {
          const std::size_t i = measured[m];
          for (int k = 0; k < kProbe; ++k)
            probe[k] = in.atFraction(i, static_cast<float>(k) / static_cast<float>(kProbe - 1));
          cand.clear();
          gr.nearest(probe[0], kPerProbe, near);
          for (const auto& x : near) cand.push_back(x.second);
          gm.nearest(probe[kProbe / 2], kPerProbe, near);
          for (const auto& x : near) cand.push_back(x.second);
          gt.nearest(probe[kProbe - 1], kPerProbe, near);
          for (const auto& x : near) cand.push_back(x.second);
          std::sort(cand.begin(), cand.end());
          cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
          float best = std::numeric_limits<float>::max();
          for (std::uint32_t c : cand) {
            const glm::vec3* q = g.data.data() + static_cast<std::size_t>(c) * C;
            float sum = 0.0f;
            for (int k = 0; k < kProbe && sum < best * kProbe; ++k) {
              const float frac = static_cast<float>(k) / static_cast<float>(kProbe - 1);
              const int s0 = std::max(0, static_cast<int>((frac - kWindow) * (C - 1)));
              const int s1 =
                  std::min(C - 1, static_cast<int>(std::ceil((frac + kWindow) * (C - 1))));
              float d2 = std::numeric_limits<float>::max();
              for (int s = s0; s < s1; ++s)
                d2 = std::min(d2, pointSegment2(probe[k], q[s], q[s + 1]));
              if (s1 == s0) d2 = glm::dot(probe[k] - q[s0], probe[k] - q[s0]);
              sum += std::sqrt(d2);
            }
            best = std::min(best, sum / kProbe);
          }
          out[m] = best;
        }
      },
      32);
  return out;
}

FitDistance summarize(std::vector<float> d, float fibreWidth) {
  FitDistance s;
  s.strands = d.size();
  if (d.empty()) return s;
  double sum = 0.0;
  for (float x : d) sum += x;
  s.meanM = sum / static_cast<double>(d.size());
  const std::size_t k =
      std::min(d.size() - 1, static_cast<std::size_t>(0.95 * (d.size() - 1) + 0.5));
  std::nth_element(d.begin(), d.begin() + k, d.end());
  s.p95M = d[k];
  s.meanWidths = fibreWidth > 0.0f ? s.meanM / fibreWidth : 0.0;
  s.p95Widths = fibreWidth > 0.0f ? s.p95M / fibreWidth : 0.0;
  return s;
}

}  // namespace clhair::fit
