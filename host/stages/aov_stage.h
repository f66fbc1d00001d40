// aov_stage.h — binds and launches kernels/aov.cl: the planes of the layers for compositing
// (Frame::aovs) started from the opaque depth, then folded groom by groom after each
// composite, on the device, so a frame with AOVs reads back its planes once at its end.
#pragma once

#include <cstdint>

#include "cl/dispatch.h"

namespace clhair {

class AovStage {
 public:
  explicit AovStage(Device::Impl& dev) : dev_(dev) {}
  // The planes, `pixels` entries each.
  struct Planes {
    const cl::Buffer* lastDepth = nullptr;    // float: depth after the last groom
    const cl::Buffer* owner = nullptr;        // int: groom owning the depth, -1: opaque
    const cl::Buffer* ownerMotion = nullptr;  // ulong: its motion-pass word (all ones: none)
    const cl::Buffer* alpha = nullptr;        // float: 1 - prod(1 - a_k)
    const cl::Buffer* hair = nullptr;         // float4: the grooms' premultiplied RGBA
    const cl::Buffer* centreZ = nullptr;      // float: depth of the nearest centre word
    const cl::Buffer* tangent = nullptr;      // float4: its tangent (xyz)
    const cl::Buffer* strand = nullptr;       // float4: groom, strand, u (-1: none)
  };
  void begin(const cl::Buffer& opaqueDepth, std::size_t pixels, const Planes& p,
             Profiler* profiler);
  struct Groom {
    const cl::Buffer* groom = nullptr;    // ClhGroomGpu (its depth mapping)
    std::uint32_t index = 0;              // in Scene::grooms
    const cl::Buffer* gbuffer = nullptr;  // its layers
    int samples = 1;                      // centre sample layers
    bool ids = false;                     // the identity layer (CLH_LAYER_ID) is written
    std::size_t layers = 2;               // layers of gbuffer
    const cl::Buffer* result = nullptr;   // float4: the hair its composite blended
    const cl::Buffer* depth = nullptr;    // float: the depth after its composite
    const cl::Buffer* motion = nullptr;   // ulong: its motion plane, or null
  };
  void groom(const Groom& g, std::size_t pixels, const Planes& p, Profiler* profiler);

 private:
  Device::Impl& dev_;
  cl::Kernel begin_, groom_;
};

}  // namespace clhair
