// env_stage.h — binds the environment kernels of kernels/env.cl (Environment,
// host/lighting/environment.h, owns the buffers and decides the levels): the procedural
// sky into the source pyramid's level 0, the pyramid's 2x2 downsampling, one GGX-
// prefiltered level, and the order-2 SH projection (per-row partial sums, then a
// fixed-order sum per coefficient).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cl/dispatch.h"
#include "clhair/gpu_env.h"

namespace clhair {

class EnvStage {
 public:
  // The kernels built with the environment's defines (Environment::kernelDefines);
  // `workGroup` the work-group size they were built for.
  EnvStage(Device::Impl& dev, const std::string& defines, std::size_t workGroup);

  // The source pyramid: its texels, count and levels (on the host and on the device).
  struct Pyramid {
    cl::Buffer* texels = nullptr;
    std::uint32_t count = 0;
    const std::vector<gpu::ClhEnvLevel>* levels = nullptr;
    const cl::Buffer* table = nullptr;
  };
  // How the map is turned and scaled in the lookups (rotation about +y).
  struct Turn {
    float cos = 1.0f, sin = 0.0f, intensity = 1.0f;
  };

  void sky(const cl::Buffer& params, const Pyramid& p, Profiler* profiler);
  // Levels 1.. of the pyramid from level 0.
  void downsample(const Pyramid& p, Profiler* profiler);
  // Level `lv` of the prefiltered texels `out` (`outCount` texels in all).
  void prefilter(const Pyramid& p, const gpu::ClhEnvLevel& lv, std::uint32_t samples,
                 cl::Buffer& out, std::uint32_t outCount, const Turn& t, Profiler* profiler);
  // The SH coefficients (CLH_ENV_SH_FLOATS) of level 0 into `sh`, through `rows`
  // (level 0's height x CLH_ENV_SH_FLOATS floats).
  void sh(const Pyramid& p, cl::Buffer& rows, cl::Buffer& sh, const Turn& t, Profiler* profiler);

 private:
  std::uint64_t bytes(const Pyramid& p) const { return std::uint64_t(p.count) * 4 * sizeof(float); }

  Device::Impl& dev_;
  std::size_t wg_;
  cl::Kernel sky_, down_, pre_, shRows_, shReduce_;
};

}  // namespace clhair
