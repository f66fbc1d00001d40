// environment.h — environment ("probe") lighting for hair, built on the device at load.
//
// Lipp et al. 2026 §3.4 light hair with a pre-filtered environment map for the specular
// lobes (R and TRT, each approximated by one GGX lobe) and 9-coefficient SH irradiance
// (Ramamoorthi & Hanrahan 2001) for the diffuse part. An Environment takes an
// equirectangular radiance map (an image file, an Image, or the procedural sky of
// SkyParams), runs kernels/env.cl once — source pyramid, one GGX prefilter dispatch per
// roughness level, SH projection and deterministic reduction — and keeps the results on
// the device for the shading pass (kernels/common/env_lookup.h):
//   texels()  float4 texels of all prefiltered levels, one buffer
//   levels()  ClhEnvLevel[levelCount()] (gpu_env.h), GGX alpha increasing
//   sh()      27 floats: radiance SH coefficients L_lm, RGB interleaved
// Conventions (direction <-> (u, v), SH order, rotation) are in kernels/include/clhair/gpu_env.h
// and docs/environment-lighting.md. Inputs are validated before anything is uploaded;
// every failure is a one-line clhair::Error. The build is deterministic: the same input
// gives bit-identical buffers on the same device.
#pragma once

#include <array>
#include <cstdint>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "cl/dispatch.h"
#include "clhair/gpu_env.h"
#include "clhair/image.h"
#include "clhair/scene.h"

namespace clhair {

// SkyParams (the procedural default sky) is public: include/clhair/scene.h.

class Environment {
 public:
  struct Options {
    float intensity = 1.0f;       // scales radiance and irradiance, finite, >= 0
    float rotateYDegrees = 0.0f;  // source direction s appears at world R_y(angle) s
    int levels = 7;               // prefiltered levels, [1, CLH_ENV_MAX_LEVELS]
    float minRoughness = 0.05f;   // GGX alpha of level 0
    float maxRoughness = 1.0f;    // GGX alpha of the last level; levels are geometric between
    int baseWidth = 512;  // level-0 width cap; actual: largest power of two <= min(cap, source)
    int minWidth = 32;    // levels halve down to this width
    int samples = 512;    // GGX samples per texel for alpha >= 0.25, [16, 1024]; a quarter
                          // below 0.25, a sixteenth below 0.1 (min 16); a -D of env.cl
  };

  static constexpr int kMaxSourceWidth = 8192;  // larger maps: downscale first
  static constexpr int kMinSourceWidth = 8;
  // Texels above this after scaling would overflow the float sums of the prefilter.
  static constexpr float kMaxRadiance = 1e9f;

  // Reads an equirectangular EXR/HDR (or any OpenImageIO format, 8-bit treated as sRGB).
  static Environment fromFile(Device::Impl& dev, const std::string& path, const Options& options,
                              Profiler* profiler = nullptr);
  // `what` names the source in error messages (a file name, "scene.json: environment").
  static Environment fromImage(Device::Impl& dev, const Image& image, const Options& options,
                               const std::string& what, Profiler* profiler = nullptr);
  static Environment fromSky(Device::Impl& dev, const SkyParams& sky, const Options& options,
                             Profiler* profiler = nullptr);

  // The -D options env.cl is built with for `options` (tests reuse them to share the
  // compiled program for env_query).
  static std::string kernelDefines(const Options& options);
  // Throws clhair::Error for options / sky parameters out of range (called by the above).
  static void validate(const Options& options, const std::string& what);
  static void validate(const SkyParams& sky, const std::string& what);

  // ---- for the shading pass (arguments of clh_env_radiance / clh_env_irradiance) ----
  const cl::Buffer& texels() const { return texels_; }
  const cl::Buffer& levels() const { return levels_; }
  const cl::Buffer& sh() const { return sh_; }
  std::uint32_t levelCount() const { return static_cast<std::uint32_t>(levelTable_.size()); }

  // ---- host-side copies and facts ----
  const std::vector<gpu::ClhEnvLevel>& levelTable() const { return levelTable_; }
  std::size_t texelCount() const { return texelCount_; }
  const std::array<float, CLH_ENV_SH_FLOATS>& shCoefficients() const { return shCpu_; }
  // E(n) from the CPU copy of the coefficients (same formula as the device; no 1/pi).
  glm::vec3 irradiance(const glm::vec3& n) const;
  int sourceWidth() const { return sourceWidth_; }
  int sourceHeight() const { return sourceHeight_; }
  double loadMs() const { return loadMs_; }  // wall-clock time of the device build
  // Downloads every prefiltered level (4 floats per texel, offsets of levelTable()).
  std::vector<float> downloadTexels(Device::Impl& dev) const;

 private:
  Environment() = default;
  // Exactly one of `rgba` (width * height * 4 floats, validated) and `sky` is non-null.
  static Environment build(Device::Impl& dev, const std::vector<float>* rgba, const SkyParams* sky,
                           int width, const Options& options, const std::string& what,
                           Profiler* profiler);
  static Environment buildOnDevice(Device::Impl& dev, const std::vector<float>* rgba,
                                   const SkyParams* sky, int width, const Options& options,
                                   const std::string& what, Profiler* profiler);

  cl::Buffer texels_, levels_, sh_;
  std::vector<gpu::ClhEnvLevel> levelTable_;
  std::size_t texelCount_ = 0;
  std::array<float, CLH_ENV_SH_FLOATS> shCpu_{};
  int sourceWidth_ = 0, sourceHeight_ = 0;
  double loadMs_ = 0.0;
};

}  // namespace clhair
