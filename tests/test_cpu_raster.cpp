// test_cpu_raster.cpp — the benchmark's CPU floor (host/groom/cpu_raster.h) against the
// device's stored-strand raster, word for word.
//
// Both compile the same segment code (kernels/include/clhair/raster_core.h) without float
// contraction, so on a device that rounds like the host's IEEE single precision (PoCL's
// CPU device: correctly rounded division and sqrt) every G-buffer word must be equal.
// The tests' synthetic groom (point counts across the kernel's round boundaries) partly
// behind an opaque sphere (so the depth test matters), at a frame size that is not a
// multiple of any work-group size.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/geometric.hpp>

#include "clhair/renderer.h"
#include "clhair/strand_groom.h"
#include "groom/cpu_raster.h"
#include "groom/explicit_data.h"
#include "synthetic_groom.h"
#include "test_util.h"

namespace clhair {
namespace {

TEST(CpuRaster, FloorEqualsDeviceGBufferWordForWord) {
  Device& dev = test::sharedDevice();
  Renderer r(dev);
  auto groom = std::make_shared<const StrandGroom>(test::syntheticGroom(3001));
  Scene s;
  s.width = 333;
  s.height = 217;
  s.spheres.push_back({glm::vec3(0.0f), 0.093f, glm::vec3(0.5f)});
  s.grooms.push_back(GroomInstance("waves", groom));
  s.camera = framePreset(s, CameraPreset::Close, 30.0f);
  RenderOptions o;
  o.lod = Toggle::Off;
  o.filter = Toggle::Off;
  o.msaa = 1;
  o.captureGBuffer = true;
  const Frame f = r.render(s, o);
  ASSERT_EQ(f.gbufferLayers, 2);
  ASSERT_FALSE(f.rasterGroom.empty());

  const ExplicitData data = prepareExplicit(*groom);
  const CpuRasterInputs in = cpuRasterInputs(f, data);
  std::vector<std::uint64_t> cpu;
  cpuRasterExplicit(in, 2, cpu);
  ASSERT_EQ(cpu.size(), f.gbuffer.size());

  std::size_t differ = 0, hits = 0, occluded = 0, firstDiff = cpu.size();
  const std::size_t pixels = f.gbuffer.size() / 2;
  for (std::size_t i = 0; i < cpu.size(); ++i) {
    hits += cpu[i] != ~std::uint64_t(0);
    if (cpu[i] != f.gbuffer[i]) {
      ++differ;
      firstDiff = std::min(firstDiff, i);
    }
  }
  for (std::size_t i = 0; i < pixels; ++i) occluded += f.rasterDepth[i] < 1e6f;
  EXPECT_GT(hits, pixels / 20) << "the groom should cover a good part of the frame";
  EXPECT_GT(occluded, pixels / 50) << "the sphere should be in view, so the depth test matters";
  EXPECT_EQ(differ, 0u) << "first differing word " << firstDiff << ": device "
                        << (firstDiff < cpu.size() ? f.gbuffer[firstDiff] : 0) << ", CPU "
                        << (firstDiff < cpu.size() ? cpu[firstDiff] : 0) << " on "
                        << dev.info().name;
}

}  // namespace
}  // namespace clhair
