// test_util.h — shared helpers for the test suite: one OpenCL device per process, paths
// to the source tree, the CLI and a scratch folder, running the CLI with its exit code and
// output, writing input files and counting lines of output, and small image statistics.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "clhair/device.h"
#include "clhair/error.h"

namespace clhair::test {

inline std::string envOr(const char* name, const std::string& def) {
  const char* v = std::getenv(name);
  return v && *v ? std::string(v) : def;
}

inline std::string sourceDir() { return envOr("CLHAIR_SOURCE_DIR", CLHAIR_SOURCE_DIR); }
inline std::string assetPath(const std::string& rel) { return sourceDir() + "/assets/" + rel; }
inline std::string cliPath() { return envOr("CLHAIR_BIN", CLHAIR_TEST_BIN); }

// The running test's folder under the build's test output: <build>/test-output/<suite>.<test>/
inline std::filesystem::path testOutputPath() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "misc";
  for (char& c : name)
    if (c == '/') c = '_';
  return std::filesystem::path(envOr("CLHAIR_TEST_OUTPUT", CLHAIR_TEST_OUTPUT_DIR)) / name;
}

// A fresh scratch folder for one test (testOutputPath(), emptied).
inline std::string scratchDir() {
  const std::filesystem::path p = testOutputPath();
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p.string();
}

// The environment of this process and of the CLI runs it starts: compiled kernels are
// cached inside the build folder unless POCL_CACHE_DIR / CLHAIR_CACHE_DIR are already set,
// and kernel warnings are errors (CLHAIR_KERNEL_WERROR=1), so the CLI builds the same
// programs as the tests' own devices and the two share every cache entry.
inline void useTestEnvironment() {
  ::setenv("CLHAIR_KERNEL_WERROR", "1", 0);
  if (!std::getenv("POCL_CACHE_DIR")) ::setenv("POCL_CACHE_DIR", CLHAIR_TEST_POCL_CACHE, 0);
  if (!std::getenv("CLHAIR_CACHE_DIR"))
    ::setenv("CLHAIR_CACHE_DIR", (std::string(CLHAIR_TEST_POCL_CACHE) + "/../clhair-cache").c_str(),
             0);
}

// The default device of this process, opened once (kernel warnings are errors in tests).
inline Device& sharedDevice() {
  static std::unique_ptr<Device> dev;
  if (!dev) {
    useTestEnvironment();
    DeviceOptions opts;
    opts.kernelWarningsAsErrors = true;
    dev = std::make_unique<Device>(Device::open(DeviceOptions::fromEnvironment(opts)));
  }
  return *dev;
}

// The shared device's platform and device opened again with its own cache folder. `programs`:
// its compiled programs are kept there even on a driver that keeps its own (PoCL), for the
// program cache's own tests; baked data (AO) goes there either way.
inline Device openWithCache(const std::string& dir, bool programs = true) {
  const DeviceInfo& shared = sharedDevice().info();
  DeviceOptions o;
  o.selector = std::to_string(shared.platformIndex) + ":" + std::to_string(shared.deviceIndex);
  o.cacheDir = dir;
  o.cacheProgramsAlways = programs;
  o.kernelWarningsAsErrors = true;
  return Device::open(o);
}

struct CommandResult {
  int exitCode = -1;
  std::string output;  // stdout and stderr together
};

// The one "clhair: error: ..." line of a command's output; a test failure (and "") when
// the output holds none or several.
inline std::string onlyErrorLine(const std::string& output) {
  const std::string tag = "clhair: error:";
  std::size_t count = 0;
  for (std::size_t at = output.find(tag); at != std::string::npos; at = output.find(tag, at + 1))
    ++count;
  if (count != 1) {
    ADD_FAILURE() << "expected exactly one \"" << tag << "\" line, found " << count;
    return {};
  }
  const std::size_t begin = output.find(tag), end = output.find('\n', begin);
  return output.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
}

// Runs a shell command, capturing both streams.
inline CommandResult runCommand(const std::string& cmd) {
  useTestEnvironment();
  CommandResult r;
  std::string full = cmd + " 2>&1";
  FILE* pipe = ::popen(full.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof(buf), pipe)) > 0) r.output.append(buf, n);
  int status = ::pclose(pipe);
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

inline std::string quote(const std::string& s) { return "'" + s + "'"; }

inline CommandResult runCli(const std::string& args) {
  return runCommand(quote(cliPath()) + " " + args);
}

// The message of the clhair::Error that f() throws, or "" when it throws none.
template <typename F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// The bytes of the file at `path` (empty when it cannot be read).
inline std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Writes `bytes` to `path` as they are (a test's input file).
inline void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

// How often `what` occurs in `text` (a command's output lines).
inline std::size_t countOf(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

}  // namespace clhair::test
