// test_visibility.cpp — baked spherical visibility (Kulikov 2025, "precomputed
// self-shadowing"): the file format (include/clhair/visibility.h), the Embree bake
// (host/groom/visibility_bake.cpp), the SH evaluation of the shading pass
// (kernels/common/visibility.h through bsdf_probe.cl) against a double-precision CPU
// reference, and the lookup in a rendered frame.
//
//  VisibilityFile.*    round trip; truncated, trailing, NaN, bad header -> one error line
//  VisibilitySh.*      L1 projection of a linear function round-trips; the device evaluates
//                      the SH and the transmittance like the CPU reference
//  VisibilityBake.*    an unoccluded strand sees no events anywhere; a strand beside a dense
//                      slab sees events toward the slab and none away from it; the bake
//                      matches a brute-force double-precision count on a small groom
//  VisibilityRender.*  strands deep in a slab render darker than the ones facing the light
//                      with the bake and alike without; the bake switched off gives the
//                      frame without a bake bit for bit; the CLI bakes, renders and refuses
//                      bad files with one line.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "cl/device_impl.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "clhair/visibility.h"
#include "clhair/visibility_sh.h"
#include "groom/visibility_bake.h"
#include "test_util.h"

namespace clhair {
namespace {

constexpr double kPi = 3.14159265358979323846;
const std::size_t kCoeffs = std::size_t(CLH_VIS_CELLS) * CLH_VIS_COEFFS;

VisibilityBake patternBake() {
  VisibilityBake b;
  b.strands = 123;
  b.raysPerPoint = 16;
  b.pointsPerCell = 2;
  b.sh.resize(kCoeffs);
  for (std::size_t i = 0; i < kCoeffs; ++i) b.sh[i] = static_cast<float>(i % 97) * 0.25f - 12.0f;
  return b;
}

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

TEST(VisibilityFile, RoundTripAndRefusals) {
  const std::string dir = test::scratchDir();
  const std::string good = dir + "/good.clhvis";
  const VisibilityBake b = patternBake();
  writeVisibility(b, good);
  const VisibilityBake r = readVisibility(good);
  EXPECT_EQ(r.strands, b.strands);
  EXPECT_EQ(r.raysPerPoint, b.raysPerPoint);
  EXPECT_EQ(r.pointsPerCell, b.pointsPerCell);
  EXPECT_EQ(r.sh, b.sh);

  const std::string bytes = readBytes(good);
  ASSERT_EQ(bytes.size(), kVisibilityHeaderBytes + 4 * kCoeffs);
  auto refused = [&](const std::string& name, std::string data, const std::string& expect) {
    const std::string p = dir + "/" + name;
    writeBytes(p, data);
    const std::string e = test::errorOf([&] { readVisibility(p); });
    EXPECT_NE(e.find(expect), std::string::npos) << name << ": " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << name << ": " << e;
  };
  refused("truncated.clhvis", bytes.substr(0, bytes.size() - 3), "is truncated");
  refused("header.clhvis", bytes.substr(0, 20), "is truncated");
  refused("trailing.clhvis", bytes + "x", "trailing bytes");
  std::string nan = bytes;
  const float q = std::nanf("");
  std::memcpy(&nan[kVisibilityHeaderBytes + 4 * 1001], &q, 4);
  refused("nan.clhvis", nan, "coefficient 1 of cell 250");
  std::string huge = bytes;
  const float h = 1e6f;
  std::memcpy(&huge[kVisibilityHeaderBytes + 8], &h, 4);
  refused("huge.clhvis", huge, "need a finite value");
  std::string magic = bytes;
  magic[7] = '2';
  refused("magic.clhvis", magic, "CLHVIS01");
  std::string version = bytes;
  version[8] = 2;
  refused("version.clhvis", version, "version 2");
  std::string axis = bytes;
  axis[12] = 32;
  refused("axis.clhvis", axis, "32 cells per axis");
  EXPECT_NE(test::errorOf([&] { readVisibility(dir + "/missing.clhvis"); }).find("cannot open"),
            std::string::npos);
}

// double-precision real L1 SH: Y00, Y1-1 (y), Y10 (z), Y11 (x)
double shRef(const double c[4], double x, double y, double z) {
  const double y0 = 0.5 / std::sqrt(kPi), y1 = std::sqrt(3.0 / (4.0 * kPi));
  return c[0] * y0 + y1 * (c[1] * y + c[2] * z + c[3] * x);
}

TEST(VisibilitySh, ProjectionRoundTrip) {
  // f(d) = a + b.d lies in the L1 space: projecting it (4096 stratified directions, the
  // bake's Monte Carlo rule) and evaluating gives f back; the coefficients match the
  // analytic ones c0 = 2 sqrt(pi) a, c_x = b_x sqrt(4 pi / 3).
  const std::uint32_t n = 4096;
  std::vector<float> dirs(3 * n), vals(n);
  sphereDirections(n, 77, dirs.data());
  const double a = 1.7, b[3] = {-2.0, 0.5, 3.25};
  for (std::uint32_t k = 0; k < n; ++k)
    vals[k] = static_cast<float>(a + b[0] * dirs[3 * k] + b[1] * dirs[3 * k + 1] +
                                 b[2] * dirs[3 * k + 2]);
  float c[4];
  projectL1(dirs.data(), vals.data(), n, c);
  const double s = std::sqrt(4.0 * kPi / 3.0);
  EXPECT_NEAR(c[0], 2.0 * std::sqrt(kPi) * a, 0.01 * 2.0 * std::sqrt(kPi) * a);
  EXPECT_NEAR(c[1], b[1] * s, 0.02);
  EXPECT_NEAR(c[2], b[2] * s, 0.02);
  EXPECT_NEAR(c[3], b[0] * s, 0.02);
  for (std::uint32_t k = 0; k < n; k += 37) {
    const double cd[4] = {c[0], c[1], c[2], c[3]};
    EXPECT_NEAR(shRef(cd, dirs[3 * k], dirs[3 * k + 1], dirs[3 * k + 2]), vals[k], 0.02);
  }
}

TEST(VisibilitySh, DeviceMatchesCpuReference) {
  // bsdf_probe_visibility (kernels/common/visibility.h, the shading pass's lookup) against
  // the double-precision reference: the light direction turned into object space by the
  // inverse of a rotation-and-scale transform, the SH value there, max(0, .) and
  // exp(-absorption x events). 1000 records, not a multiple of the work-group size.
  auto& d = *test::sharedDevice().impl();
  const glm::mat4 objToWorld = glm::rotate(glm::scale(glm::mat4(1.0f), glm::vec3(2.0f, 0.5f, 1.0f)),
                                           0.7f, glm::vec3(0.3f, 1.0f, -0.2f));
  const glm::mat4 inv = glm::inverse(objToWorld);
  gpu::ClhVisibilityGpu v{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) v.world_to_obj[4 * r + c] = inv[c][r];
  v.absorption = 0.8f;
  v.cells = CLH_VIS_CELLS;
  v.enabled = 1;
  const cl_uint n = 1000;
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> rec(8 * n);
  for (cl_uint i = 0; i < n; ++i) {
    for (int k = 0; k < 4; ++k) rec[8 * i + k] = 12.0f * u(rng);
    float l[3];
    do {
      for (float& x : l) x = u(rng);
    } while (l[0] * l[0] + l[1] * l[1] + l[2] * l[2] < 0.05f);
    const float len = std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    for (int k = 0; k < 3; ++k) rec[8 * i + 4 + k] = l[k] / len;
  }
  cl::Kernel k(d.program("bsdf_probe.cl"), "bsdf_probe_visibility");
  cl::Buffer vb(d.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof(v), &v);
  cl::Buffer rb(d.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, rec.size() * sizeof(float),
                rec.data());
  const cl_float4 canary = {{-3.0f, -4.0f, -5.0f, -6.0f}};
  std::vector<cl_float4> out(n + 1, canary);
  cl::Buffer ob(d.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, out.size() * sizeof(cl_float4),
                out.data());
  k.setArg(0, vb);
  k.setArg(1, rb);
  k.setArg(2, n);
  k.setArg(3, ob);
  d.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(1024), cl::NDRange(64));
  d.queue.enqueueReadBuffer(ob, CL_TRUE, 0, out.size() * sizeof(cl_float4), out.data());
  for (int c = 0; c < 4; ++c) EXPECT_EQ(out[n].s[c], canary.s[c]);
  int clamped = 0;
  for (cl_uint i = 0; i < n; ++i) {
    const float* r = &rec[8 * i];
    const glm::dvec3 lo = glm::normalize(glm::dmat3(glm::mat3(inv)) * glm::dvec3(r[4], r[5], r[6]));
    const double c[4] = {r[0], r[1], r[2], r[3]};
    const double sh = shRef(c, lo.x, lo.y, lo.z);
    const double events = std::max(sh, 0.0);
    const double vis = std::exp(-0.8 * events);
    clamped += sh < 0.0;
    EXPECT_NEAR(out[i].s[2], sh, 2e-5 * (1.0 + std::fabs(sh))) << "record " << i;
    EXPECT_NEAR(out[i].s[1], events, 2e-5 * (1.0 + events)) << "record " << i;
    EXPECT_NEAR(out[i].s[0], vis, 1e-5 + 1e-5 * vis) << "record " << i;
  }
  EXPECT_GT(clamped, 100);  // both sides of the clamp are exercised
  EXPECT_LT(clamped, 900);
}

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

// The slab as a scene: 1200 vertical strands in x in [-20, 20] mm, z in [-10, 10] mm with
// root uv from (x, z), one directional light from +x without a deep opacity map, the camera
// on the x axis at `cameraX` looking at the slab; no ambient light, black background.
Scene slabScene(std::shared_ptr<const VisibilityBake> bake, float cameraX = 0.12f) {
  StrandGroom g;
  g.name = "slab";
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> j(-0.3f, 0.3f);
  for (int a = 0; a < 40; ++a)
    for (int c = 0; c < 30; ++c) {
      const float x = -0.02f + 0.001f * (a + 0.5f + j(rng));
      const float z = -0.01f + (0.02f / 30.0f) * (c + 0.5f + j(rng));
      g.pointCounts.push_back(9);
      for (int k = 0; k < 9; ++k) g.points.emplace_back(x, -0.03f + 0.06f * k / 8.0f, z);
      g.rootUv.emplace_back((a + 0.5f) / 40.0f, (c + 0.5f) / 30.0f);
    }
  g.appearance.strandWidth = 2e-4f;
  Scene s;
  s.width = 96;
  s.height = 64;
  s.camera.position = glm::vec3(cameraX, 0.0f, 0.0f);
  s.camera.target = glm::vec3(0.0f);
  s.camera.fovYDegrees = 35.0f;
  s.ambient = glm::vec3(0.0f);
  s.background = glm::vec3(0.0f);
  Light l;
  l.type = Light::Type::Directional;
  l.direction = glm::vec3(1.0f, 0.0f, 0.0f);
  l.intensity = 3.0f;
  s.lights.push_back(l);
  GroomInstance gi("slab", std::make_shared<const StrandGroom>(std::move(g)));
  gi.visibility = std::move(bake);
  s.grooms.push_back(gi);
  return s;
}

// Mean luminance of `f` over the pixels where `mask` (the same view without the bake) is lit.
double meanOverHair(const Frame& f, const Frame& mask) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < f.color.rgba.size() / 4; ++i) {
    const float* m = &mask.color.rgba[4 * i];
    if (0.2126 * m[0] + 0.7152 * m[1] + 0.0722 * m[2] <= 1e-3) continue;
    const float* p = &f.color.rgba[4 * i];
    sum += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    ++n;
  }
  EXPECT_GT(n, 100);
  return sum / std::max(n, 1);
}

std::shared_ptr<const VisibilityBake> bakeSlab(Renderer& r) {
  VisibilityBakeOptions o;
  o.raysPerPoint = 32;
  o.pointsPerCell = 2;
  const Scene s = slabScene(nullptr);
  return std::make_shared<const VisibilityBake>(bakeGroomVisibility(r, s, 0, o));
}

TEST(VisibilityRender, DeepStrandsDarkerThanLitSide) {
  // Lit from +x, no deep opacity map: without the bake nothing shadows the light. Seen from
  // +x, the face of the slab that faces the light keeps at least 90 % of its brightness with
  // the bake; seen from -x, the far face, whose light crosses 40 mm of strands, keeps at
  // most 30 %. The same views without the bake are the yardstick (they differ in the BSDF's
  // front and back lighting, which the ratios cancel).
  Renderer r(test::sharedDevice());
  const auto bake = bakeSlab(r);
  RenderOptions o;
  o.lod = Toggle::Off;
  o.filter = Toggle::Off;
  const Frame litNo = r.render(slabScene(nullptr, 0.12f), o);
  const Frame farNo = r.render(slabScene(nullptr, -0.12f), o);
  const double lit =
      meanOverHair(r.render(slabScene(bake, 0.12f), o), litNo) / meanOverHair(litNo, litNo);
  const double deep =
      meanOverHair(r.render(slabScene(bake, -0.12f), o), farNo) / meanOverHair(farNo, farNo);
  std::printf("slab: the bake keeps %.3f of the lit face and %.3f of the far face\n", lit, deep);
  EXPECT_GT(lit, 0.9);
  EXPECT_LE(lit, 1.0 + 1e-6);  // visibility never brightens
  EXPECT_LT(deep, 0.3);
}

TEST(VisibilityRender, OffIsBitIdenticalToNoBake) {
  Renderer r(test::sharedDevice());
  const auto bake = bakeSlab(r);
  RenderOptions o;
  o.lod = Toggle::Off;
  const Frame none = r.render(slabScene(nullptr), o);
  RenderOptions off = o;
  off.bakedVisibility = false;
  const Frame a = r.render(slabScene(bake), off);
  ASSERT_EQ(none.color.rgba.size(), a.color.rgba.size());
  EXPECT_EQ(std::memcmp(none.color.rgba.data(), a.color.rgba.data(),
                        none.color.rgba.size() * sizeof(float)),
            0);
  const Frame on = r.render(slabScene(bake), o);
  EXPECT_NE(std::memcmp(none.color.rgba.data(), on.color.rgba.data(),
                        none.color.rgba.size() * sizeof(float)),
            0);
}

TEST(VisibilityRender, CliBakesRendersAndRefusesBadFiles) {
  const std::string dir = test::scratchDir();
  const std::string groom = test::assetPath("grooms/tiny.hairmesh.json");
  const std::string scene = dir + "/scene.json";
  auto writeScene = [&](const std::string& vis) {
    std::ofstream(scene)
        << R"({"resolution": [64, 48], "camera": {"position": [0, 0.03, 0.12], )"
        << R"("target": [0, 0.02, 0]}, "lights": [{"type": "directional", )"
        << R"("direction": [1, 0.3, 0.2]}], "spheres": [{"center": [0, -0.02, 0], )"
        << R"("radius": 0.02}], "grooms": [{"file": ")" << groom << "\"" << vis << "}]}";
  };
  writeScene("");
  const std::string vis = dir + "/tiny.clhvis";
  const auto bake = test::runCli("bake-visibility " + test::quote(scene) + " -o " +
                                 test::quote(vis) + " --rays 8 --points-per-cell 1");
  ASSERT_EQ(bake.exitCode, 0) << bake.output;
  EXPECT_NE(bake.output.find("cells"), std::string::npos) << bake.output;
  writeScene(R"(, "visibility": {"file": ")" + vis + R"(", "absorption": 0.7})");
  const auto render =
      test::runCli("render " + test::quote(scene) + " -o " + test::quote(dir + "/out.png") + " -q");
  EXPECT_EQ(render.exitCode, 0) << render.output;
  // a truncated file, and a bake of another groom: one error line each, no image
  const std::string bytes = readBytes(vis);
  writeBytes(vis, bytes.substr(0, bytes.size() - 1));
  auto bad = test::runCli("render " + test::quote(scene) + " -o " + test::quote(dir + "/bad.png"));
  EXPECT_NE(bad.exitCode, 0);
  EXPECT_NE(test::onlyErrorLine(bad.output).find("is truncated"), std::string::npos) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/bad.png"));
  VisibilityBake other = readVisibility([&] {
    writeBytes(vis, bytes);
    return vis;
  }());
  other.strands += 1;
  writeVisibility(other, vis);
  bad = test::runCli("render " + test::quote(scene) + " -o " + test::quote(dir + "/bad.png"));
  EXPECT_NE(bad.exitCode, 0);
  EXPECT_NE(test::onlyErrorLine(bad.output).find("was baked for a groom of"), std::string::npos)
      << bad.output;
  writeScene("");
  const auto noGroom = test::runCli("bake-visibility " + test::quote(scene) + " -o " +
                                    test::quote(dir + "/x.clhvis") + " --groom 3");
  EXPECT_NE(noGroom.exitCode, 0);
  EXPECT_NE(test::onlyErrorLine(noGroom.output).find("does not exist"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.clhvis"));
  // the event cap and the study mode's options: one error line each, nothing written
  for (const std::string& args : {std::string("--max-events 0"), std::string("--max-events 33"),
                                  std::string("--transmittance-out ") +
                                      test::quote(dir + "/t.clhtrn") + " --directions per-cell"}) {
    const auto refused = test::runCli("bake-visibility " + test::quote(scene) + " -o " +
                                      test::quote(dir + "/x.clhvis") + " " + args);
    EXPECT_NE(refused.exitCode, 0) << args;
    EXPECT_NE(test::onlyErrorLine(refused.output).find("--"), std::string::npos) << refused.output;
    EXPECT_FALSE(std::filesystem::exists(dir + "/x.clhvis")) << args;
    EXPECT_FALSE(std::filesystem::exists(dir + "/t.clhtrn")) << args;
  }
  // the study mode writes a table of 4 absorptions x 64^3 cells x the rays' directions
  const auto study =
      test::runCli("bake-visibility " + test::quote(scene) + " -o " +
                   test::quote(dir + "/s.clhvis") + " --rays 8 --points-per-cell 1 " +
                   "--max-events 32 --transmittance-out " + test::quote(dir + "/s.clhtrn"));
  ASSERT_EQ(study.exitCode, 0) << study.output;
  const std::string table = readBytes(dir + "/s.clhtrn");
  ASSERT_EQ(table.size(), 20u + 4u * 4u + 4u * 4u * CLH_VIS_CELLS * 8u);
  EXPECT_EQ(table.substr(0, 8), "CLHTRN01");
  float t = 0.0f, most = 0.0f;
  for (std::size_t i = 36; i < table.size(); i += 4) {
    std::memcpy(&t, table.data() + i, 4);
    ASSERT_TRUE(t >= 0.0f && t <= 1.0f) << t;
    most = std::max(most, t);
  }
  EXPECT_GT(most, 0.5f);  // some cell sees open sky
}

}  // namespace
}  // namespace clhair
