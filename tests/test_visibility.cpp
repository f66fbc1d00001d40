// test_visibility.cpp — baked spherical visibility (Kulikov 2025, "precomputed
// self-shadowing"): the file format (include/clhair/visibility.h) and the SH evaluation of
// the shading pass (kernels/common/visibility.h through bsdf_probe.cl) against a
// double-precision CPU reference. The Embree bake: test_visibility_bake.cpp.
//
//  VisibilityFile.*    round trip; truncated, trailing, NaN, bad header -> one error line
//  VisibilitySh.*      L1 projection of a linear function round-trips; the device evaluates
//                      the SH and the transmittance like the CPU reference
// The bake in rendered frames: test_visibility_render.cpp.
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

using test::readBytes;
using test::writeBytes;

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

}  // namespace
}  // namespace clhair
