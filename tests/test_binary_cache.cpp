// test_binary_cache.cpp — compiled programs kept between runs (host/cl/binary_cache.h):
// a build stores one entry per (device, driver, options, source); a second device handle
// takes the program from it and computes the same result; a corrupt entry is refused by
// the driver and rebuilt from source; a changed option is a different entry.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cl/device_impl.h"
#include "test_util.h"

namespace clhair {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> entries(const std::string& dir, const std::string& ext = ".clbin") {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ext) out.push_back(e.path());
  return out;
}

// Packs G-buffer words on the device (selftest_gbuffer): a result that needs a working program.
std::vector<cl_ulong> packWords(Device& dev) {
  auto& d = *dev.impl();
  cl::Kernel k(d.program("selftest.cl"), "selftest_gbuffer");
  const std::vector<float> in = {0.3f, 0.1f, 0.2f,  0.9f, 0.4f, 0.5f,
                                 0.6f, 0.7f, 0.25f, 1.0f, 0.5f, 0.0f};
  cl::Buffer bin(d.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, in.size() * sizeof(float),
                 const_cast<float*>(in.data()));
  std::vector<cl_ulong> out(64, 0);
  cl::Buffer bout(d.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                  out.size() * sizeof(cl_ulong), out.data());
  k.setArg(0, bin);
  k.setArg(1, bout);
  k.setArg(2, 1u);
  d.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(1), cl::NullRange);
  d.queue.enqueueReadBuffer(bout, CL_TRUE, 0, out.size() * sizeof(cl_ulong), out.data());
  return out;
}

TEST(BinaryCache, StoresReusesAndSurvivesACorruptEntry) {
  const std::string dir = test::scratchDir() + "/cache";
  std::vector<cl_ulong> first;
  {
    Device dev = test::openWithCache(dir);  // builds the self-test program
    first = packWords(dev);
  }
  const std::vector<fs::path> stored = entries(dir);
  ASSERT_EQ(stored.size(), 1u)
      << "selftest.cl (the sub-group self-test and the packing kernel share it) is stored";
  {
    Device again = test::openWithCache(dir);
    EXPECT_EQ(packWords(again), first) << "a program taken from the cache computes the same";
  }
  EXPECT_EQ(entries(dir).size(), stored.size())
      << "a second run adds no entries: every program came from disk";
  for (const fs::path& p : stored)
    std::ofstream(p, std::ios::binary | std::ios::trunc) << "not a binary";
  {
    Device rebuilt = test::openWithCache(dir);
    EXPECT_EQ(packWords(rebuilt), first) << "corrupt entries are rebuilt from source";
  }
  for (const fs::path& p : stored) EXPECT_GT(fs::file_size(p), 100u) << p << " was written again";
}

TEST(BinaryCache, KeyChangesWithEveryInput) {
  const std::string base = BinaryCache::key("p", "d", "1.0", "-DX=1", "kernel");
  EXPECT_NE(base, BinaryCache::key("q", "d", "1.0", "-DX=1", "kernel"));
  EXPECT_NE(base, BinaryCache::key("p", "e", "1.0", "-DX=1", "kernel"));
  EXPECT_NE(base, BinaryCache::key("p", "d", "1.1", "-DX=1", "kernel"));
  EXPECT_NE(base, BinaryCache::key("p", "d", "1.0", "-DX=2", "kernel"));
  EXPECT_NE(base, BinaryCache::key("p", "d", "1.0", "-DX=1", "kernel "));
  // field boundaries are part of the key
  EXPECT_NE(BinaryCache::key("ab", "c", "", "", ""), BinaryCache::key("a", "bc", "", "", ""));
  EXPECT_EQ(base, BinaryCache::key("p", "d", "1.0", "-DX=1", "kernel"));
}

TEST(BinaryCache, OffMeansNoFiles) {
  BinaryCache off("off");
  EXPECT_FALSE(off.enabled());
  off.store("x.clbin", {1, 2, 3});
  EXPECT_FALSE(off.load("x.clbin").has_value());
}

}  // namespace
}  // namespace clhair
