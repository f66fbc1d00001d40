// test_binary_cache.cpp — compiled programs kept between runs (host/cl/binary_cache.h):
// a build stores one entry per (device, driver, options, source); a second device handle
// takes the program from it and computes the same result; a changed option is a different
// entry. The cache heals: an entry that is not an entry, cut short (as a full disk or a killed
// write leaves it), flipped or another key's is discarded and rebuilt, never given to the
// driver; the entry reader refuses every truncation and every flipped byte; a cache on a full
// or read-only file system means no cache, and the render still succeeds. A binary written
// wrong under a valid checksum is caught in a child process and rebuilt; baked data is keyed
// by the host build. A driver that keeps its own compiled programs (PoCL) has none stored here.
// A sub-group self-test's pass is kept, and a start that finds it skips the test.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <sys/stat.h>

#include "cl/binary_cache.h"
#include "cl/device_impl.h"
#include "fault_fs.h"
#include "test_util.h"

namespace clhair {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> entries(const std::string& dir, const std::string& ext = ".clbin") {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const auto& e :
       fs::directory_iterator(fs::path(BinaryCache(dir).entryPath("x")).parent_path(), ec))
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

// An entry cut to half its length made every later run die in the driver (SIGSEGV in PoCL):
// now it is discarded before the driver sees it, and the rebuilt program is stored whole.
TEST(BinaryCache, TruncatedEntriesAreDiscardedAndRebuilt) {
  const std::string dir = test::scratchDir() + "/cache";
  std::vector<cl_ulong> first;
  {
    Device dev = test::openWithCache(dir);
    first = packWords(dev);
  }
  const std::vector<fs::path> stored = entries(dir);
  ASSERT_FALSE(stored.empty());
  std::vector<std::uintmax_t> sizes;
  for (const fs::path& p : stored) {
    sizes.push_back(fs::file_size(p));
    fs::resize_file(p, sizes.back() / 2);
  }
  {
    Device again = test::openWithCache(dir);
    EXPECT_EQ(packWords(again), first) << "a program rebuilt after a truncated entry";
  }
  for (const fs::path& p : stored)
    EXPECT_TRUE(decodeCacheEntry(test::readBytes(p.string()), p.filename().string()))
        << p << " was not written again whole";
}

TEST(BinaryCache, EntryReaderRefusesEveryDamage) {
  const std::string key = BinaryCache::key("p", "d", "1.0", "-DX=1", "kernel");
  std::vector<unsigned char> payload(97);
  for (std::size_t i = 0; i < payload.size(); ++i) payload[i] = static_cast<unsigned char>(i * 7);
  const std::string entry = encodeCacheEntry(key, payload);
  ASSERT_EQ(decodeCacheEntry(entry, key), payload);
  std::string why;
  for (std::size_t n = 0; n < entry.size(); ++n)
    EXPECT_FALSE(decodeCacheEntry(entry.substr(0, n), key, &why)) << "cut to " << n << " bytes";
  EXPECT_FALSE(decodeCacheEntry(entry + "x", key)) << "a trailing byte";
  for (std::size_t i = 0; i < entry.size(); ++i)
    for (unsigned char bit : {0x01, 0x80}) {
      std::string flipped = entry;
      flipped[i] = static_cast<char>(flipped[i] ^ bit);
      EXPECT_FALSE(decodeCacheEntry(flipped, key)) << "byte " << i << " flipped";
    }
  EXPECT_FALSE(decodeCacheEntry(entry, BinaryCache::key("p", "d", "1.0", "-DX=2", "kernel"), &why));
  EXPECT_EQ(why, "another key's entry");
  EXPECT_FALSE(decodeCacheEntry(std::string(entry.size(), '\0'), key));
}

// A cache folder on a full or read-only file system (or holding a FIFO where an entry
// belongs) costs compiles, never the render.
TEST(BinaryCache, AFullOrReadOnlyCacheIsNoCache) {
  const std::string dir = test::scratchDir();
  fs::create_directories(dir + "/scene");
  const std::string scene = dir + "/scene/scene.json";
  test::writeBytes(scene, R"({"resolution": [32, 24],
    "camera": {"position": [0, 0.03, 0.2], "target": [0, 0.025, 0], "fov": 35},
    "grooms": [{"file": ")" + test::assetPath("grooms/tiny.hairmesh.json") +
                              R"("}]})");
  // a warm cache of this build's programs, to copy the names of
  const std::string warm = dir + "/warm";
  const test::CommandResult w =
      test::runCommand("env CLHAIR_CACHE_PROGRAMS=1 CLHAIR_CACHE_DIR=" + test::quote(warm) + " " +
                       test::quote(test::cliPath()) + " render " + test::quote(scene) + " -q -o " +
                       test::quote(dir + "/warm.png"));
  ASSERT_EQ(w.exitCode, 0) << w.output;
  const std::string expected = test::readBytes(dir + "/warm.png");
  {
    test::FullFolder full(dir + "/full");
    const test::CommandResult r = test::runCommand(
        full.env() + "CLHAIR_CACHE_PROGRAMS=1 CLHAIR_CACHE_DIR=" + test::quote(dir + "/full/c") +
        " " + test::quote(test::cliPath()) + " render " + test::quote(scene) + " -q -o " +
        test::quote(dir + "/full.png"));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output, "");
    EXPECT_EQ(test::readBytes(dir + "/full.png"), expected);
    EXPECT_TRUE(test::temporariesIn(dir + "/full/c/v2").empty());
  }
  {
    test::ReadOnlyFolder ro(dir + "/ro");
    const test::CommandResult r = test::runCommand(
        "env CLHAIR_CACHE_PROGRAMS=1 CLHAIR_CACHE_DIR=" + test::quote(dir + "/ro") + " " +
        test::quote(test::cliPath()) + " render " + test::quote(scene) + " -q -o " +
        test::quote(dir + "/ro.png"));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(test::readBytes(dir + "/ro.png"), expected);
  }
  // FIFOs where the entries belong: refused unopened, removed, rebuilt
  fs::create_directories(dir + "/fifo/v2");
  for (const auto& e : fs::directory_iterator(warm + "/v2"))
    ASSERT_EQ(::mkfifo((dir + "/fifo/v2/" + e.path().filename().string()).c_str(), 0644), 0);
  const test::CommandResult r = test::runCommand(
      "timeout -s KILL 60 env CLHAIR_CACHE_PROGRAMS=1 CLHAIR_CACHE_DIR=" +
      test::quote(dir + "/fifo") + " " + test::quote(test::cliPath()) + " render " +
      test::quote(scene) + " -q -o " + test::quote(dir + "/fifo.png"));
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(test::readBytes(dir + "/fifo.png"), expected);
  for (const auto& e : fs::directory_iterator(dir + "/fifo/v2"))
    EXPECT_TRUE(fs::is_regular_file(e.path())) << e.path() << " was not rebuilt as an entry";
}

// A cache folder that cannot take an entry says so before the driver is asked for a binary
// (reading one back from PoCL compiles the program's kernels again); the probe leaves nothing.
TEST(BinaryCache, AReadOnlyOrFullFolderIsNotWritable) {
  const std::string dir = test::scratchDir();
  EXPECT_TRUE(BinaryCache(dir + "/ok").writable());
  EXPECT_TRUE(test::listFolder(dir + "/ok/v2").empty());
  EXPECT_FALSE(BinaryCache("off").writable());
  {
    test::ReadOnlyFolder ro(dir + "/ro");
    // as root without a tmpfs, mode 0555 does not stop a write
    if (ro.tmpfs() || ::geteuid() != 0) {
      EXPECT_FALSE(BinaryCache(dir + "/ro").writable());
    }
  }
  {
    test::FullFolder full(dir + "/full");
    // without a tmpfs the folder is full only for child processes with the shim
    if (full.tmpfs()) {
      EXPECT_FALSE(BinaryCache(dir + "/full/c").writable());
    }
  }
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

// A binary the driver wrote wrong, stored under a valid checksum (the checksums cannot see
// it): the next start builds it in a child process first, which fails, so the entry is
// removed and rebuilt from source with one note line, and the run goes on. A proven entry is
// stamped and not proven again.
TEST(BinaryCache, ABinaryWrittenWrongIsCaughtInAChildAndRebuilt) {
  const std::string dir = test::scratchDir() + "/cache";
  std::vector<cl_ulong> first;
  {
    Device dev = test::openWithCache(dir);
    first = packWords(dev);
  }
  const std::vector<fs::path> stored = entries(dir);
  ASSERT_EQ(stored.size(), 1u);
  const fs::path entry = stored[0];
  const std::string key = entry.filename().string();
  {
    Device again = test::openWithCache(dir);  // proves the entry, once
    EXPECT_EQ(packWords(again), first);
  }
  ASSERT_TRUE(fs::exists(entry.string() + ".proven")) << "a proven entry is stamped";
  auto readAll = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  auto payload = decodeCacheEntry(readAll(entry), key);
  ASSERT_TRUE(payload.has_value());
  std::vector<unsigned char> damaged = *payload;
  for (std::size_t i = damaged.size() / 4; i < 3 * damaged.size() / 4; ++i) damaged[i] ^= 0x5a;
  std::ofstream(entry, std::ios::binary | std::ios::trunc) << encodeCacheEntry(key, damaged);
  ASSERT_TRUE(decodeCacheEntry(readAll(entry), key).has_value()) << "the checksum is valid";
  // through the command, whose device builds this program at a start that has not kept the
  // self-test's pass (the self-test runs it)
  for (const fs::path& pass : entries(dir, ".selftest")) fs::remove(pass);
  const test::CommandResult r =
      test::runCommand("CLHAIR_CACHE_PROGRAMS=1 CLHAIR_CACHE_DIR=" + test::quote(dir) + " " +
                       test::quote(test::cliPath()) + " devices");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("clhair: note: the cached program of selftest.cl"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("rebuilt from source"), std::string::npos) << r.output;
  const auto rebuilt = decodeCacheEntry(readAll(entry), key);
  ASSERT_TRUE(rebuilt.has_value()) << "the rebuilt program is stored again";
  EXPECT_NE(*rebuilt, damaged);
  {
    Device after = test::openWithCache(dir);
    EXPECT_EQ(packWords(after), first);
  }
}

// Baked data (the AO of a hair mesh) is keyed by the host build as well: a cache folder filled
// by another build (a sanitized one, whose AO bytes differed from Release's under one key)
// holds its entries under other names, which this build never reads.
TEST(BinaryCache, BakedDataIsKeyedByTheHostBuild) {
  const std::string build = BinaryCache::hostBuild();
  EXPECT_NE(build, "unknown build") << "CMakeLists.txt names the build";
  EXPECT_NE(build.find(CLHAIR_TEST_COMPILER), std::string::npos) << build;
  const std::string here = BinaryCache::dataKey("ao", "p", "d", "1.0", "mesh");
  EXPECT_EQ(here, BinaryCache::dataKey("ao", "p", "d", "1.0", "mesh", build));
  const std::string other =
      BinaryCache::dataKey("ao", "p", "d", "1.0", "mesh", build + " -fsanitize=address");
  EXPECT_NE(here, other);
  const std::string dir = test::scratchDir() + "/cache";
  BinaryCache(dir).store(other, {1, 2, 3, 4});  // the other build fills the shared folder
  EXPECT_TRUE(BinaryCache(dir).load(other).has_value());
  EXPECT_FALSE(BinaryCache(dir).load(here).has_value()) << "this build read the other's entry";
}

// The payload of the one entry of kind `ext` in `dir`, or "" (with a failure) when there is
// not exactly one.
std::string onlyPayload(const std::string& dir, const std::string& ext) {
  const std::vector<fs::path> found = entries(dir, ext);
  EXPECT_EQ(found.size(), 1u) << ext;
  if (found.size() != 1) return {};
  const auto payload =
      decodeCacheEntry(test::readBytes(found[0].string()), found[0].filename().string());
  EXPECT_TRUE(payload) << found[0] << " is not an entry";
  return payload ? std::string(payload->begin(), payload->end()) : std::string();
}

// The sub-group self-test's pass is kept beside the programs (device.cpp, selfTestOnce): a
// later start neither builds nor runs it, and says so (`clhair devices`: "self-test passed on
// an earlier start"). Only a pass is kept, and an entry holding anything else is not taken for
// one: the test runs again and the entry holds the pass again.
TEST(BinaryCache, ASelfTestPassIsKeptAndOnlyAPassSkipsTheTest) {
  const std::string dir = test::scratchDir() + "/cache";
  auto devices = [&] {
    const test::CommandResult r = test::runCommand("CLHAIR_CACHE_DIR=" + test::quote(dir) + " " +
                                                   test::quote(test::cliPath()) + " devices");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return r.output;
  };
  const std::string ran = "(self-test passed)", kept = "(self-test passed on an earlier start)";
  std::string out = devices();
  EXPECT_NE(out.find(ran), std::string::npos) << out;
  EXPECT_EQ(onlyPayload(dir, ".selftest"), "passed");
  out = devices();
  EXPECT_NE(out.find(kept), std::string::npos) << out;

  const fs::path entry = entries(dir, ".selftest").at(0);
  std::ofstream(entry, std::ios::binary | std::ios::trunc)
      << encodeCacheEntry(entry.filename().string(), {'f', 'a', 'i', 'l', 'e', 'd'});
  out = devices();
  EXPECT_NE(out.find(ran), std::string::npos) << "an entry that is not a pass was taken:\n" << out;
  EXPECT_EQ(onlyPayload(dir, ".selftest"), "passed");
}

TEST(BinaryCache, OffMeansNoFiles) {
  BinaryCache off("off");
  EXPECT_FALSE(off.enabled());
  off.store("x.clbin", {1, 2, 3});
  EXPECT_FALSE(off.load("x.clbin").has_value());
}

// PoCL keeps what it compiles in its own kernel cache, so its programs are not stored here
// again (reading a binary back from PoCL compiles every kernel of the program once more);
// other drivers' programs are, and so are PoCL's when its own cache is off.
TEST(BinaryCache, ProgramsAreLeftToADriverThatKeepsItsOwn) {
  const char* before = std::getenv("POCL_KERNEL_CACHE");
  const std::string saved = before ? before : "";
  ::unsetenv("POCL_KERNEL_CACHE");
  EXPECT_TRUE(BinaryCache::driverKeepsPrograms("Portable Computing Language"));
  EXPECT_FALSE(BinaryCache::driverKeepsPrograms("Intel(R) OpenCL"));
  EXPECT_FALSE(BinaryCache::driverKeepsPrograms("NVIDIA CUDA"));
  ::setenv("POCL_KERNEL_CACHE", "0", 1);
  EXPECT_FALSE(BinaryCache::driverKeepsPrograms("Portable Computing Language"));
  if (before)
    ::setenv("POCL_KERNEL_CACHE", saved.c_str(), 1);
  else
    ::unsetenv("POCL_KERNEL_CACHE");

  // the test device without cacheProgramsAlways: an entry only where the driver keeps none
  const std::string dir = test::scratchDir() + "/cache";
  const DeviceInfo& shared = test::sharedDevice().info();
  DeviceOptions o;
  o.selector = std::to_string(shared.platformIndex) + ":" + std::to_string(shared.deviceIndex);
  o.cacheDir = dir;
  std::vector<cl_ulong> words;
  {
    Device dev = Device::open(o);
    words = packWords(dev);
  }
  const bool driverKeeps = BinaryCache::driverKeepsPrograms(shared.platformName);
  RecordProperty("driver_keeps_programs", driverKeeps ? "yes" : "no");
  EXPECT_EQ(entries(dir).size(), driverKeeps ? 0u : 1u) << shared.platformName;
  {
    Device again = Device::open(o);
    EXPECT_EQ(packWords(again), words);
  }
}

}  // namespace
}  // namespace clhair
