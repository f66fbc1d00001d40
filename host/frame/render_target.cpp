// render_target.cpp — see render_target.h.
#include "frame/render_target.h"

#include "cl/buffers.h"
#include "clhair/scene.h"

#include <algorithm>

namespace clhair {

RenderTarget::RenderTarget(Device::Impl& dev) : dev_(dev), clear_(dev) {
  view = makeBuffer<gpu::ClhViewGpu>(dev, "view parameters", 1);
  stats = makeBuffer<cl_uint>(dev, "raster statistics", 4);
  motionParams = makeBuffer<gpu::ClhMotionGpu>(dev, "motion parameters", 1);
}

void RenderTarget::ensure(int w, int h, int msaa) {
  if (w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide)
    throw Error("resolution " + std::to_string(w) + "x" + std::to_string(h) + " is outside 1.." +
                std::to_string(kMaxImageSide) + " per side");
  if (msaa != 1 && msaa != 2 && msaa != 4 && msaa != 8)
    throw Error("MSAA must be 1, 2, 4 or 8 samples, not " + std::to_string(msaa));
  const std::size_t n = static_cast<std::size_t>(w) * h;
  const std::string res = std::to_string(w) + "x" + std::to_string(h);
  if (w != width_ || h != height_) {
    color = makeBuffer<cl_float4>(dev_, "the " + res + " colour target", n);
    depth = makeBuffer<cl_float>(dev_, "the " + res + " depth target", n);
    layers_ = 0;
  }
  // the identity and linking layers a groom asked for (useLayers) stay while the size and
  // sample count do
  if (layers_ < msaa + 1 || msaa != msaa_) {
    gbuffer = makeBuffer<cl_ulong>(
        dev_, "the " + res + " G-buffer with " + std::to_string(msaa + 1) + " layers",
        n * static_cast<std::size_t>(msaa + 1));
    layers_ = msaa + 1;
    cleanLayers_ = 0;
  }
  width_ = w;
  height_ = h;
  used_ = msaa + 1;
  msaa_ = msaa;
}

void RenderTarget::useLayers(int layers) {
  layers = std::max(layers, msaa_ + 1);
  if (layers > layers_) {
    const std::string res = std::to_string(width_) + "x" + std::to_string(height_);
    gbuffer = makeBuffer<cl_ulong>(
        dev_, "the " + res + " G-buffer with " + std::to_string(layers) + " layers",
        pixels() * static_cast<std::size_t>(layers));
    layers_ = layers;
    cleanLayers_ = 0;
  }
  used_ = layers;
}

void RenderTarget::clearWords(const cl::Buffer& buffer, std::size_t count, Profiler* profiler) {
  clear_.words(buffer, count, ~std::uint64_t(0), "clear", profiler);
}

void RenderTarget::clearUints(const cl::Buffer& buffer, std::size_t count, Profiler* profiler) {
  clear_.uints(buffer, count, 0u, "clear", profiler);
}

void RenderTarget::copyUints(const cl::Buffer& src, std::size_t srcFirst, const cl::Buffer& dst,
                             std::size_t dstFirst, std::size_t count, Profiler* profiler) {
  clear_.copyUints(src, srcFirst, dst, dstFirst, count, "statistics", profiler);
}

void RenderTarget::clearGBuffer(const PixelRect& box, Profiler* profiler) {
  const PixelRect whole{0, 0, width_, height_};
  if (used_ > cleanLayers_ || dirty_.clipped(width_, height_) == whole) {
    clear_.words(gbuffer, pixels() * static_cast<std::size_t>(used_), ~std::uint64_t(0), "clear",
                 profiler);
    cleanLayers_ = used_;
  } else {
    clear_.box(gbuffer, width_, height_, cleanLayers_, dirty_, ~std::uint64_t(0), "clear",
               profiler);
  }
  dirty_ = box.clipped(width_, height_);
}

}  // namespace clhair
