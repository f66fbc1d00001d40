// cpu_raster.h — the stored-strand raster pass as plain multithreaded C++: the benchmark's
// in-run floor and a word-for-word check of the device kernel.
//
// It does exactly the work of strands_explicit_raster with LOD off and MSAA 1: every
// stored strand, tangents by central differences with Bhokare's end rule, the same
// projection, walk, hit rule, G-buffer word, depth test and load skip — by compiling the
// same code (kernels/include/clhair/raster_core.h) — with a compare-and-swap loop for the 64-bit
// atomic minimum. Threads take blocks of strands from a shared counter.
#pragma once

#include <cstdint>
#include <vector>

#include "clhair/renderer.h"
#include "groom/explicit_data.h"

namespace clhair {

struct CpuRasterInputs {
  const std::uint8_t* groom = nullptr;  // ClhGroomGpu bytes (Frame::rasterGroom)
  const std::uint8_t* view = nullptr;   // ClhViewGpu bytes (Frame::rasterView)
  const float* sceneDepth = nullptr;    // width * height (Frame::rasterDepth)
  const ExplicitData* strands = nullptr;
};

// The inputs a frame rendered with RenderOptions::captureGBuffer recorded, with the
// groom's stored strands (both must outlive the result).
CpuRasterInputs cpuRasterInputs(const Frame& frame, const ExplicitData& strands);

// Clears `gbuffer` to two layers (centre, conservative) of width * height empty words and
// draws every strand with `threads` threads (0: hardware concurrency).
void cpuRasterExplicit(const CpuRasterInputs& in, unsigned threads,
                       std::vector<std::uint64_t>& gbuffer);

}  // namespace clhair
