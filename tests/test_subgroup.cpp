// test_subgroup.cpp — the sub-group layer against a CPU model on every backend the device
// offers: shuffle up/down with edge fill (scalar and uint4), broadcast, and two exchanges
// in a row (both halves of the __local ping-pong buffer).
#include "cl/device_impl.h"
#include "test_util.h"

namespace clhair {
namespace {

constexpr int kWords = 16;

// The CPU model of selftest_subgroup (kernels/selftest.cl): `strands` strands of `lanes`
// lanes, each strand exchanging its own values.
std::vector<cl_uint> model(int lanes, int strands) {
  const int kLanes = lanes;
  std::vector<cl_uint> m(std::size_t(lanes) * strands * kWords, 0);
  for (int item = 0; item < lanes * strands; ++item) {
    const int l = item % lanes, slot = item / lanes;
    auto x = [slot](int i) { return static_cast<cl_uint>(i * 7 + 3 + slot * 1000); };
    auto y = [slot](int i) { return static_cast<cl_uint>(i * 13 + 100 + slot * 1000); };
    cl_uint* o = &m[std::size_t(item) * kWords];
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
    o[14] = static_cast<cl_uint>(lanes * strands);
  }
  return m;
}

std::vector<cl_uint> runOn(Device& dev, SubgroupBackend b) {
  auto& d = *dev.impl();
  cl::Kernel k(d.programFor(b, "selftest.cl", ""), "selftest_subgroup");
  const std::size_t group = d.tuningFor(b).groupSize();
  std::vector<cl_uint> out(group * kWords, 0xDEADBEEFu);
  cl::Buffer buf(d.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, out.size() * sizeof(cl_uint),
                 out.data());
  k.setArg(0, buf);
  d.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(group), cl::NDRange(group));
  d.queue.enqueueReadBuffer(buf, CL_TRUE, 0, out.size() * sizeof(cl_uint), out.data());
  return out;
}

class SubgroupBackends : public ::testing::TestWithParam<SubgroupBackend> {};

TEST_P(SubgroupBackends, ShufflesMatchCpuModel) {
  Device& dev = test::sharedDevice();
  const auto& cands = dev.info().candidates;
  if (std::find(cands.begin(), cands.end(), GetParam()) == cands.end())
    GTEST_SKIP() << "backend " << subgroupBackendName(GetParam()) << " is not offered by "
                 << dev.info().name << " (its kernels are compile-checked by CrossCompile tests)";
  std::vector<cl_uint> got = runOn(dev, GetParam());
  const StrandTuning t = dev.impl()->tuningFor(GetParam());
  std::vector<cl_uint> want = model(static_cast<int>(t.lanes), static_cast<int>(t.strandsPerGroup));
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size() / kWords; ++i)
    for (int w = 0; w < 15; ++w)
      EXPECT_EQ(got[i * kWords + w], want[i * kWords + w]) << "work-item " << i << " word " << w;
  EXPECT_EQ(dev.selfTest(GetParam()), "");
}

INSTANTIATE_TEST_SUITE_P(All, SubgroupBackends,
                         ::testing::Values(SubgroupBackend::Local, SubgroupBackend::Khr,
                                           SubgroupBackend::Intel, SubgroupBackend::NvPtx,
                                           SubgroupBackend::Amd, SubgroupBackend::Single),
                         [](const auto& info) {
                           return std::string(subgroupBackendName(info.param));
                         });

TEST(Subgroup, ForcedBackendThatFailsIsRefused) {
  DeviceOptions o;
  o.subgroup = "nvptx";  // inline PTX cannot build on a CPU device
  Device& shared = test::sharedDevice();
  if (shared.info().vendor.find("NVIDIA") != std::string::npos)
    GTEST_SKIP() << "NVIDIA device: nvptx is valid";
  o.selector =
      std::to_string(shared.info().platformIndex) + ":" + std::to_string(shared.info().deviceIndex);
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
