// device.cpp — device enumeration and choice, capability checks, and the sub-group backend
// choice with its start-up self-test (device_programs.cpp builds and caches the programs).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "cl/cache_proof.h"
#include "cl/cl_error.h"
#include "cl/device_caps.h"
#include "cl/device_impl.h"
#include "cl/stderr_capture.h"
#include "cl/tuning.h"

namespace clhair {

namespace {

constexpr int kSelftestWords = 16;

std::string envOr(const char* name, const std::string& given) {
  if (!given.empty()) return given;
  const char* v = std::getenv(name);
  return v ? std::string(v) : std::string();
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

DeviceInfo describe(const cl::Platform& platform, const cl::Device& device, int p, int d) {
  DeviceInfo info;
  info.platformIndex = p;
  info.deviceIndex = d;
  info.platformName = platform.getInfo<CL_PLATFORM_NAME>();
  info.name = device.getInfo<CL_DEVICE_NAME>();
  info.vendor = device.getInfo<CL_DEVICE_VENDOR>();
  info.version = device.getInfo<CL_DEVICE_VERSION>();
  info.clcVersion = device.getInfo<CL_DEVICE_OPENCL_C_VERSION>();
  info.driverVersion = device.getInfo<CL_DRIVER_VERSION>();
  info.isGpu = (device.getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_GPU) != 0;
  info.hostUnified = device.getInfo<CL_DEVICE_HOST_UNIFIED_MEMORY>() != CL_FALSE;
  info.maxAlloc = device.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
  info.globalMem = device.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
  info.computeUnits = device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
  std::string ext = device.getInfo<CL_DEVICE_EXTENSIONS>();
  info.int64Atomics = hasExtension(ext, "cl_khr_int64_base_atomics") &&
                      hasExtension(ext, "cl_khr_int64_extended_atomics");
  std::string vendor = lower(info.vendor + " " + info.platformName);
  int clc = clcVersionNumber(info.clcVersion);
  if (hasExtension(ext, "cl_khr_subgroup_shuffle_relative") && clc >= 200)
    info.candidates.push_back(SubgroupBackend::Khr);
  if (hasExtension(ext, "cl_intel_subgroups")) info.candidates.push_back(SubgroupBackend::Intel);
  if (vendor.find("nvidia") != std::string::npos) info.candidates.push_back(SubgroupBackend::NvPtx);
  if (info.isGpu && (vendor.find("advanced micro devices") != std::string::npos ||
                     vendor.find("amd") != std::string::npos))
    info.candidates.push_back(SubgroupBackend::Amd);
  info.candidates.push_back(SubgroupBackend::Local);
  // CPUs: one work-item per strand first (DESIGN.md, "Lanes per strand")
  if (!info.isGpu) info.candidates.insert(info.candidates.begin(), SubgroupBackend::Single);
  return info;
}

struct Found {
  cl::Platform platform;
  cl::Device device;
  DeviceInfo info;
};

std::vector<Found> enumerate() {
  std::vector<Found> all;
  std::vector<cl::Platform> platforms;
  try {
    cl::Platform::get(&platforms);
  } catch (const cl::Error& e) {
    if (e.err() == -1001 /* CL_PLATFORM_NOT_FOUND_KHR */) return all;
    rethrowAsClhairError("listing OpenCL platforms");
  }
  for (int p = 0; p < static_cast<int>(platforms.size()); ++p) {
    std::vector<cl::Device> devices;
    try {
      platforms[p].getDevices(CL_DEVICE_TYPE_ALL, &devices);
    } catch (const cl::Error&) {
      continue;  // a platform without devices
    }
    for (int d = 0; d < static_cast<int>(devices.size()); ++d)
      all.push_back({platforms[p], devices[d], describe(platforms[p], devices[d], p, d)});
  }
  return all;
}

std::string describeList(const std::vector<Found>& all) {
  std::string s;
  for (const Found& f : all)
    s += "\n  " + std::to_string(f.info.platformIndex) + ":" + std::to_string(f.info.deviceIndex) +
         "  " + f.info.name + " (" + f.info.platformName + ")";
  return s.empty() ? std::string(" (none)") : s;
}

constexpr char kSelfTestPassed[] = "passed";

// The sub-group self-test of `b`, or "" at once where the cache folder holds its pass (`kept`). The
// test's result is fixed by what the key holds (the device, its driver, the self-test's kernel
// text and build options, the lanes and strands of a group, the host build), so a pass is kept
// beside the programs and a later start skips building and running it (PoCL preprocesses every
// program it builds: about 50 ms a start). A failure is never kept, and with the cache off the
// test runs on every start.
std::string selfTestOnce(const Device& dev, SubgroupBackend b, bool& kept) {
  kept = false;
  Device::Impl& d = *dev.impl();
  std::string key;
  const std::string passed = kSelfTestPassed;
  if (d.binaries.enabled()) {
    const StrandTuning t = d.tuningFor(b);
    const std::string inputs = "subgroup-selftest-1|" + d.buildOptions(b, "") + "|" +
                               std::to_string(t.lanes) + "|" + std::to_string(t.strandsPerGroup) +
                               "|" + d.sources.program("selftest.cl");
    key = BinaryCache::dataKey("selftest", d.info.platformName, d.info.name, d.info.driverVersion,
                               inputs);
    const auto bytes = d.binaries.load(key);
    kept = bytes && std::string(bytes->begin(), bytes->end()) == passed;
    if (kept) return {};
  }
  const std::string why = dev.selfTest(b);
  if (why.empty() && !key.empty())
    d.binaries.store(key, std::vector<unsigned char>(passed.begin(), passed.end()));
  return why;
}

}  // namespace

const char* subgroupBackendName(SubgroupBackend b) {
  switch (b) {
    case SubgroupBackend::Local:
      return "local";
    case SubgroupBackend::Khr:
      return "khr";
    case SubgroupBackend::Intel:
      return "intel";
    case SubgroupBackend::NvPtx:
      return "nvptx";
    case SubgroupBackend::Amd:
      return "amd";
    case SubgroupBackend::Single:
      return "single";
  }
  return "?";
}

SubgroupBackend parseSubgroupBackend(const std::string& name) {
  for (SubgroupBackend b : {SubgroupBackend::Local, SubgroupBackend::Khr, SubgroupBackend::Intel,
                            SubgroupBackend::NvPtx, SubgroupBackend::Amd, SubgroupBackend::Single})
    if (name == subgroupBackendName(b)) return b;
  throw Error("unknown sub-group backend \"" + name +
              "\"; expected one of: local, khr, intel, nvptx, amd, single");
}

DeviceOptions DeviceOptions::fromEnvironment(DeviceOptions given) {
  given.selector = envOr("CLHAIR_DEVICE", given.selector);
  given.subgroup = envOr("CLHAIR_SUBGROUP", given.subgroup);
  given.kernelDir = envOr("CLHAIR_KERNEL_DIR", given.kernelDir);
  if (envOr("CLHAIR_KERNEL_WERROR", "") == "1") given.kernelWarningsAsErrors = true;
  if (envOr("CLHAIR_CACHE_PROGRAMS", "") == "1") given.cacheProgramsAlways = true;
  if (given.strandsPerGroup == 0) {
    std::string spg = envOr("CLHAIR_STRANDS_PER_GROUP", "");
    if (!spg.empty()) {
      char* end = nullptr;
      unsigned long v = std::strtoul(spg.c_str(), &end, 10);
      if (end == spg.c_str() || *end != '\0' || v == 0 || v > 256)
        throw Error("CLHAIR_STRANDS_PER_GROUP=\"" + spg +
                    "\": expected a whole number from 1 to 256");
      given.strandsPerGroup = static_cast<std::uint32_t>(v);
    }
  }
  return given;
}

std::vector<DeviceInfo> Device::list() {
  std::vector<DeviceInfo> out;
  for (const Found& f : enumerate()) out.push_back(f.info);
  return out;
}

Device Device::open(const DeviceOptions& options) {
  std::vector<Found> all = enumerate();
  if (all.empty())
    throw Error(
        "no OpenCL device found: install an OpenCL driver (on Debian: pocl-opencl-icd) and "
        "check `clinfo`");

  const Found* chosen = nullptr;
  const std::string& sel = options.selector;
  if (sel.empty()) {
    for (const Found& f : all)
      if (f.info.int64Atomics && f.info.isGpu && !chosen) chosen = &f;
    for (const Found& f : all)
      if (f.info.int64Atomics && !chosen) chosen = &f;
    if (!chosen) chosen = &all.front();
  } else {
    int p = -1, d = -1;
    char tail = 0;
    if (std::sscanf(sel.c_str(), "%d:%d%c", &p, &d, &tail) == 2) {
      for (const Found& f : all)
        if (f.info.platformIndex == p && f.info.deviceIndex == d) chosen = &f;
    } else {
      for (const Found& f : all)
        if (!chosen &&
            (lower(f.info.name + " " + f.info.platformName).find(lower(sel)) != std::string::npos))
          chosen = &f;
    }
    if (!chosen)
      throw Error("no OpenCL device matches \"" + sel + "\" (--device or CLHAIR_DEVICE: P:D " +
                      "indices or a name; this machine has " + std::to_string(all.size()) +
                      (all.size() == 1 ? " device" : " devices") + ", `clhair devices` lists them)",
                  "devices on this machine:" + describeList(all));
  }
  if (!chosen->info.int64Atomics)
    throw Error("device \"" + chosen->info.name + "\" (" + chosen->info.platformName +
                ") lacks cl_khr_int64_extended_atomics: clhair needs 64-bit atom_min for its "
                "G-buffer; choose another device with --device or CLHAIR_DEVICE");

  auto impl = std::make_shared<Impl>();
  impl->platform = chosen->platform;
  impl->device = chosen->device;
  impl->info = chosen->info;
  impl->sources = KernelSources(options.kernelDir);
  impl->kernelWarningsAsErrors = options.kernelWarningsAsErrors;
  impl->strandsPerGroupOverride = options.strandsPerGroup;
  impl->binaries = BinaryCache(
      BinaryCache::cacheablePlatform(impl->info.platformName) ? options.cacheDir : "off");
  impl->keepPrograms =
      impl->binaries.enabled() &&
      (options.cacheProgramsAlways || !BinaryCache::driverKeepsPrograms(impl->info.platformName));
  const char* dbg = std::getenv("CLHAIR_DEBUG_SYNC");
  impl->debugFinish = dbg && std::string(dbg) == "1";
  const char* checks = std::getenv("CLHAIR_GRAPH_CHECK");
  impl->graphChecks = checks && std::string(checks) == "1";
  const char* pinned = std::getenv("CLHAIR_PINNED_READBACK");
  impl->pinnedReadBack = pinned && std::string(pinned) == "1";
  impl->zeroNewBuffers = impl->info.platformName.find("Oclgrind") != std::string::npos;
  clCall("creating the OpenCL context on " + impl->info.name, [&] {
    impl->context = cl::Context(impl->device);
    impl->queue = cl::CommandQueue(impl->context, impl->device, CL_QUEUE_PROFILING_ENABLE);
    return 0;
  });
  Device dev(impl);

  std::string forced = options.subgroup == "auto" ? std::string() : options.subgroup;
  if (!forced.empty()) {
    SubgroupBackend b = parseSubgroupBackend(forced);
    bool kept = false;
    std::string why = selfTestOnce(dev, b, kept);
    if (!why.empty())
      throw Error(std::string("forced sub-group backend \"") + subgroupBackendName(b) +
                  "\" fails its self-test on " + impl->info.name + ": " + why);
    impl->useBackend(b, "forced");
    return dev;
  }
  std::string notes;
  for (SubgroupBackend b : impl->info.candidates) {
    bool kept = false;
    std::string why = selfTestOnce(dev, b, kept);
    if (why.empty()) {
      const char* passed = kept ? "self-test passed on an earlier start" : "self-test passed";
      impl->useBackend(b, notes.empty() ? passed : notes);
      return dev;
    }
    notes += std::string(subgroupBackendName(b)) + " failed (" + why + "); ";
  }
  throw Error("no sub-group backend passes its self-test on " + impl->info.name + ": " + notes);
}

const DeviceInfo& Device::info() const { return impl_->info; }

Device Device::withBackend(SubgroupBackend b) const {
  auto impl = std::make_shared<Impl>();
  impl->platform = impl_->platform;
  impl->device = impl_->device;
  impl->context = impl_->context;
  impl->queue = impl_->queue;
  impl->info = impl_->info;
  impl->sources = impl_->sources;
  impl->kernelWarningsAsErrors = impl_->kernelWarningsAsErrors;
  impl->strandsPerGroupOverride = impl_->strandsPerGroupOverride;
  impl->binaries = impl_->binaries;
  impl->keepPrograms = impl_->keepPrograms;
  impl->useBackend(b, "selected");
  impl->debugFinish = impl_->debugFinish;
  impl->graphChecks = impl_->graphChecks;
  impl->pinnedReadBack = impl_->pinnedReadBack;
  return Device(impl);
}

std::string Device::selfTest(SubgroupBackend b) const {
  Impl& d = *impl_;
  try {
    cl::Program program = d.programFor(b, "selftest.cl", "");
    cl::Kernel k(program, "selftest_subgroup");
    const StrandTuning t = d.tuningFor(b);
    const cl_uint lanes = t.lanes, group = t.groupSize();
    size_t wg = k.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(d.device);
    if (wg < group)
      return "kernel work-group limit " + std::to_string(wg) + " < " + std::to_string(group);
    std::vector<cl_uint> out(std::size_t(group) * kSelftestWords, 0xDEADu);
    cl::Buffer buf(d.context, CL_MEM_READ_WRITE, out.size() * sizeof(cl_uint));
    d.queue.enqueueWriteBuffer(buf, CL_TRUE, 0, out.size() * sizeof(cl_uint), out.data());
    k.setArg(0, buf);
    d.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(group), cl::NDRange(group));
    d.queue.enqueueReadBuffer(buf, CL_TRUE, 0, out.size() * sizeof(cl_uint), out.data());
    for (cl_uint item = 0; item < group; ++item) {
      const cl_uint* o = &out[item * kSelftestWords];
      const cl_uint lane = item % lanes, slot = item / lanes;
      auto xOf = [slot](cl_uint l) { return l * 7u + 3u + slot * 1000u; };
      auto yOf = [slot](cl_uint l) { return l * 13u + 100u + slot * 1000u; };
      cl_uint expect[14];
      expect[0] = lane == 0 ? 0xF00Du : xOf(lane - 1);
      expect[1] = lane == lanes - 1 ? 0xBEEFu : xOf(lane + 1);
      expect[2] = xOf(0);
      for (cl_uint c = 0; c < 4; ++c) {
        expect[3 + c] = lane == 0 ? 1u + c : xOf(lane - 1) + c;
        expect[7 + c] = lane == lanes - 1 ? 1u + c : xOf(lane + 1) + c;
      }
      expect[11] = lane == 0 ? 0xF00Du : yOf(lane - 1);
      expect[12] = lane == lanes - 1 ? 0xBEEFu : yOf(lane + 1);
      expect[13] = lane;
      for (int w = 0; w < 14; ++w)
        if (o[w] != expect[w])
          return "work-item " + std::to_string(item) + " word " + std::to_string(w) + " is " +
                 std::to_string(o[w]) + ", expected " + std::to_string(expect[w]);
    }
    return {};
  } catch (const Error& e) {
    std::string msg = e.what();
    return msg.substr(0, msg.find('\n'));
  } catch (const cl::Error& e) {
    return std::string(e.what()) + " " + clErrorName(e.err());
  }
}

// ---- Impl: build options and the program cache -------------------------------------------

}  // namespace clhair
