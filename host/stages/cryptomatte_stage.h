// cryptomatte_stage.h — binds and launches kernels/cryptomatte.cl: one groom's hair folded
// into the ranked (key, coverage) lists of the Cryptomatte layers (clhair/cryptomatte.h),
// after its composite, so a frame reads the lists back once at its end.
#pragma once

#include <cstdint>

#include "cl/dispatch.h"

namespace clhair {

class CryptomatteStage {
 public:
  explicit CryptomatteStage(Device::Impl& dev) : dev_(dev) {}
  // Bytes of one layer's keys (ulong) and coverages (float): kCryptomatteRanks per pixel.
  static std::size_t keyBytes(std::size_t pixels);
  static std::size_t coverageBytes(std::size_t pixels);
  struct Params {
    std::uint32_t width = 0, height = 0;
    bool first = false;                   // the frame's first groom drawn: the lists start here
    std::uint32_t groomKey = 0;           // the groom's key (one per name)
    const cl::Buffer* result = nullptr;   // float4: the hair its composite blended
    const cl::Buffer* gbuffer = nullptr;  // its layers, the identity layer among them
    std::size_t layers = 0;               // layers of gbuffer (> CLH_LAYER_ID)
    const cl::Buffer *groomKeys = nullptr, *groomCoverage = nullptr;
    const cl::Buffer *strandKeys = nullptr, *strandCoverage = nullptr;
  };
  void enqueue(const Params& p, Profiler* profiler);

 private:
  Device::Impl& dev_;
  cl::Kernel kernel_;
};

}  // namespace clhair
