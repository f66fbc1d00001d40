// dispatch.cpp — launching kernels and summing profiled times.
#include "cl/dispatch.h"

#include <algorithm>
#include <chrono>
#include <ctime>

#include "cl/cl_error.h"

namespace clhair {

double processCpuMs() {
  timespec t{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

void Profiler::addHost(const std::string& stage, double wallMs, double cpuMs) {
  for (StageTime& t : host_)
    if (t.stage == stage) {
      t.wallMs += wallMs;
      t.cpuMs += cpuMs;
      return;
    }
  StageTime t;
  t.stage = stage;
  t.wallMs = wallMs;
  t.cpuMs = cpuMs;
  host_.push_back(t);
}

std::vector<StageTime> Profiler::collect() {
  std::vector<StageTime> out;
  for (auto& [stage, event] : events_) {
    double ms = 0.0;
    try {
      event.wait();
      cl_ulong start = event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
      cl_ulong end = event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
      ms = end > start ? static_cast<double>(end - start) * 1e-6 : 0.0;
    } catch (...) {
      rethrowAsClhairError("reading profiling times of stage " + stage);
    }
    bool found = false;
    for (StageTime& t : out)
      if (t.stage == stage) {
        t.ms += ms;
        found = true;
      }
    if (!found) out.push_back({stage, ms});
  }
  events_.clear();
  for (StageTime& t : out)
    for (const StageTime& h : host_)
      if (h.stage == t.stage) {
        t.wallMs = h.wallMs;
        t.cpuMs = h.cpuMs;
      }
  host_.clear();
  return out;
}

std::uint64_t bufferBytes(const cl::Buffer& b) {
  if (!b()) return 0;
  return clCall("reading a buffer size",
                [&] { return static_cast<std::uint64_t>(b.getInfo<CL_MEM_SIZE>()); });
}

KernelArgs::KernelArgs(cl::Kernel& kernel, std::string stage)
    : kernel_(kernel), stage_(std::move(stage)) {
  kernelName_ = clCall(stage_, [&] { return kernel_.getInfo<CL_KERNEL_FUNCTION_NAME>(); });
  // some drivers count the terminating zero in the name's length
  while (!kernelName_.empty() && kernelName_.back() == '\0') kernelName_.pop_back();
}

void KernelArgs::fail(const char* name, const std::string& why) const {
  throw Error(stage_ + ": kernel " + kernelName_ + " argument " + std::to_string(index_) + " (" +
              name + "): " + why);
}

KernelArgs& KernelArgs::buffer(const char* name, const cl::Buffer& b, std::uint64_t minBytes) {
  if (!b()) fail(name, "no buffer");
  const std::uint64_t bytes = bufferBytes(b);
  if (bytes < minBytes)
    fail(name, "the buffer holds " + std::to_string(bytes) + " bytes, the launch needs " +
                   std::to_string(minBytes));
  if (LaunchAudit* audit = LaunchAudit::current()) audit->bound(b, name);
  set(name, [&] { kernel_.setArg(index_, b); });
  return *this;
}

LaunchAudit*& LaunchAudit::current() {
  thread_local LaunchAudit* audit = nullptr;
  return audit;
}

std::size_t roundUp(std::size_t n, std::size_t multiple) {
  return multiple == 0 ? n : (n + multiple - 1) / multiple * multiple;
}

cl::Event dispatch(Device::Impl& dev, cl::Kernel& kernel, const std::string& stage,
                   cl::NDRange global, cl::NDRange local, Profiler* profiler) {
  std::string name = clCall(stage, [&] { return kernel.getInfo<CL_KERNEL_FUNCTION_NAME>(); });
  std::size_t wgLimit =
      clCall(stage, [&] { return kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(dev.device); });
  std::size_t localTotal = 1;
  for (cl::size_type d = 0; d < local.dimensions(); ++d) localTotal *= local.get()[d];
  if (localTotal > wgLimit)
    throw Error(stage + ": kernel " + name + " needs work-groups of " + std::to_string(localTotal) +
                " items but " + dev.info.name + " allows " + std::to_string(wgLimit) +
                " for it (too many registers or local memory)");
  std::size_t g[3] = {1, 1, 1};
  for (cl::size_type d = 0; d < global.dimensions(); ++d) {
    std::size_t l = d < local.dimensions() ? local.get()[d] : 1;
    g[d] = roundUp(global.get()[d], l);
    if (g[d] == 0) return cl::Event();
  }
  cl::NDRange rounded = global.dimensions() == 1   ? cl::NDRange(g[0])
                        : global.dimensions() == 2 ? cl::NDRange(g[0], g[1])
                                                   : cl::NDRange(g[0], g[1], g[2]);
  if (LaunchAudit* audit = LaunchAudit::current()) audit->launched(name);
  const bool timed = profiler && profiler->hostTiming;
  const bool profiled = profiler && (profiler->enabled || timed);
  if (timed) {
    dev.transfers.countWait();
    clCall(stage + ": finish before " + name, [&] { return dev.queue.finish(); });
  }
  const double c0 = timed ? processCpuMs() : 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  cl::Event event;
  clCall(stage + ": enqueue " + name, [&] {
    dev.queue.enqueueNDRangeKernel(kernel, cl::NullRange, rounded, local, nullptr,
                                   profiled ? &event : nullptr);
    return 0;
  });
  if (dev.debugFinish || timed) {
    dev.transfers.countWait();
    clCall(stage + ": finish after " + name, [&] { return dev.queue.finish(); });
  }
  if (timed)
    profiler->addHost(
        stage,
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count(),
        processCpuMs() - c0);
  if (profiled) profiler->add(stage, event);
  return event;
}

void dispatchStrands(Device::Impl& dev, cl::Kernel& kernel, const std::string& stage,
                     std::uint32_t strands, cl_uint baseArg, Profiler* profiler) {
  const StrandTuning t = dev.tuning();
  for (std::uint32_t base = 0; base < strands; base += kMaxStrandsPerDispatch) {
    const std::uint32_t count = std::min(kMaxStrandsPerDispatch, strands - base);
    const std::size_t groups = (count + t.strandsPerGroup - 1) / t.strandsPerGroup;
    clCall(stage + ": setting the first strand", [&] { return kernel.setArg(baseArg, base); });
    dispatch(dev, kernel, stage, cl::NDRange(groups * t.groupSize()), cl::NDRange(t.groupSize()),
             profiler);
  }
}

void dispatchStrandsPersistent(Device::Impl& dev, cl::Kernel& kernel, const std::string& stage,
                               std::uint32_t strands, cl_uint groupsArg, Profiler* profiler) {
  if (strands == 0) return;
  const StrandTuning t = dev.tuning();
  const std::uint32_t needed = (strands + t.strandsPerGroup - 1) / t.strandsPerGroup;
  const std::uint32_t groups =
      std::min<std::uint32_t>(needed, std::max<std::uint32_t>(1, dev.info.computeUnits) * 16);
  clCall(stage + ": setting the grid size", [&] { return kernel.setArg(groupsArg, groups); });
  dispatch(dev, kernel, stage, cl::NDRange(std::size_t(groups) * t.groupSize()),
           cl::NDRange(t.groupSize()), profiler);
}

}  // namespace clhair
