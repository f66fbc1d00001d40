// point_stage.cpp — see point_stage.h.
#include "stages/point_stage.h"

#include <algorithm>
#include <string>

#include "clhair/gpu_types.h"

namespace clhair {

namespace {
// points_scan's one work-group (kernels/points.cl, CLH_POINT_SCAN_WG)
constexpr std::size_t kScanGroup = 256;
}  // namespace

PointStage::PointStage(Device::Impl& dev) : dev_(dev), clear_(dev) {}

std::uint64_t PointStage::Sizes::recordsBytes() const {
  return (std::uint64_t(capacity) + 1) * sizeof(gpu::ClhPointGpu);
}

PointStage::Sizes PointStage::sizes(std::uint64_t space, std::size_t boxPixels, int msaa) {
  // the identity word's point field is 32 bits, and point + 1 must fit too
  if (space + 2 > 0xFFFFFFFFull)
    throw Error("per-point shading: the groom has " + std::to_string(space) +
                " points, more than the sample identity's 32 bits hold");
  Sizes s;
  s.words = gpu::clh_point_words(static_cast<std::uint32_t>(space));
  s.blocks = (s.words + CLH_POINT_BLOCK - 1) / CLH_POINT_BLOCK;
  const std::uint64_t perSamples = std::uint64_t(boxPixels) * std::uint64_t(msaa) * 2u;
  s.capacity = static_cast<std::uint32_t>(std::min<std::uint64_t>(space, perSamples));
  return s;
}

cl::Kernel& PointStage::kernel(const char* name, int msaa) {
  auto it = kernels_.find({name, msaa});
  if (it != kernels_.end()) return it->second;
  return kernels_[{name, msaa}] =
             dev_.kernel("points.cl", name, "-DCLH_MSAA=" + std::to_string(msaa));
}

void PointStage::mark(const ViewTarget& target, const cl::Buffer& gbuffer, int layers, int msaa,
                      const PixelRect& box, const Lists& lists, Profiler* profiler) {
  if (layers < 2 * msaa + 1)
    throw Error("per-point shading: the G-buffer has " + std::to_string(layers) +
                " layers, the sample identities need " + std::to_string(2 * msaa + 1));
  clear_.uints(*lists.bits, lists.sizes.words, 0u, "points", profiler);
  cl::Kernel& k = kernel("points_mark", msaa);
  const PixelRect b = box.clipped(target.width, target.height);
  KernelArgs(k, "points")
      .buffer("G-buffer", gbuffer,
              target.pixels() * static_cast<std::uint64_t>(layers) * sizeof(cl_ulong))
      .value("width", static_cast<cl_uint>(target.width))
      .value("height", static_cast<cl_uint>(target.height))
      .value("box", b.arg())
      .buffer("marked points", *lists.bits, lists.sizes.bitsBytes())
      .value("point words", static_cast<cl_uint>(lists.sizes.words));
  dispatchBox(dev_, k, "points", b, profiler);
}

void PointStage::rank(const Lists& lists, Profiler* profiler) {
  const Sizes& s = lists.sizes;
  cl::Kernel& count = kernel("points_count", 1);
  KernelArgs(count, "points")
      .buffer("marked points", *lists.bits, s.bitsBytes())
      .value("point words", static_cast<cl_uint>(s.words))
      .buffer("block counts", *lists.blocks, s.blocksBytes())
      .value("blocks", static_cast<cl_uint>(s.blocks));
  dispatch(dev_, count, "points", cl::NDRange(s.blocks), cl::NDRange(64), profiler);
  cl::Kernel& scan = kernel("points_scan", 1);
  KernelArgs(scan, "points")
      .buffer("block counts", *lists.blocks, s.blocksBytes())
      .value("blocks", static_cast<cl_uint>(s.blocks));
  dispatch(dev_, scan, "points", cl::NDRange(kScanGroup), cl::NDRange(kScanGroup), profiler);
  cl::Kernel& ranks = kernel("points_offsets", 1);
  KernelArgs(ranks, "points")
      .buffer("marked points", *lists.bits, s.bitsBytes())
      .value("point words", static_cast<cl_uint>(s.words))
      .buffer("block counts", *lists.blocks, s.blocksBytes())
      .value("blocks", static_cast<cl_uint>(s.blocks))
      .buffer("point ranks", *lists.offsets, s.offsetsBytes());
  dispatch(dev_, ranks, "points", cl::NDRange(s.blocks), cl::NDRange(64), profiler);
}

void PointStage::resolve(const ViewTarget& target, const cl::Buffer& gbuffer, int layers, int msaa,
                         const PixelRect& box, const Lists& lists, cl::Buffer& hair,
                         Profiler* profiler) {
  cl::Kernel& k = kernel("points_resolve", msaa);
  const PixelRect b = box.clipped(target.width, target.height);
  const Sizes& s = lists.sizes;
  KernelArgs(k, "shade")
      .buffer("view", *target.view, sizeof(gpu::ClhViewGpu))
      .buffer("G-buffer", gbuffer,
              target.pixels() * static_cast<std::uint64_t>(layers) * sizeof(cl_ulong))
      .buffer("marked points", *lists.bits, s.bitsBytes())
      .buffer("point ranks", *lists.offsets, s.offsetsBytes())
      .value("point words", static_cast<cl_uint>(s.words))
      .buffer("point colours", *lists.colors, s.colorsBytes())
      .value("point capacity", static_cast<cl_uint>(s.capacity))
      .buffer("hair colour", hair, target.pixels() * 4 * sizeof(float))
      .value("box", b.arg());
  dispatchBox(dev_, k, "shade", b, profiler);
}

}  // namespace clhair
