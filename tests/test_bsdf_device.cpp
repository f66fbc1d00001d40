// test_bsdf_device.cpp — the hair BSDF's device helpers (kernels/common/hair_bsdf.h via
// kernels/bsdf_probe.cl):
//  BsdfDevice.*     sigma_a helpers and the one-call API agree with the host; the lane-wise
//                   exp, log2 and sincos the shading evaluates three at a time (clh_math.h)
//                   equal fast_math.h's scalar functions bit for bit.
// Fixed seeds; record counts are not multiples of the work-group size and a canary after the
// outputs catches out-of-bounds writes.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "bsdf_support.h"

namespace clhair {
namespace {

using namespace bsdf_test;

TEST(BsdfDevice, SigmaAHelpersMatchReference) {
  auto& d = *test::sharedDevice().impl();
  const cl_uint n = 37;
  std::vector<float> in(n * 8, 0.0f);
  Rng rng(3);
  for (cl_uint i = 0; i < n; ++i) {
    in[i * 8 + 0] = static_cast<float>(8 * rng.u());
    in[i * 8 + 1] = static_cast<float>(2 * rng.u());
    in[i * 8 + 2] = static_cast<float>(0.2 + 0.5 * rng.u());
    for (int c = 0; c < 3; ++c) in[i * 8 + 4 + c] = static_cast<float>(0.05 + 0.95 * rng.u());
  }
  cl::Kernel k(d.program("bsdf_probe.cl"), "bsdf_probe_sigma");
  cl::Buffer bi(d.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, in.size() * sizeof(float),
                in.data());
  std::vector<cl_float4> out(2 * n);
  cl::Buffer bo(d.context, CL_MEM_WRITE_ONLY, out.size() * sizeof(cl_float4));
  k.setArg(0, bi);
  k.setArg(1, n);
  k.setArg(2, bo);
  d.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(64), cl::NDRange(64));
  d.queue.enqueueReadBuffer(bo, CL_TRUE, 0, out.size() * sizeof(cl_float4), out.data());
  for (cl_uint i = 0; i < n; ++i) {
    const Rgb mel = ref::sigmaAFromMelanin(in[i * 8], in[i * 8 + 1]);
    const Rgb col =
        ref::sigmaAFromColor({in[i * 8 + 4], in[i * 8 + 5], in[i * 8 + 6]}, in[i * 8 + 2]);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(out[2 * i].s[c], mel[c], 1e-5 + 1e-5 * mel[c]);
      EXPECT_NEAR(out[2 * i + 1].s[c], col[c], 1e-5 + 1e-4 * col[c]);
    }
  }
}

TEST(BsdfDevice, LaneMathEqualsScalarBitForBit) {
  // the shading's lane-wise functions must return the scalar functions' bits, lane by lane:
  // the image does not change with how many values are evaluated at once
  std::mt19937 gen(11);
  std::uniform_real_distribution<float> wide(-130.0f, 130.0f), angle(-1e4f, 1e4f);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> in = {0.0f,    -0.0f, 1.0f,   -1.0f,  0.5f,   2.0f,       1e-38f,
                           1e-45f,  3.75f, 17.0f,  -17.0f, 126.5f, -126.5f,    3.14159265f,
                           1.5708f, 1e30f, -1e30f, 87.0f,  -87.0f, 1.41421356f};
  for (int i = 0; i < 997; ++i) in.push_back(wide(gen));  // not a multiple of the group size
  for (int i = 0; i < 500; ++i) in.push_back(angle(gen));
  for (int i = 0; i < 500; ++i) in.push_back(std::ldexp(unit(gen), -int(unit(gen) * 120.0f)));
  const cl_uint n = static_cast<cl_uint>(in.size());
  const std::vector<float> out = test::runProbeKernel("bsdf_probe_lanes", in, n, 8, -12345.0f, 4);
  const char* names[4] = {"exp", "log2", "sin", "cos"};
  for (cl_uint i = 0; i < n; ++i)
    for (int f = 0; f < 4; ++f) {
      const float lane = out[8 * i + f], scalar = out[8 * i + 4 + f];
      std::uint32_t a, b;
      std::memcpy(&a, &lane, 4);
      std::memcpy(&b, &scalar, 4);
      EXPECT_EQ(a, b) << names[f] << "(" << in[i] << "): lane " << lane << ", scalar " << scalar;
    }
}

TEST(BsdfDevice, OneCallEqualsPartsAndIsFinite) {
  Rng rng(41);
  std::vector<float> recs;
  const int n = 1001;
  for (int i = 0; i < n; ++i) {
    ChiangMaterial m =
        material(10 * rng.u(), 0.1 + 0.9 * rng.u(), 0.15 + 0.45 * rng.u(), 4 * rng.u() - 2);
    Frame f = randomFrame(rng);
    // include exactly grazing and tangent-aligned directions
    const double so = i % 50 == 0 ? 1.0 : 2 * rng.u() - 1;
    const double si = i % 70 == 0 ? -1.0 : 2 * rng.u() - 1;
    float r[kIn];
    putRecord(r, m, f.t, f.dir(so, 0.0), f.dir(si, 2 * kPi * rng.u()));
    recs.insert(recs.end(), r, r + kIn);
  }
  const auto out = runProbe(recs);
  for (int i = 0; i < n; ++i) {
    const cl_float4* r = &out[static_cast<size_t>(i) * kOut];
    for (int c = 0; c < 3; ++c) {
      const double parts = r[0].s[c] + r[1].s[c] + r[2].s[c] + r[3].s[c];
      ASSERT_TRUE(std::isfinite(r[4].s[c])) << "record " << i;
      ASSERT_GE(r[4].s[c], 0.0f) << "record " << i;
      EXPECT_NEAR(r[4].s[c], parts, 1e-5 * (1 + parts)) << "record " << i;
    }
    // clh_hair_eval_cos (luminance in .w) is f cos(theta_i) without the division
    ASSERT_TRUE(std::isfinite(r[4].s[3])) << "record " << i;
    if (r[0].s[3] > 1e-3f) {
      const double fc = lum(r[4]) * r[0].s[3];
      EXPECT_NEAR(r[4].s[3], fc, 1e-4 * (1 + fc)) << "record " << i;
    }
  }
}

}  // namespace
}  // namespace clhair
