// test_subgroup.cpp — the sub-group layer against a CPU model on every backend the device
// offers: shuffle up/down with edge fill (scalar and uint4), broadcast, and two exchanges
// in a row (both halves of the __local ping-pong buffer).
#include "cl/device_impl.h"
#include "test_util.h"

namespace clhair {
namespace {

constexpr int kLanes = 32;
constexpr int kWords = 16;

// The CPU model of selftest_subgroup (kernels/selftest.cl).
std::vector<cl_uint> model() {
  std::vector<cl_uint> m(kLanes * kWords, 0);
  auto x = [](int l) { return static_cast<cl_uint>(l * 7 + 3); };
  auto y = [](int l) { return static_cast<cl_uint>(l * 13 + 100); };
  for (int l = 0; l < kLanes; ++l) {
    cl_uint* o = &m[l * kWords];
    o[0] = l == 0 ? 0xF00Du : x(l - 1);
    o[1] = l == kLanes - 1 ? 0xBEEFu : x(l + 1);
    o[2] = x(0);
    for (int c = 0; c < 4; ++c) {
      o[3 + c] = l == 0 ? 1u + c : x(l - 1) + c;
      o[7 + c] = l == kLanes - 1 ? 1u + c : x(l + 1) + c;
    }
    o[11] = l == 0 ? 0xF00Du : y(l - 1);
    o[12] = l == kLanes - 1 ? 0xBEEFu : y(l + 1);
    o[13] = static_cast<cl_uint>(l);
    o[14] = kLanes;
  }
  return m;
}

std::vector<cl_uint> runOn(Device& dev, SubgroupBackend b) {
  auto& d = *dev.impl();
  cl::Kernel k(d.programFor(b, "selftest.cl", ""), "selftest_subgroup");
  std::vector<cl_uint> out(kLanes * kWords, 0xDEADBEEFu);
  cl::Buffer buf(d.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, out.size() * sizeof(cl_uint), out.data());
  k.setArg(0, buf);
  d.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(kLanes), cl::NDRange(kLanes));
  d.queue.enqueueReadBuffer(buf, CL_TRUE, 0, out.size() * sizeof(cl_uint), out.data());
  return out;
}

class SubgroupBackends : public ::testing::TestWithParam<SubgroupBackend> {};

TEST_P(SubgroupBackends, ShufflesMatchCpuModel) {
  Device& dev = test::sharedDevice();
  const auto& cands = dev.info().candidates;
  if (std::find(cands.begin(), cands.end(), GetParam()) == cands.end())
    GTEST_SKIP() << "backend " << subgroupBackendName(GetParam()) << " is not offered by " << dev.info().name
                 << " (its kernels are compile-checked by CrossCompile tests)";
  std::vector<cl_uint> got = runOn(dev, GetParam());
  std::vector<cl_uint> want = model();
  for (int l = 0; l < kLanes; ++l)
    for (int w = 0; w < 15; ++w)
      EXPECT_EQ(got[l * kWords + w], want[l * kWords + w]) << "lane " << l << " word " << w;
  EXPECT_EQ(dev.selfTest(GetParam()), "");
}

INSTANTIATE_TEST_SUITE_P(All, SubgroupBackends,
                         ::testing::Values(SubgroupBackend::Local, SubgroupBackend::Khr, SubgroupBackend::Intel,
                                           SubgroupBackend::NvPtx, SubgroupBackend::Amd),
                         [](const auto& info) { return std::string(subgroupBackendName(info.param)); });

TEST(Subgroup, ForcedBackendThatFailsIsRefused) {
  DeviceOptions o;
  o.subgroup = "nvptx";  // inline PTX cannot build on a CPU device
  Device& shared = test::sharedDevice();
  if (shared.info().vendor.find("NVIDIA") != std::string::npos) GTEST_SKIP() << "NVIDIA device: nvptx is valid";
  o.selector = std::to_string(shared.info().platformIndex) + ":" + std::to_string(shared.info().deviceIndex);
  try {
    Device::open(o);
    FAIL() << "forcing nvptx on " << shared.info().name << " should fail its self-test";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("self-test"), std::string::npos) << e.what();
  }
}

TEST(Subgroup, UnknownBackendNameIsAnError) {
  EXPECT_THROW(parseSubgroupBackend("warp9"), Error);
  EXPECT_EQ(parseSubgroupBackend("local"), SubgroupBackend::Local);
}

}  // namespace
}  // namespace clhair
