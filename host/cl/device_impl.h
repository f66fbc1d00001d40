// device_impl.h — the OpenCL objects behind clhair::Device and its program cache.
//
// Programs are built from KernelSources with the options of the chosen sub-group backend
// and cached per (file, options); the driver's own binary cache (PoCL: POCL_CACHE_DIR)
// makes later processes skip compilation. Kernels are handed out per call (cl::Kernel
// objects hold argument state, so each stage keeps its own).
#pragma once

#include <map>
#include <mutex>
#include <string>

#include "cl/binary_cache.h"
#include "cl/kernel_sources.h"
#include "cl/opencl.h"
#include "cl/transfer.h"
#include "cl/tuning.h"
#include "clhair/device.h"

namespace clhair {

struct Device::Impl {
  cl::Platform platform;
  cl::Device device;
  cl::Context context;
  cl::CommandQueue queue;
  DeviceInfo info;
  KernelSources sources;
  bool kernelWarningsAsErrors = false;
  bool debugFinish = false;                   // finish() after every dispatch (CLHAIR_DEBUG_SYNC=1)
  std::uint32_t strandsPerGroupOverride = 0;  // DeviceOptions::strandsPerGroup
  BinaryCache binaries;                       // compiled programs and baked data between runs
  // Programs go into `binaries` (else only the baked data does): where the driver keeps no
  // compiled programs of its own, or DeviceOptions::cacheProgramsAlways.
  bool keepPrograms = false;
  Transfers transfers;  // staged uploads, counted host waits
  // Checks of the frame graph (host/graph/frame_graph.h) that cost a driver query per kernel
  // argument: every buffer a pass binds and every kernel it launches was declared
  // (CLHAIR_GRAPH_CHECK=1; the tests turn it on).
  bool graphChecks = false;
  // Read frames back through pinned staging even on a host-unified device
  // (CLHAIR_PINNED_READBACK=1: the tests run the discrete-GPU path on the CPU).
  bool pinnedReadBack = false;
  // Every new buffer starts with host-written zeros (on Oclgrind only). Oclgrind 21.10's
  // --uninitialized check keys its record of a buffer by the buffer's slot and starts it
  // only on a host write: a buffer that no host write ever covers inherits the record of
  // the last buffer freed from its slot, sized as that one was, and every word past that
  // size reads as uninitialised although a kernel wrote it.
  bool zeroNewBuffers = false;

  // The strand kernels' launch shape for `backend` (host/cl/tuning.h).
  StrandTuning tuningFor(SubgroupBackend backend) const;
  // The launch shape of the chosen backend.
  StrandTuning tuning() const { return tuningFor(info.backend); }
  // Makes `backend` the one programs are built for, with its tuning, in `info`.
  void useBackend(SubgroupBackend backend, const std::string& note);

  // Build options for `backend` (sub-group defines, -cl-std) plus `extra`.
  std::string buildOptions(SubgroupBackend backend, const std::string& extra) const;
  // Builds (or returns the cached) program of kernel file `file` for the chosen backend.
  cl::Program program(const std::string& file, const std::string& extraOptions = {});
  cl::Program programFor(SubgroupBackend backend, const std::string& file,
                         const std::string& extraOptions);
  cl::Kernel kernel(const std::string& file, const std::string& name,
                    const std::string& extraOptions = {});

 private:
  std::mutex mutex_;
  std::map<std::string, cl::Program> programs_;
};

}  // namespace clhair
