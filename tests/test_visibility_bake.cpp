// test_visibility_bake.cpp — the Embree bake of baked spherical visibility (Kulikov 2025,
// "precomputed self-shadowing"; host/groom/visibility_bake.cpp).
//
//  VisibilityBake.*    an unoccluded strand sees no events anywhere; a strand beside a dense
//                      slab sees events toward the slab and none away from it; the bake
//                      matches a brute-force double-precision count on a small groom; its
//                      estimator against a high-count reference and its default cap
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#include <glm/glm.hpp>

#include "clhair/visibility.h"
#include "clhair/visibility_sh.h"
#include "groom/visibility_bake.h"
#include "test_util.h"

namespace clhair {
namespace {

constexpr double kPi = 3.14159265358979323846;

// n strands along +y from y = 0 to 0.1 with 9 points each, at (x, z), root uv given.
void addStrand(StrandSet& s, float x, float z, float u, float v) {
  const std::uint32_t n = 9;
  s.pointCounts.push_back(n);
  s.uv.insert(s.uv.end(), {u, v});
  for (std::uint32_t k = 0; k < n; ++k) {
    const float t = static_cast<float>(k) / (n - 1);
    s.points.insert(s.points.end(), {x, 0.1f * t, z});
    s.tangents.insert(s.tangents.end(), {0.0f, 1.0f, 0.0f});
    s.w.push_back(t);
    s.ao.push_back(1.0f);
  }
}

// n points of a wavy strand 12 mm tall rooted at (x, z), its wobble's phase ph.
void addWavyPoints(StrandSet& s, float x, float z, float ph, std::uint32_t n) {
  for (std::uint32_t k = 0; k < n; ++k) {
    const float t = static_cast<float>(k) / (n - 1);
    s.points.insert(s.points.end(), {x + 0.001f * std::sin(ph + 6.0f * t), 0.012f * t,
                                     z + 0.001f * std::cos(ph + 5.0f * t)});
    s.tangents.insert(s.tangents.end(), {0.0f, 1.0f, 0.0f});
    s.w.push_back(t);
    s.ao.push_back(1.0f);
  }
}

// A 2 m square of two triangles at height y: the head of the small test grooms.
struct Floor {
  explicit Floor(float y)
      : tri{{-1.0f, y, -1.0f}, {1.0f, y, -1.0f}, {1.0f, y, 1.0f}, {-1.0f, y, 1.0f}} {}
  std::vector<glm::vec3> tri;
  std::vector<std::uint32_t> idx = {0, 1, 2, 0, 2, 3};
};

float eventsToward(const VisibilityBake& b, float u, float v, float w, float x, float y, float z) {
  const std::uint32_t cell = gpu::clh_vis_cell(
      gpu::clh_unorm_bits(u, 6u), gpu::clh_unorm_bits(v, 6u), gpu::clh_unorm_bits(w, 6u));
  const float* c = &b.sh[std::size_t(cell) * 4];
  return gpu::clh_vis_events(c[0], c[1], c[2], c[3], x, y, z);
}

TEST(VisibilityBake, UnoccludedStrandSeesNoEvents) {
  // One strand alone: every ray misses, every cell holds the miss bias (c0 = -5 * 2 sqrt(pi)),
  // so the clamped SH is 0 and the visibility 1 in every direction.
  StrandSet s;
  addStrand(s, 0.0f, 0.0f, 0.5f, 0.5f);
  VisibilityBakeOptions o;
  o.raysPerPoint = 64;
  const VisibilityBake b = bakeVisibility(s, 1e-4f, {}, {}, 1, o);
  std::mt19937 rng(3);
  std::normal_distribution<float> g;
  int cells = 0;
  for (int k = 0; k < 9; ++k) {
    const float w = k / 8.0f;
    const std::uint32_t cell = gpu::clh_vis_cell(32, 32, gpu::clh_unorm_bits(w, 6u));
    EXPECT_NEAR(b.sh[4 * cell], -5.0 * 2.0 * std::sqrt(kPi), 1e-3);
    ++cells;
    for (int r = 0; r < 200; ++r) {
      float d[3] = {g(rng), g(rng), g(rng)};
      const float l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      EXPECT_EQ(eventsToward(b, 0.5f, 0.5f, w, d[0] / l, d[1] / l, d[2] / l), 0.0f);
    }
  }
  EXPECT_EQ(cells, 9);
}

TEST(VisibilityBake, SlabDarkensItsSide) {
  // A probe strand at x = 0 beside a dense slab of strands filling x in [1, 11] mm: its
  // mid-length cells see events toward +x (into the slab) and none toward -x; a sphere
  // (the head, as triangles) below the probe adds events downward.
  StrandSet s;
  addStrand(s, 0.0f, 0.0f, 0.1f, 0.1f);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> j(-0.2f, 0.2f);
  int i = 0;
  for (int a = 0; a < 20; ++a)
    for (int c = 0; c < 30; ++c, ++i)
      addStrand(s, 0.001f + 0.0005f * (a + j(rng)), -0.0075f + 0.0005f * (c + j(rng)),
                0.5f + 0.4f * a / 20.0f, 0.5f + 0.4f * c / 30.0f);
  VisibilityBakeOptions o;
  o.raysPerPoint = 128;
  o.pointsPerCell = 1;
  const VisibilityBake b = bakeVisibility(s, 1e-4f, {}, {}, 601, o);
  for (float w : {0.375f, 0.5f, 0.625f}) {
    const float into = eventsToward(b, 0.1f, 0.1f, w, 1.0f, 0.0f, 0.0f);
    const float away = eventsToward(b, 0.1f, 0.1f, w, -1.0f, 0.0f, 0.0f);
    EXPECT_GT(into, 1.0f) << "w " << w;
    EXPECT_EQ(away, 0.0f) << "w " << w;
  }
}

// The brute-force count the bake's Embree tracing must reproduce: squared distance between
// the ray piece o + t d, t in [0, T], and the segment [a, b] (closest points of two
// segments, clamped), in double precision.
double raySegmentDistance2(const double o[3], const double d[3], double T, const double a[3],
                           const double b[3]) {
  double u[3], v[3], w0[3];
  for (int k = 0; k < 3; ++k) {
    u[k] = d[k] * T;
    v[k] = b[k] - a[k];
    w0[k] = o[k] - a[k];
  }
  auto dot = [](const double* x, const double* y) {
    return x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
  };
  const double A = dot(u, u), B = dot(u, v), C = dot(v, v), D = dot(u, w0), E = dot(v, w0);
  const double den = A * C - B * B;
  double sN, sD = den, tN, tD = den;
  if (den < 1e-18) {
    sN = 0.0, sD = 1.0, tN = E, tD = C;
  } else {
    sN = B * E - C * D, tN = A * E - B * D;
    if (sN < 0.0) {
      sN = 0.0, tN = E, tD = C;
    } else if (sN > sD) {
      sN = sD, tN = E + B, tD = C;
    }
  }
  if (tN < 0.0) {
    tN = 0.0;
    sN = std::clamp(-D, 0.0, A), sD = A;
  } else if (tN > tD) {
    tN = tD;
    sN = std::clamp(-D + B, 0.0, A), sD = A;
  }
  const double sc = sD > 0.0 ? sN / sD : 0.0, tc = tD > 0.0 ? tN / tD : 0.0;
  double q[3];
  for (int k = 0; k < 3; ++k) q[k] = w0[k] + sc * u[k] - tc * v[k];
  return dot(q, q);
}

TEST(VisibilityBake, MatchesBruteForceCount) {
  // 96 wavy strands of 9 points in a 6 mm square, fibre radius 0.4 mm (counts up to the
  // cap of 20), a floor of two triangles just below them as the head. Every point has its
  // own cell, so with one point per cell every point is traced, with the bake's directions
  // (sphereDirections seeded by the point index). Per ray the reference counts, in double
  // precision, the distinct other strands whose capsule the ray meets before the floor,
  // adds 5 for the floor, clamps at 20 and biases misses to -5; the L1 projection of those
  // values is the cell's expected SH. Embree's float curve intersection differs from it for
  // rays that graze a capsule: measured 785 of 864 cells exact and the worst cell off by
  // 1.82 times one ray's one-event change (the bake before the packet tracing and the
  // Morton layout gave exactly the same numbers).
  StrandSet s;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> pos(-0.003f, 0.003f), phase(0.0f, 6.2832f);
  const std::uint32_t strands = 96, n = 9;
  for (std::uint32_t st = 0; st < strands; ++st) {
    const float x = pos(rng), z = pos(rng), ph = phase(rng);
    s.pointCounts.push_back(n);
    s.uv.insert(s.uv.end(),
                {static_cast<float>(st % 12) / 11.0f, static_cast<float>(st / 12) / 7.0f});
    addWavyPoints(s, x, z, ph, n);
  }
  const float radius = 4e-4f, floorY = -5e-4f;
  const Floor floor(floorY);
  const std::vector<glm::vec3>& tri = floor.tri;
  const std::vector<std::uint32_t>& idx = floor.idx;
  VisibilityBakeOptions o;
  o.raysPerPoint = 32;
  o.pointsPerCell = 1;
  o.maxEvents = 20;
  const VisibilityBake b = bakeVisibility(s, radius, tri, idx, strands, o);

  const std::uint32_t R = o.raysPerPoint;
  const auto cap = static_cast<float>(o.maxEvents);
  std::vector<float> dirs(3 * R), values(R);
  int cells = 0, exact = 0, saturated = 0, headRays = 0;
  double worst = 0.0;
  for (std::uint32_t st = 0; st < strands; ++st)
    for (std::uint32_t k = 0; k < n; ++k) {
      const std::uint32_t i = st * n + k;
      sphereDirections(R, i, dirs.data());
      const double org[3] = {s.points[3 * i], s.points[3 * i + 1], s.points[3 * i + 2]};
      for (std::uint32_t r = 0; r < R; ++r) {
        const double d[3] = {dirs[3 * r], dirs[3 * r + 1], dirs[3 * r + 2]};
        const double tFloor = d[1] < 0.0 ? (floorY - org[1]) / d[1] : 1e30;
        const bool head =
            std::fabs(org[0] + tFloor * d[0]) < 1.0 && std::fabs(org[2] + tFloor * d[2]) < 1.0;
        const double T = head ? tFloor : 10.0;
        int count = 0;
        for (std::uint32_t other = 0; other < strands; ++other) {
          if (other == st) continue;
          for (std::uint32_t q = 0; q + 1 < n; ++q) {
            const std::size_t p = std::size_t(other) * n + q;
            const double a[3] = {s.points[3 * p], s.points[3 * p + 1], s.points[3 * p + 2]};
            const double c[3] = {s.points[3 * p + 3], s.points[3 * p + 4], s.points[3 * p + 5]};
            if (raySegmentDistance2(org, d, T, a, c) <= double(radius) * radius) {
              ++count;
              break;
            }
          }
        }
        float e = std::min(static_cast<float>(count) + (head ? 5.0f : 0.0f), cap);
        saturated += e >= cap;
        headRays += head;
        values[r] = e > 0.0f ? e : -CLH_HAIR_MAX_SCATTER_EVENTS;
      }
      float ref[4];
      projectL1(dirs.data(), values.data(), R, ref);
      const std::uint32_t cell = gpu::clh_vis_cell(gpu::clh_unorm_bits(s.uv[2 * st], 6u),
                                                   gpu::clh_unorm_bits(s.uv[2 * st + 1], 6u),
                                                   gpu::clh_unorm_bits(s.w[i], 6u));
      double diff = 0.0;
      for (int q = 0; q < 4; ++q)
        diff = std::max(diff, double(std::fabs(b.sh[std::size_t(cell) * 4 + q] - ref[q])));
      worst = std::max(worst, diff);
      ++cells;
      exact += diff <= 1e-4;
    }
  // one ray's value changing by one event moves a coefficient by at most 4 pi / 32 * 0.49
  const double oneEvent = 4.0 * kPi / R * 0.4886;
  std::printf(
      "brute force: %d of %d cells match, worst coefficient error %.4f (%.2f events of "
      "one ray); %d of %d rays saturated, %d toward the floor\n",
      exact, cells, worst, worst / oneEvent, saturated, cells * int(R), headRays);
  EXPECT_EQ(cells, int(strands * n));
  EXPECT_GE(exact, cells * 85 / 100);
  EXPECT_LE(worst, 2.5 * oneEvent);
  EXPECT_GT(saturated, cells * int(R) / 50);  // the cap is exercised
}

// A small dense groom whose cells each hold 8 points: 200 wavy strands of 17 points in a
// 6 mm square, fibre radius 0.15 mm, a floor below as the head; strands take their root uv
// from a 5 x 5 grid of columns, 8 strands each, so every (u, v, w) cell averages 8 strands.
StrandSet denseCellsGroom() {
  StrandSet s;
  std::mt19937 rng(29);
  std::uniform_real_distribution<float> pos(-0.003f, 0.003f), phase(0.0f, 6.2832f);
  const std::uint32_t n = 17;
  for (std::uint32_t st = 0; st < 200; ++st) {
    const float x = pos(rng), z = pos(rng), ph = phase(rng);
    const std::uint32_t col = st % 25;
    s.pointCounts.push_back(n);
    s.uv.insert(s.uv.end(), {0.1f + 0.2f * static_cast<float>(col % 5),
                             0.1f + 0.2f * static_cast<float>(col / 5)});
    addWavyPoints(s, x, z, ph, n);
  }
  return s;
}

TEST(VisibilityBake, EstimatorErrorAgainstHighCountReference) {
  // The estimator against a high-count reference (256 rays for each of the 8 points of every
  // cell), in the mean absolute SH coefficient over the 425 cells holding points: the
  // defaults (16 rays, 4 points per cell, PerPoint directions) and PerCell directions at the
  // same counts must both be closer than a deliberately worse estimator, the defaults with a
  // quarter of the rays (4 per point). With one point per cell PerCell gives that point the
  // same directions as PerPoint, so the tables are identical.
  const StrandSet s = denseCellsGroom();
  const Floor floor(-5e-4f);
  const std::vector<glm::vec3>& tri = floor.tri;
  const std::vector<std::uint32_t>& idx = floor.idx;
  using D = VisibilityBakeOptions::Directions;
  auto bake = [&](std::uint32_t rays, std::uint32_t perCell, D d) {
    VisibilityBakeOptions o;
    o.raysPerPoint = rays;
    o.pointsPerCell = perCell;
    o.directions = d;
    VisibilityBakeStats st;
    VisibilityBake b = bakeVisibility(s, 1.5e-4f, tri, idx, 200, o, &st);
    EXPECT_EQ(st.cells, 25u * 17u);
    return b;
  };
  const VisibilityBakeOptions defaults;
  ASSERT_EQ(defaults.directions, D::PerPoint);
  const VisibilityBake ref = bake(256, 8, D::PerPoint);
  std::vector<char> baked(CLH_VIS_CELLS, 0);  // the cells holding points (not interpolated)
  for (std::size_t st = 0, i = 0; st < s.pointCounts.size(); ++st)
    for (std::uint32_t k = 0; k < s.pointCounts[st]; ++k, ++i)
      baked[gpu::clh_vis_cell(gpu::clh_unorm_bits(s.uv[2 * st], 6u),
                              gpu::clh_unorm_bits(s.uv[2 * st + 1], 6u),
                              gpu::clh_unorm_bits(s.w[i], 6u))] = 1;
  auto error = [&](const VisibilityBake& b) {
    double sum = 0.0;
    int n = 0;
    for (std::size_t i = 0; i < ref.sh.size(); ++i)
      if (baked[i / 4]) {
        sum += std::fabs(b.sh[i] - ref.sh[i]);
        ++n;
      }
    EXPECT_EQ(n, 25 * 17 * 4);
    return sum / std::max(n, 1);
  };
  const double perPoint = error(bake(defaults.raysPerPoint, defaults.pointsPerCell, D::PerPoint));
  const double perCell = error(bake(defaults.raysPerPoint, defaults.pointsPerCell, D::PerCell));
  const double worse = error(bake(defaults.raysPerPoint / 4, defaults.pointsPerCell, D::PerPoint));
  std::printf("mean |SH - reference|: defaults %.4f, PerCell %.4f, a quarter of the rays %.4f\n",
              perPoint, perCell, worse);
  EXPECT_LT(perPoint, worse);
  EXPECT_LT(perCell, worse);
  EXPECT_EQ(bake(16, 1, D::PerCell).sh, bake(16, 1, D::PerPoint).sh);
}

TEST(VisibilityBake, DefaultCapIsCloserToTheTransmittanceThanTwenty) {
  // What shading uses is exp(-A x max(0, SH(l))); what it stands for is the mean
  // transmittance exp(-A x events) of the rays themselves. The study mode keeps the latter
  // (64 fixed directions, 8 points per cell, events up to 32). At the scene's default
  // absorption A = 0.5, the L1 table of the default cap (10 events) must be closer to it than
  // a cap of 20, and the default 16 rays per point no more than 5 % further from it than 32.
  const StrandSet s = denseCellsGroom();
  const Floor floor(-5e-4f);
  const std::vector<glm::vec3>& tri = floor.tri;
  const std::vector<std::uint32_t>& idx = floor.idx;
  VisibilityBakeOptions ro;
  ro.raysPerPoint = 64;
  ro.pointsPerCell = 8;
  ro.maxEvents = kMaxEventsLimit;
  ro.transmittance = true;
  VisibilityBakeStats rs;
  bakeVisibility(s, 1.5e-4f, tri, idx, 200, ro, &rs);
  ASSERT_EQ(rs.transmittance.size(), std::size_t(kTransmittanceAbsorptions) * CLH_VIS_CELLS * 64);
  ASSERT_EQ(kTransmittanceAbsorption[2], 0.5f);
  const float* ref = &rs.transmittance[std::size_t(2) * CLH_VIS_CELLS * 64];
  std::vector<float> dirs(3 * 64);
  fibonacciDirections(64, dirs.data());
  auto error = [&](std::uint32_t rays, std::uint32_t cap) {
    VisibilityBakeOptions o;
    o.raysPerPoint = rays;
    o.maxEvents = cap;
    const VisibilityBake b = bakeVisibility(s, 1.5e-4f, tri, idx, 200, o);
    double sum = 0.0;
    int n = 0;
    for (std::uint32_t c = 0; c < CLH_VIS_CELLS; ++c) {
      const float* t = &ref[std::size_t(c) * 64];
      if (std::all_of(t, t + 64, [](float v) { return v == 0.0f; })) continue;  // no points
      const float* sh = &b.sh[std::size_t(c) * 4];
      for (std::uint32_t d = 0; d < 64; ++d, ++n)
        sum +=
            std::fabs(std::exp(-0.5f * gpu::clh_vis_events(sh[0], sh[1], sh[2], sh[3], dirs[3 * d],
                                                           dirs[3 * d + 1], dirs[3 * d + 2])) -
                      t[d]);
    }
    EXPECT_EQ(n, 25 * 17 * 64);
    return sum / std::max(n, 1);
  };
  const VisibilityBakeOptions defaults;
  ASSERT_EQ(defaults.maxEvents, 10u);
  const double cap10 = error(defaults.raysPerPoint, 10), cap20 = error(defaults.raysPerPoint, 20);
  const double rays32 = error(32, 10);
  std::printf(
      "mean |visibility - transmittance| at A = 0.5: cap 10 %.4f, cap 20 %.4f; "
      "cap 10 with 32 rays %.4f\n",
      cap10, cap20, rays32);
  EXPECT_LT(cap10, cap20);
  EXPECT_LT(cap10, 1.05 * rays32);
}
}  // namespace
}  // namespace clhair
