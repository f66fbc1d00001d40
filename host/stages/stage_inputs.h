// stage_inputs.h — named groups of device buffers several stages read: the view a pass
// draws into, the scene's lighting (lights, deep opacity maps, environment) and helpers
// that bind them in the order the kernels declare them, with their sizes checked.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>

#include "cl/dispatch.h"
#include "clhair/gpu_env.h"
#include "clhair/gpu_types.h"

namespace clhair {

// A view and the size of the target it covers (ClhViewGpu; the kernels read the size
// from the record, the host sizes the launch and checks the target buffers with it).
struct ViewTarget {
  const cl::Buffer* view = nullptr;
  int width = 0, height = 0;
  std::size_t pixels() const {
    return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  }
};

// A box of pixels [x0, x1) x [y0, y1) of a target: the screen box of a groom
// (stages/view_math.h, screenBox), over which the passes that only concern that groom's
// pixels run (hair linking and Huang's filter, the bounded compositing, the G-buffer
// clears). The default holds every pixel of any target.
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = kAll, y1 = kAll;
  static constexpr int kAll = 1 << 30;
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  int width() const { return empty() ? 0 : x1 - x0; }
  int height() const { return empty() ? 0 : y1 - y0; }
  std::size_t pixels() const {
    return static_cast<std::size_t>(width()) * static_cast<std::size_t>(height());
  }
  // `m` more pixels on every side (no more than the default box holds)
  PixelRect grown(int m) const {
    auto clampSide = [](long long v) {
      return static_cast<int>(std::max<long long>(-kAll, std::min<long long>(kAll, v)));
    };
    return {clampSide(static_cast<long long>(x0) - m), clampSide(static_cast<long long>(y0) - m),
            clampSide(static_cast<long long>(x1) + m), clampSide(static_cast<long long>(y1) + m)};
  }
  // the part inside a width x height image
  PixelRect clipped(int width, int height) const {
    return {std::max(x0, 0), std::max(y0, 0), std::min(x1, width), std::min(y1, height)};
  }
  // the smallest box holding both
  PixelRect united(const PixelRect& o) const {
    if (o.empty()) return *this;
    if (empty()) return o;
    return {std::min(x0, o.x0), std::min(y0, o.y0), std::max(x1, o.x1), std::max(y1, o.y1)};
  }
  // the kernels' int4 `box` argument (kernels/common/clh_math.h, clh_box_pixel)
  cl_int4 arg() const { return cl_int4{{x0, y0, x1, y1}}; }
  bool operator==(const PixelRect& o) const {
    return x0 == o.x0 && y0 == o.y0 && x1 == o.x1 && y1 == o.y1;
  }
};

// A 2D launch over `box` (already clipped to the target) in 8x8 work-groups, for a kernel
// whose int4 `box` argument (set by the caller) is box.arg(); nothing when it is empty.
inline cl::Event dispatchBox(Device::Impl& dev, cl::Kernel& kernel, const std::string& stage,
                             const PixelRect& box, Profiler* profiler) {
  if (box.empty()) return cl::Event();
  return dispatch(
      dev, kernel, stage,
      cl::NDRange(static_cast<std::size_t>(box.width()), static_cast<std::size_t>(box.height())),
      cl::NDRange(8, 8), profiler);
}

// The deep opacity maps of every shadowed light (ShadowMaps): one ClhShadowGpu per slot
// and the texel planes of all CLH_MAX_SHADOWS slots, `texels` per slot.
struct ShadowMapInputs {
  const cl::Buffer* params = nullptr;       // ClhShadowGpu[CLH_MAX_SHADOWS]
  const cl::Buffer* opaqueDepth = nullptr;  // float per texel
  const cl::Buffer* hairDepth = nullptr;    // float per texel
  const cl::Buffer* opacity = nullptr;      // uint per texel and layer
  std::size_t texels = 0;
};

// The prefiltered environment (host/lighting/environment.h) or placeholders.
struct EnvironmentInputs {
  const cl::Buffer* texels = nullptr;  // float4
  const cl::Buffer* levels = nullptr;  // ClhEnvLevel[]
  const cl::Buffer* sh = nullptr;      // CLH_ENV_SH_FLOATS floats
};

struct LightingInputs {
  const cl::Buffer* scene = nullptr;   // ClhSceneGpu
  const cl::Buffer* lights = nullptr;  // ClhLightGpu[lightCount]
  std::uint32_t lightCount = 0;
  ShadowMapInputs shadows;
  EnvironmentInputs env;
};

// Binds lights, shadow parameters and the three map planes (the order every shading
// kernel declares them in).
inline void bindLightsAndShadows(KernelArgs& a, const LightingInputs& l) {
  const std::uint64_t slots = CLH_MAX_SHADOWS, texels = l.shadows.texels;
  a.buffer("lights", *l.lights, l.lightCount * sizeof(gpu::ClhLightGpu))
      .buffer("shadow parameters", *l.shadows.params, slots * sizeof(gpu::ClhShadowGpu))
      .buffer("shadow opaque depth", *l.shadows.opaqueDepth, slots * texels * sizeof(float))
      .buffer("shadow hair depth", *l.shadows.hairDepth, slots * texels * sizeof(float))
      .buffer("shadow opacity", *l.shadows.opacity,
              slots * texels * CLH_DOM_LAYERS * sizeof(std::uint32_t));
}

inline void bindEnvironment(KernelArgs& a, const EnvironmentInputs& e) {
  a.buffer("environment texels", *e.texels, 4 * sizeof(float))
      .buffer("environment levels", *e.levels, sizeof(gpu::ClhEnvLevel))
      .buffer("environment SH", *e.sh, CLH_ENV_SH_FLOATS * sizeof(float));
}

}  // namespace clhair
