// fit_error.cpp — see fit_error.h.
#include "fit/fit_error.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "fit/parallel.h"
#include "groom/blue_noise.h"
#include "groom/groom_data.h"
#include "groom/reference.h"

namespace clhair::fit {

namespace {

constexpr int kProbe = 17;         // points of an input strand
constexpr int kPerProbe = 8;       // candidates from each of root, middle, tip
constexpr float kWindow = 0.15f;   // part of G searched around a point's length fraction

// k nearest points of a static point set (uniform grid).
class PointGrid {
 public:
  PointGrid(std::vector<glm::vec3> pts) : pts_(std::move(pts)) {
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const glm::vec3& p : pts_) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    lo_ = lo;
    const float ext = std::max(glm::length(hi - lo), 1e-9f);
    // about 8 points per occupied cell, whether the points fill a volume, a surface or a
    // curve: the spacing is adjusted from the occupied count (surface-like: square root)
    const std::size_t n = std::max<std::size_t>(pts_.size(), 1);
    cell_ = ext / std::max(1.0f, std::cbrt(static_cast<float>(n) / 8.0f));
    for (int it = 0; it < 6; ++it) {
      cells_.clear();
      for (std::size_t i = 0; i < pts_.size(); ++i)
        cells_[key(cellOf(pts_[i]))].push_back(static_cast<std::uint32_t>(i));
      const double perCell = static_cast<double>(n) / static_cast<double>(std::max<std::size_t>(cells_.size(), 1));
      if (perCell > 4.0 && perCell < 16.0) break;
      cell_ = std::max(cell_ * static_cast<float>(std::sqrt(8.0 / perCell)), ext * 1e-6f);
      if (it == 5) {  // the last adjustment: rebuild with it
        cells_.clear();
        for (std::size_t i = 0; i < pts_.size(); ++i)
          cells_[key(cellOf(pts_[i]))].push_back(static_cast<std::uint32_t>(i));
      }
    }
  }
  // Up to k nearest indices to p.
  void nearest(const glm::vec3& p, int k, std::vector<std::pair<float, std::uint32_t>>& out) const {
    out.clear();
    const glm::ivec3 c = cellOf(p);
    for (int r = 0; r < 64; ++r) {
      if (static_cast<int>(out.size()) >= k &&
          static_cast<float>(r - 1) * cell_ > std::sqrt(out[k - 1].first))
        break;
      for (int z = -r; z <= r; ++z)
        for (int y = -r; y <= r; ++y)
          for (int x = -r; x <= r; ++x) {
            if (std::max({std::abs(x), std::abs(y), std::abs(z)}) != r) continue;
            auto it = cells_.find(key(c + glm::ivec3(x, y, z)));
            if (it == cells_.end()) continue;
            for (std::uint32_t i : it->second) {
              const glm::vec3 d = pts_[i] - p;
              out.push_back({glm::dot(d, d), i});
            }
          }
      std::sort(out.begin(), out.end());
      if (static_cast<int>(out.size()) > k) out.resize(k);
    }
  }

 private:
  glm::ivec3 cellOf(const glm::vec3& p) const { return glm::ivec3(glm::floor((p - lo_) / cell_)); }
  static std::int64_t key(const glm::ivec3& c) {
    return (static_cast<std::int64_t>(c.x & 0x1FFFFF) << 42) |
           (static_cast<std::int64_t>(c.y & 0x1FFFFF) << 21) | (c.z & 0x1FFFFF);
  }
  std::vector<glm::vec3> pts_;
  glm::vec3 lo_{0.0f};
  float cell_ = 1.0f;
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> cells_;
};

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
  parallelFor(g.count(), threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const ReferenceStrand r = referenceStrand(data, params, roots, g.bundle[i], local[i], C);
      std::copy(r.points.begin(), r.points.end(), g.data.begin() + static_cast<std::ptrdiff_t>(i * C));
    }
  }, 64);
  return g;
}

LengthStats lengthStats(std::vector<float> v) {
  LengthStats s;
  s.strands = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  double sum = 0.0;
  for (float x : v) sum += x;
  auto q = [&](double f) { return static_cast<double>(v[static_cast<std::size_t>(f * (v.size() - 1) + 0.5)]); };
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
  parallelFor(measured.size(), threads, [&](std::size_t b, std::size_t e) {
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
          const int s1 = std::min(C - 1, static_cast<int>(std::ceil((frac + kWindow) * (C - 1))));
          float d2 = std::numeric_limits<float>::max();
          for (int s = s0; s < s1; ++s) d2 = std::min(d2, pointSegment2(probe[k], q[s], q[s + 1]));
          if (s1 == s0) d2 = glm::dot(probe[k] - q[s0], probe[k] - q[s0]);
          sum += std::sqrt(d2);
        }
        best = std::min(best, sum / kProbe);
      }
      out[m] = best;
    }
  }, 32);
  return out;
}

FitDistance summarize(std::vector<float> d, float fibreWidth) {
  FitDistance s;
  s.strands = d.size();
  if (d.empty()) return s;
  double sum = 0.0;
  for (float x : d) sum += x;
  s.meanM = sum / static_cast<double>(d.size());
  const std::size_t k = std::min(d.size() - 1, static_cast<std::size_t>(0.95 * (d.size() - 1) + 0.5));
  std::nth_element(d.begin(), d.begin() + k, d.end());
  s.p95M = d[k];
  s.meanWidths = fibreWidth > 0.0f ? s.meanM / fibreWidth : 0.0;
  s.p95Widths = fibreWidth > 0.0f ? s.p95M / fibreWidth : 0.0;
  return s;
}

}  // namespace clhair::fit
