// cryptomatte_stage.cpp — see cryptomatte_stage.h.
#include "stages/cryptomatte_stage.h"

#include "clhair/cryptomatte.h"
#include "clhair/gpu_types.h"

namespace clhair {

std::size_t CryptomatteStage::keyBytes(std::size_t pixels) {
  return pixels * kCryptomatteRanks * sizeof(cl_ulong);
}

std::size_t CryptomatteStage::coverageBytes(std::size_t pixels) {
  return pixels * kCryptomatteRanks * sizeof(float);
}

void CryptomatteStage::enqueue(const Params& p, Profiler* profiler) {
  if (!kernel_())
    kernel_ = dev_.kernel("cryptomatte.cl", "cryptomatte_groom",
                          "-DCRYPTO_RANKS=" + std::to_string(kCryptomatteRanks));
  if (p.layers <= CLH_LAYER_ID)
    throw Error("cryptomatte: the groom's G-buffer has " + std::to_string(p.layers) +
                " layers, without the strand identity layer (" + std::to_string(CLH_LAYER_ID + 1) +
                " needed)");
  const std::uint64_t n = std::uint64_t(p.width) * p.height;
  KernelArgs(kernel_, "cryptomatte")
      .value("width", static_cast<cl_uint>(p.width))
      .value("height", static_cast<cl_uint>(p.height))
      .value("first", static_cast<cl_uint>(p.first ? 1 : 0))
      .value("groom key", static_cast<cl_uint>(p.groomKey))
      .buffer("hair result", *p.result, n * 16)
      .buffer("G-buffer", *p.gbuffer, n * p.layers * 8)
      .buffer("groom keys", *p.groomKeys, keyBytes(n))
      .buffer("groom coverage", *p.groomCoverage, coverageBytes(n))
      .buffer("strand keys", *p.strandKeys, keyBytes(n))
      .buffer("strand coverage", *p.strandCoverage, coverageBytes(n));
  dispatch(dev_, kernel_, "cryptomatte", cl::NDRange(p.width, p.height), cl::NDRange(8, 8),
           profiler);
}

}  // namespace clhair
