// dispatch.h — the one way kernels are bound and launched: arguments set in order by name
// with every buffer checked against the bytes the launch reads or writes (KernelArgs),
// rounded global sizes, work-group limits checked with readable messages, a named
// profiling event per dispatch, and finish() after every dispatch when CLHAIR_DEBUG_SYNC=1.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "cl/cl_error.h"
#include "cl/device_impl.h"
#include "clhair/frame_types.h"

namespace clhair {

// Per-stage device times of a frame from profiling events. Events are asked for only while
// `enabled` (RenderOptions::timings): without them a dispatch creates no event at all.
class Profiler {
 public:
  bool enabled = true;
  void add(const std::string& stage, const cl::Event& e) { events_.emplace_back(stage, e); }
  // Host timing (RenderOptions::stageCores): dispatch() then waits for each dispatch and
  // adds its wall and process CPU time to the stage.
  bool hostTiming = false;
  void addHost(const std::string& stage, double wallMs, double cpuMs);
  // Waits for every event and sums the device time per stage, in first-seen order.
  std::vector<StageTime> collect();
  void clear() {
    events_.clear();
    host_.clear();
  }
  // Hands the events and host times gathered so far to `other` (a frame in flight keeps
  // its own until it is waited for) and starts empty.
  void moveTo(Profiler& other) {
    other.events_ = std::move(events_);
    other.host_ = std::move(host_);
    events_.clear();
    host_.clear();
  }

 private:
  std::vector<std::pair<std::string, cl::Event>> events_;
  std::vector<StageTime> host_;
};

std::size_t roundUp(std::size_t n, std::size_t multiple);

// Bytes of a buffer (0 for a null handle).
std::uint64_t bufferBytes(const cl::Buffer& b);

// Told of every buffer bound and kernel launched on this thread while it is installed: the
// frame executor checks them against what the running pass declared (frame_graph.h).
class LaunchAudit {
 public:
  virtual ~LaunchAudit() = default;
  virtual void bound(const cl::Buffer& b, const char* argument) = 0;
  virtual void launched(const std::string& kernel) = 0;
  // The audit of this thread (null: none).
  static LaunchAudit*& current();
};

// Sets a kernel's arguments in order, each under a name for messages. A buffer argument is
// checked before it is set: it must exist and hold at least `minBytes` (what the launch
// touches), else one clhair::Error names the stage, kernel, argument and both sizes.
// Errors of the driver become clhair::Error naming the argument too.
class KernelArgs {
 public:
  KernelArgs(cl::Kernel& kernel, std::string stage);
  KernelArgs& buffer(const char* name, const cl::Buffer& b, std::uint64_t minBytes);
  template <typename T>
  KernelArgs& value(const char* name, const T& v) {
    set(name, [&] { kernel_.setArg(index_, v); });
    return *this;
  }
  cl_uint next() const { return index_; }  // index of the next argument to set

 private:
  template <typename F>
  void set(const char* name, F&& f);
  [[noreturn]] void fail(const char* name, const std::string& why) const;
  cl::Kernel& kernel_;
  std::string stage_, kernelName_;
  cl_uint index_ = 0;
};

template <typename F>
void KernelArgs::set(const char* name, F&& f) {
  try {
    f();
  } catch (const cl::Error& e) {
    fail(name, std::string(e.what()) + " failed with " + clErrorName(e.err()));
  }
  ++index_;
}

// CPU time of this process (every thread, the OpenCL runtime's included), in ms.
double processCpuMs();

// 1D or 2D dispatch: `global` is rounded up to a multiple of `local` per dimension.
cl::Event dispatch(Device::Impl& dev, cl::Kernel& kernel, const std::string& stage,
                   cl::NDRange global, cl::NDRange local, Profiler* profiler);

// Launches a strand kernel over `strands` draw indices in the device's launch shape
// (host/cl/tuning.h): work-groups of lanes x strands-per-group items, split into
// dispatches of at most kMaxStrandsPerDispatch strands (every driver's global-size
// limits), each told its first strand through argument `baseArg`.
constexpr std::uint32_t kMaxStrandsPerDispatch = 1u << 22;
void dispatchStrands(Device::Impl& dev, cl::Kernel& kernel, const std::string& stage,
                     std::uint32_t strands, cl_uint baseArg, Profiler* profiler);
// A persistent grid for up to `strands` strands: a few work-groups per compute unit, each
// walking the strands of its slots in steps of the grid; the grid's group count goes to
// argument `groupsArg`.
void dispatchStrandsPersistent(Device::Impl& dev, cl::Kernel& kernel, const std::string& stage,
                               std::uint32_t strands, cl_uint groupsArg, Profiler* profiler);

}  // namespace clhair
