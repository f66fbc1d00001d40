// float_frames.h — frames rendered in separate processes with different CPU thread counts,
// compared bit for bit as 32-bit floats (colour, alpha and depth as the renderer returned
// them; tests/render_float.cpp writes them), on every OpenCL device with 64-bit atomics
// whose runtime lets a variable set its thread count:
//   PoCL                      POCL_MAX_PTHREAD_COUNT
//   Intel's CPU runtime       SYCL_CPU_NUM_CUS (and its older name DPCPP_CPU_NUM_CUS, set too)
// Other devices are listed as not compared; with none compared the test is skipped.
#pragma once

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "clhair/device.h"
#include "test_util.h"

namespace clhair::test {

inline std::string renderFloatPath() {
  return envOr("CLHAIR_RENDER_FLOAT", CLHAIR_TEST_RENDER_FLOAT);
}

// The variables that set the number of threads `d`'s runtime runs work-groups on (none:
// not known).
inline std::vector<std::string> threadCountVariables(const DeviceInfo& d) {
  if (d.platformName.find("Portable Computing Language") != std::string::npos)
    return {"POCL_MAX_PTHREAD_COUNT"};
  if (!d.isGpu && d.platformName.find("Intel(R) OpenCL") != std::string::npos)
    return {"SYCL_CPU_NUM_CUS", "DPCPP_CPU_NUM_CUS"};
  return {};
}

// The R, G, B, A, Z floats of an EXR written by clhair_render_float; empty on failure.
inline std::vector<float> readFloatFrame(const std::string& path, int* width, int* height) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    ADD_FAILURE() << path << ": " << OIIO::geterror();
    return {};
  }
  const OIIO::ImageSpec spec = in->spec();
  EXPECT_EQ(spec.nchannels, 5) << path;
  EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT) << path << " is not stored as 32-bit floats";
  std::vector<float> v(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, v.data())) {
    ADD_FAILURE() << path << ": " << in->geterror();
    return {};
  }
  *width = spec.width;
  *height = spec.height;
  return v;
}

// Renders `scene` with each of `threads` on every device that allows it and expects the
// frames of one device to be identical bit for bit.
inline void expectBitIdenticalAcrossThreadCounts(const std::string& scene, const std::string& dir,
                                                 const std::vector<int>& threads = {1, 2, 3}) {
  useTestEnvironment();
  std::string compared, notCompared;
  for (const DeviceInfo& d : Device::list()) {
    if (!d.int64Atomics) continue;
    const std::string device =
        std::to_string(d.platformIndex) + ":" + std::to_string(d.deviceIndex);
    const std::vector<std::string> variables = threadCountVariables(d);
    const std::string variable = variables.empty() ? "" : variables.front();
    if (variables.empty()) {
      notCompared += "\n  " + d.name + " (" + d.platformName + "): no known thread-count variable";
      continue;
    }
    std::vector<float> first;
    int width = 0, height = 0;
    for (int t : threads) {
      const std::string out = dir + "/frame-" + std::to_string(d.platformIndex) + "-" +
                              std::to_string(d.deviceIndex) + "-t" + std::to_string(t) + ".exr";
      std::string env;
      for (const std::string& v : variables) env += v + "=" + std::to_string(t) + " ";
      const CommandResult r =
          runCommand(env + "CLHAIR_DEVICE=" + device + " " + quote(renderFloatPath()) + " " +
                     quote(scene) + " " + quote(out));
      ASSERT_EQ(r.exitCode, 0) << d.name << ", " << variable << "=" << t << ":\n" << r.output;
      int w = 0, h = 0;
      std::vector<float> frame = readFloatFrame(out, &w, &h);
      ASSERT_FALSE(frame.empty());
      if (first.empty()) {
        first = std::move(frame);
        width = w;
        height = h;
        continue;
      }
      ASSERT_EQ(w, width);
      ASSERT_EQ(h, height);
      std::size_t differ = 0, at = 0;
      for (std::size_t i = 0; i < first.size(); ++i)
        if (std::memcmp(&first[i], &frame[i], sizeof(float)) != 0 && differ++ == 0) at = i;
      EXPECT_EQ(differ, 0u) << d.name << ": " << variable << "=" << t << " against " << variable
                            << "=" << threads.front() << ": " << differ
                            << " floats differ, the first at pixel (" << (at / 5) % width << ", "
                            << (at / 5) / width << ") channel "
                            << "RGBAZ"[at % 5] << "; see " << out;
    }
    compared += "\n  " + d.name + " (" + variable + ")";
  }
  std::printf("[ threads  ] compared:%s\n", compared.empty() ? " none" : compared.c_str());
  if (!notCompared.empty()) std::printf("[ threads  ] not compared:%s\n", notCompared.c_str());
  if (compared.empty()) GTEST_SKIP() << "no device whose thread count can be set:" << notCompared;
}

}  // namespace clhair::test
