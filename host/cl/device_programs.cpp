// device_programs.cpp — the device's programs: build options per sub-group backend (with
// the strand tuning), the program of a kernel file built from the embedded sources (or the
// override tree) and kept per file and options, through the on-disk binary cache, and its
// kernels. A failed build is one error line with the log's first diagnostic.
#include <algorithm>
#include <cstdio>
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

constexpr cl_device_info kComputeCapabilityMajorNv = 0x4000;

// The first line of a build log that reports an error, as ": <line>" ("" when none does).
std::string firstDiagnostic(const std::string& log) {
  std::size_t at = 0;
  while (at < log.size()) {
    const std::size_t end = std::min(log.find('\n', at), log.size());
    const std::string line = log.substr(at, end - at);
    if (line.find("error") != std::string::npos) return ": " + line.substr(0, 300);
    at = end + 1;
  }
  return {};
}

}  // namespace

std::string Device::Impl::buildOptions(SubgroupBackend backend, const std::string& extra) const {
  std::string opts;
  int clc = clcVersionNumber(info.clcVersion);
  std::string ext = device.getInfo<CL_DEVICE_EXTENSIONS>();
  switch (backend) {
    case SubgroupBackend::Khr:
      opts = clc >= 300 ? "-cl-std=CL3.0" : "-cl-std=CL2.0";
      break;
    default:
      opts = "-cl-std=CL1.2";
      break;
  }
  const StrandTuning t = tuningFor(backend);
  opts += " -DSG_SIZE=" + std::to_string(t.lanes) +
          " -DSG_STRANDS=" + std::to_string(t.strandsPerGroup);
  opts += " -DSG_BACKEND=" + std::to_string(static_cast<int>(backend));
  if ((backend == SubgroupBackend::Intel || backend == SubgroupBackend::Khr) &&
      hasExtension(ext, "cl_intel_required_subgroup_size"))
    opts += " -DSG_INTEL_REQD_SIZE=1";
  if (backend == SubgroupBackend::NvPtx) {
    cl_uint major = 0;
    if (clGetDeviceInfo(device(), kComputeCapabilityMajorNv, sizeof(major), &major, nullptr) ==
            CL_SUCCESS &&
        major < 7)
      opts += " -DSG_PTX_LEGACY_SHFL=1";
  }
  if (kernelWarningsAsErrors) opts += " -Werror";
  if (!extra.empty()) opts += " " + extra;
  return opts;
}

StrandTuning Device::Impl::tuningFor(SubgroupBackend backend) const {
  return strandTuning(info, backend, strandsPerGroupOverride);
}

void Device::Impl::useBackend(SubgroupBackend backend, const std::string& note) {
  const StrandTuning t = tuningFor(backend);
  info.backend = backend;
  info.backendNote = note;
  info.lanesPerStrand = t.lanes;
  info.strandsPerGroup = t.strandsPerGroup;
}

cl::Program Device::Impl::programFor(SubgroupBackend backend, const std::string& file,
                                     const std::string& extraOptions) {
  std::string options = buildOptions(backend, extraOptions);
  std::string key = file + "|" + options;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = programs_.find(key);
    if (it != programs_.end()) return it->second;
  }
  std::string text = sources.program(file);
  const std::string cacheKey =
      BinaryCache::key(info.platformName, info.name, info.driverVersion, options, text);
  auto binary = keepPrograms ? binaries.load(cacheKey) : std::nullopt;
  if (binary && !binaries.proven(cacheKey, *binary)) {
    // a binary the driver wrote wrong (or a disk stored wrong) under a valid checksum can
    // crash the driver: built in a child process first, once per entry
    std::string why;
    if (proveCachedProgram(info.platformIndex, info.deviceIndex, binaries.entryPath(cacheKey),
                           cacheKey, options, why)) {
      binaries.markProven(cacheKey, *binary);
    } else {
      binaries.remove(cacheKey);
      binary.reset();
      std::fprintf(stderr,
                   "clhair: note: the cached program of %s (%s) failed its check: %s; removed, "
                   "rebuilt from source\n",
                   file.c_str(), binaries.entryPath(cacheKey).c_str(), why.c_str());
    }
  }
  if (binary) {
    StderrCapture quiet;  // a driver refusing a binary may say so on stderr
    try {                 // a binary the driver does not take back is rebuilt from source below
      cl::Program cached(context, {device}, cl::Program::Binaries{*binary});
      cached.build({device}, options.c_str());
      std::lock_guard<std::mutex> lock(mutex_);
      programs_[key] = cached;
      return cached;
    } catch (const cl::Error&) {
    }
  }
  cl::Program program(context, text);
  {
    // the driver's compiler may print lines of its own besides the build log: they go into
    // the error's details with it, never onto the user's terminal
    StderrCapture driverOutput;
    try {
      program.build({device}, options.c_str());
    } catch (const cl::Error& e) {
      const std::string printed = driverOutput.finish();
      std::string log;
      try {
        log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device);
      } catch (const cl::Error&) {
      }
      throw Error("building " + file + " for " + info.name + " failed with " +
                      clErrorName(e.err()) + firstDiagnostic(log),
                  "options: " + options + "\n--- build log ---\n" + log +
                      (printed.empty() ? std::string() : "--- driver output ---\n" + printed));
    }
  }
  // Only for the cache: reading a binary back can cost a compile of its own (PoCL compiles
  // every kernel of the program for any local size to write one), so not for a cache folder
  // that cannot take it (read-only, full).
  if (keepPrograms && binaries.writable()) try {
      const std::vector<std::vector<unsigned char>> bins = program.getInfo<CL_PROGRAM_BINARIES>();
      if (bins.size() == 1) {
        binaries.store(cacheKey, bins[0]);
        // proven now, while the start pays a compile anyway, so that the next start finds
        // it stamped (a binary that fails is not kept; this run has its program from source)
        std::string why;
        std::error_code ec;
        // not stored (a full or read-only cache folder): nothing to prove
        const bool stored = std::filesystem::is_regular_file(binaries.entryPath(cacheKey), ec);
        if (stored && proveCachedProgram(info.platformIndex, info.deviceIndex,
                                         binaries.entryPath(cacheKey), cacheKey, options, why))
          binaries.markProven(cacheKey, bins[0]);
        else if (stored)
          binaries.remove(cacheKey);
      }
    } catch (const cl::Error&) {  // a driver without binaries just compiles every time
    }
  std::lock_guard<std::mutex> lock(mutex_);
  programs_[key] = program;
  return program;
}

cl::Program Device::Impl::program(const std::string& file, const std::string& extraOptions) {
  return programFor(info.backend, file, extraOptions);
}

cl::Kernel Device::Impl::kernel(const std::string& file, const std::string& name,
                                const std::string& extraOptions) {
  cl::Program p = program(file, extraOptions);
  return clCall("creating kernel " + name + " from " + file,
                [&] { return cl::Kernel(p, name.c_str()); });
}

}  // namespace clhair
