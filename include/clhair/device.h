// device.h — choosing an OpenCL device and describing what it offers.
//
// Device::open picks a platform/device (by index "P:D", by a name substring, or the first
// device with 64-bit atomics, GPUs first), refuses devices without
// cl_khr_int64_extended_atomics, chooses the sub-group backend (DESIGN.md) and proves it
// with a start-up self-test, falling back to the __local backend when the test fails.
// A Device is cheap to copy (shared state) and owns the context, queue and program cache.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace clhair {

enum class SubgroupBackend { Local = 0, Khr = 1, Intel = 2, NvPtx = 3, Amd = 4, Single = 5 };

const char* subgroupBackendName(SubgroupBackend b);
// Parses "local", "khr", "intel", "nvptx", "amd", "single"; throws clhair::Error otherwise.
SubgroupBackend parseSubgroupBackend(const std::string& name);

struct DeviceOptions {
  std::string selector;   // "" (auto), "P:D" indices, or a device/platform name substring
  std::string subgroup;   // "" or "auto", or a backend name to force
  std::string kernelDir;  // developer override: source tree to read kernels from
  bool kernelWarningsAsErrors = false;
  std::uint32_t strandsPerGroup = 0;  // 0: the tuning table; else strands per work-group
  std::string cacheDir;  // compiled programs ("" default, "off": none; host/cl/binary_cache.h)
  // Compiled programs go into cacheDir only where the driver keeps none of its own (PoCL
  // does: BinaryCache::driverKeepsPrograms); true stores them there too.
  bool cacheProgramsAlways = false;
  // Values not given here are taken from CLHAIR_DEVICE, CLHAIR_SUBGROUP, CLHAIR_KERNEL_DIR,
  // CLHAIR_STRANDS_PER_GROUP; CLHAIR_KERNEL_WERROR=1 sets kernelWarningsAsErrors and
  // CLHAIR_CACHE_PROGRAMS=1 cacheProgramsAlways.
  static DeviceOptions fromEnvironment(DeviceOptions given);
};

struct DeviceInfo {
  int platformIndex = 0;
  int deviceIndex = 0;
  std::string platformName;
  std::string name;
  std::string vendor;
  std::string version;     // CL_DEVICE_VERSION
  std::string clcVersion;  // CL_DEVICE_OPENCL_C_VERSION
  std::string driverVersion;
  bool isGpu = false;
  // CL_DEVICE_HOST_UNIFIED_MEMORY: the device works in host memory (CPUs, integrated GPUs),
  // so a frame is read back straight into the Frame; else through pinned staging memory.
  bool hostUnified = false;
  bool int64Atomics = false;  // cl_khr_int64_base_atomics + cl_khr_int64_extended_atomics
  std::uint64_t maxAlloc = 0;
  std::uint64_t globalMem = 0;
  std::uint32_t computeUnits = 0;
  std::vector<SubgroupBackend> candidates;           // backends this device may run, best first
  SubgroupBackend backend = SubgroupBackend::Local;  // chosen (after the self-test)
  std::uint32_t lanesPerStrand = 32;  // work-items per strand for `backend` (host/cl/tuning.h)
  std::uint32_t strandsPerGroup = 1;  // strands per work-group for `backend`
  std::string backendNote;            // why this backend (fallback reasons)
};

class Device {
 public:
  // Every OpenCL device on the machine with its capabilities (no self-test is run).
  static std::vector<DeviceInfo> list();
  static Device open(const DeviceOptions& options);

  const DeviceInfo& info() const;
  // Runs the sub-group self-test for `b` on this device; returns "" on success or the
  // reason it failed (build error, wrong results).
  std::string selfTest(SubgroupBackend b) const;
  // A device handle that uses backend `b` (shares the context; used by tests).
  Device withBackend(SubgroupBackend b) const;

  struct Impl;
  const std::shared_ptr<Impl>& impl() const { return impl_; }

 private:
  explicit Device(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}
  std::shared_ptr<Impl> impl_;
};

}  // namespace clhair
