// test_gbuffer.cpp — the 64-bit G-buffer word: host round trip, octahedral error bound,
// device packing equal to host packing, and struct layouts identical on both sides.
#include <cmath>
#include <random>

#include "cl/device_impl.h"
#include "clhair/gpu_types.h"
#include "test_util.h"

namespace clhair {
namespace {

using namespace gpu;

float angleBetween(const float* a, float x, float y, float z) {
  float len = std::sqrt(x * x + y * y + z * z);
  float d = (a[0] * x + a[1] * y + a[2] * z) / len;
  return std::acos(std::min(1.0f, std::max(-1.0f, d)));
}

TEST(GBuffer, PackUnpackRoundTripOnHost) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::uint32_t> u24(0, CLH_DEPTH_MAX_CODE), u16(0, 0xFFFF),
      u6(0, 63);
  for (int i = 0; i < 10000; ++i) {
    std::uint32_t d = u24(rng), o = u16(rng), u = u6(rng), v = u6(rng), w = u6(rng), ao = u6(rng);
    clh_u64 word = clh_gbuf_pack(d, o, u, v, w, ao);
    ASSERT_NE(word, CLH_GBUF_EMPTY);
    EXPECT_EQ(clh_gbuf_depth(word), d);
    EXPECT_EQ(clh_gbuf_oct(word), o);
    EXPECT_EQ(clh_gbuf_u(word), u);
    EXPECT_EQ(clh_gbuf_v(word), v);
    EXPECT_EQ(clh_gbuf_w(word), w);
    EXPECT_EQ(clh_gbuf_ao(word), ao);
  }
  // depth is the most significant field: a nearer depth always wins atom_min
  EXPECT_LT(clh_gbuf_pack(10, 0xFFFF, 63, 63, 63, 63), clh_gbuf_pack(11, 0, 0, 0, 0, 0));
}

TEST(GBuffer, DepthQuantisationError) {
  const float nearZ = 0.5f, farZ = 3.5f;
  float worst = 0.0f;
  for (int i = 0; i <= 100000; ++i) {
    float z = nearZ + (farZ - nearZ) * static_cast<float>(i) / 100000.0f;
    float back = clh_depth_decode(clh_depth_encode(z, nearZ, farZ), nearZ, farZ);
    worst = std::max(worst, std::fabs(back - z));
  }
  // half a code step plus float rounding
  EXPECT_LE(worst, 0.5f * (farZ - nearZ) / CLH_DEPTH_MAX_CODE + 4e-7f * farZ);
}

TEST(GBuffer, OctahedralTangentErrorBound) {
  // 8 + 8 bit octahedral codes with plain rounding: half a code step is 1/255 on the
  // octahedron, which the projection to the sphere stretches by up to ~1.7 near the fold;
  // the measured maximum is 0.95 degrees, the bound 1.0 degree.
  const float bound = 1.0f * 3.14159265f / 180.0f;
  std::mt19937 rng(3);
  std::normal_distribution<float> n(0.0f, 1.0f);
  float worst = 0.0f;
  for (int i = 0; i < 200000; ++i) {
    float x = n(rng), y = n(rng), z = n(rng);
    float out[3];
    clh_oct_decode(clh_oct_encode(x, y, z), out);
    EXPECT_NEAR(out[0] * out[0] + out[1] * out[1] + out[2] * out[2], 1.0f, 1e-5f);
    worst = std::max(worst, angleBetween(out, x, y, z));
  }
  // axis directions and the octahedron's fold are represented well
  for (float s : {-1.0f, 1.0f}) {
    float out[3];
    clh_oct_decode(clh_oct_encode(0, 0, s), out);
    EXPECT_LT(angleBetween(out, 0, 0, s), bound);
    clh_oct_decode(clh_oct_encode(s, 0, 0), out);
    EXPECT_LT(angleBetween(out, s, 0, 0), bound);
  }
  RecordProperty("oct_max_error_deg", std::to_string(worst * 180.0f / 3.14159265f));
  EXPECT_LT(worst, bound);
}

TEST(GBuffer, DevicePackingMatchesHost) {
  Device& dev = test::sharedDevice();
  auto& d = *dev.impl();
  const std::uint32_t n = 5003;  // not a multiple of any work-group size
  std::vector<float> in(n * 10);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f), s(-1.0f, 1.0f);
  for (std::uint32_t i = 0; i < n; ++i) {
    float* e = &in[i * 10];
    e[1] = 0.3f;
    e[2] = 2.7f;
    e[0] = 0.2f + 2.7f * u(rng);  // some outside [near, far]: clamped
    e[3] = s(rng);
    e[4] = s(rng);
    e[5] = s(rng);
    for (int k = 6; k < 10; ++k) e[k] = -0.1f + 1.2f * u(rng);
  }
  cl::Program program = d.program("selftest.cl");
  cl::Kernel k(program, "selftest_gbuffer");
  cl::Buffer bin(d.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, in.size() * sizeof(float),
                 in.data());
  // canaries after the last word catch writes past the end
  std::vector<cl_ulong> out(n + 4, 0x0123456789ABCDEFull);
  cl::Buffer bout(d.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                  out.size() * sizeof(cl_ulong), out.data());
  k.setArg(0, bin);
  k.setArg(1, bout);
  k.setArg(2, n);
  d.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange((n + 63) / 64 * 64), cl::NDRange(64));
  d.queue.enqueueReadBuffer(bout, CL_TRUE, 0, out.size() * sizeof(cl_ulong), out.data());
  int exact = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const float* e = &in[i * 10];
    clh_u64 host =
        clh_gbuf_pack(clh_depth_encode(e[0], e[1], e[2]), clh_oct_encode(e[3], e[4], e[5]),
                      clh_unorm_bits(e[6], 6), clh_unorm_bits(e[7], 6), clh_unorm_bits(e[8], 6),
                      clh_unorm_bits(e[9], 6));
    clh_u64 dv = out[i];
    // the 24-bit depth code sits at float's precision limit, and OpenCL division is not
    // correctly rounded: it may differ by one code; every other field must match exactly
    const clh_u64 depthMask = ~(static_cast<clh_u64>(0xFFFFFF) << 40);
    exact += (dv & depthMask) == (host & depthMask);
    EXPECT_LE(
        std::abs(static_cast<int>(clh_gbuf_depth(dv)) - static_cast<int>(clh_gbuf_depth(host))), 1);
  }
  EXPECT_GE(exact, static_cast<int>(n) - 5);
  for (std::uint32_t i = n; i < n + 4; ++i)
    EXPECT_EQ(out[i], 0x0123456789ABCDEFull) << "canary " << i;
}

TEST(GBuffer, StructLayoutsMatchDevice) {
  auto& d = *test::sharedDevice().impl();
  cl::Kernel k(d.program("selftest.cl"), "selftest_layout");
  std::vector<cl_uint> out(11, 0);
  cl::Buffer b(d.context, CL_MEM_READ_WRITE, out.size() * sizeof(cl_uint));
  k.setArg(0, b);
  d.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(1), cl::NDRange(1));
  d.queue.enqueueReadBuffer(b, CL_TRUE, 0, out.size() * sizeof(cl_uint), out.data());
  EXPECT_EQ(out[0], sizeof(ClhMeshVertex));
  EXPECT_EQ(out[1], sizeof(ClhBundle));
  EXPECT_EQ(out[2], sizeof(ClhGroomGpu));
  EXPECT_EQ(out[3], sizeof(ClhViewGpu));
  EXPECT_EQ(out[4], sizeof(ClhLightGpu));
  EXPECT_EQ(out[5], sizeof(ClhSphereGpu));
  EXPECT_EQ(out[6], sizeof(ClhPlaneGpu));
  EXPECT_EQ(out[7], sizeof(ClhSceneGpu));
  EXPECT_EQ(out[8], sizeof(ClhLodRecord));
  EXPECT_EQ(out[9], sizeof(ClhVisibilityGpu));
  EXPECT_EQ(out[10], sizeof(ClhChildrenGpu));
}

}  // namespace
}  // namespace clhair
