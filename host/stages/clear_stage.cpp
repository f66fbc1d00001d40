// clear_stage.cpp — see clear_stage.h.
#include "stages/clear_stage.h"

namespace clhair {

ClearStage::ClearStage(Device::Impl& dev)
    : dev_(dev),
      kernel_(dev.kernel("clear.cl", "clear_words")),
      box_(dev.kernel("clear.cl", "clear_box")),
      uints_(dev.kernel("clear.cl", "clear_uints")),
      copy_(dev.kernel("clear.cl", "copy_uints")) {}

void ClearStage::words(const cl::Buffer& buffer, std::size_t count, std::uint64_t value,
                       const std::string& stage, Profiler* profiler) {
  KernelArgs(kernel_, stage)
      .buffer("words", buffer, count * sizeof(cl_ulong))
      .value("value", static_cast<cl_ulong>(value))
      .value("count", static_cast<cl_ulong>(count));
  dispatch(dev_, kernel_, stage, cl::NDRange(count), cl::NDRange(256), profiler);
}

void ClearStage::uints(const cl::Buffer& buffer, std::size_t count, std::uint32_t value,
                       const std::string& stage, Profiler* profiler) {
  if (count == 0) return;
  KernelArgs(uints_, stage)
      .buffer("words", buffer, count * sizeof(cl_uint))
      .value("value", static_cast<cl_uint>(value))
      .value("count", static_cast<cl_ulong>(count));
  dispatch(dev_, uints_, stage, cl::NDRange(count), cl::NDRange(256), profiler);
}

void ClearStage::copyUints(const cl::Buffer& src, std::size_t srcFirst, const cl::Buffer& dst,
                           std::size_t dstFirst, std::size_t count, const std::string& stage,
                           Profiler* profiler) {
  if (count == 0) return;
  KernelArgs(copy_, stage)
      .buffer("source", src, (srcFirst + count) * sizeof(cl_uint))
      .value("source first", static_cast<cl_ulong>(srcFirst))
      .buffer("destination", dst, (dstFirst + count) * sizeof(cl_uint))
      .value("destination first", static_cast<cl_ulong>(dstFirst))
      .value("count", static_cast<cl_ulong>(count));
  dispatch(dev_, copy_, stage, cl::NDRange(count), cl::NDRange(64), profiler);
}

void ClearStage::box(const cl::Buffer& buffer, int width, int height, int layers,
                     const PixelRect& box, std::uint64_t value, const std::string& stage,
                     Profiler* profiler) {
  const PixelRect b = box.clipped(width, height);
  if (b.empty() || layers < 1) return;
  KernelArgs(box_, stage)
      .buffer(
          "words", buffer,
          std::uint64_t(width) * std::uint64_t(height) * std::uint64_t(layers) * sizeof(cl_ulong))
      .value("value", static_cast<cl_ulong>(value))
      .value("width", static_cast<cl_int>(width))
      .value("height", static_cast<cl_int>(height))
      .value("layers", static_cast<cl_uint>(layers))
      .value("box", b.arg());
  dispatchBox(dev_, box_, stage, b, profiler);
}

}  // namespace clhair
