// clear_stage.cpp — see clear_stage.h.
#include "stages/clear_stage.h"

namespace clhair {

ClearStage::ClearStage(Device::Impl& dev)
    : dev_(dev), kernel_(dev.kernel("clear.cl", "clear_words")) {}

void ClearStage::words(const cl::Buffer& buffer, std::size_t count, std::uint64_t value,
                       const std::string& stage, Profiler* profiler) {
  KernelArgs(kernel_, stage)
      .buffer("words", buffer, count * sizeof(cl_ulong))
      .value("value", static_cast<cl_ulong>(value))
      .value("count", static_cast<cl_ulong>(count));
  dispatch(dev_, kernel_, stage, cl::NDRange(count), cl::NDRange(256), profiler);
}

}  // namespace clhair
