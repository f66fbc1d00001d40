// throughput.h — the benchmark's throughput section: a shot rendered and written frame
// after frame as a user's `clhair render --frames` does, in frames per second, with per frame
// the wall time, the device-time sum, the host's own CPU time and its waits for the device;
// frames in flight with encoding on worker threads against one frame at a time with
// encoding on the render thread (the loop before frames in flight), and single still
// images, each in its own process and in-process.
#pragma once

#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "clhair/device.h"

namespace clhair::bench {

struct ThroughputOptions {
  std::string scene;  // the shot (assets/scenes/wind.json)
  int width = 1920, height = 1080;
  int frames = 240;    // frames of the shot per format and mode
  int stills = 5;      // single still images per way of rendering them
  std::string outDir;  // scratch folder for the images (removed afterwards)
  std::string cli;     // the clhair binary (for the one-image-per-process stills)
  std::string formats = "png,exr";
};

void throughputSection(const Device& dev, const ThroughputOptions& o, std::ostringstream& md,
                       nlohmann::json& report);

}  // namespace clhair::bench
