// stage_inputs.h — named groups of device buffers several stages read: the view a pass
// draws into, the scene's lighting (lights, deep opacity maps, environment) and helpers
// that bind them in the order the kernels declare them, with their sizes checked.
#pragma once

#include <cstdint>

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

// The deep opacity maps of every shadowed light (ShadowPass): one ClhShadowGpu per slot
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
