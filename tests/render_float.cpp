// render_float.cpp — a test helper: renders a scene JSON through the API, with default
// render options, and writes the frame as it left the renderer: colour and depth in one
// 32-bit float OpenEXR (channels R, G, B, A, Z), so tests can compare frames from separate
// processes bit for bit (the CLI writes half floats). The device comes from CLHAIR_DEVICE
// and the other CLHAIR_* variables, as for every clhair program.
//
//   clhair_render_float SCENE.json OUT.exr
//
// Prints the device's name on success; on failure one line "clhair_render_float: error:
// ..." and exit code 1.
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "clhair/device.h"
#include "clhair/error.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"

int main(int argc, char** argv) {
  using namespace clhair;
  if (argc != 3) {
    std::fprintf(stderr, "usage: clhair_render_float SCENE.json OUT.exr\n");
    return 2;
  }
  try {
    Device dev = Device::open(DeviceOptions::fromEnvironment({}));
    const Scene scene = loadScene(argv[1], dev.info().maxAlloc);
    Renderer renderer(dev);
    const Frame f = renderer.render(scene);
    const std::size_t pixels = static_cast<std::size_t>(scene.width) * scene.height;
    if (f.color.rgba.size() != 4 * pixels || f.depth.size() != pixels)
      throw Error("the frame has the wrong size");
    std::vector<float> rgbaz(5 * pixels);
    for (std::size_t p = 0; p < pixels; ++p) {
      for (int c = 0; c < 4; ++c) rgbaz[5 * p + c] = f.color.rgba[4 * p + c];
      rgbaz[5 * p + 4] = f.depth[p];
    }
    OIIO::ImageSpec spec(scene.width, scene.height, 5, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "A", "Z"};
    spec.alpha_channel = 3;
    spec.z_channel = 4;
    auto out = OIIO::ImageOutput::create(argv[2]);
    if (!out || !out->open(argv[2], spec) ||
        !out->write_image(OIIO::TypeDesc::FLOAT, rgbaz.data()) || !out->close())
      throw Error(std::string(argv[2]) + ": writing the frame failed (" +
                  (out ? out->geterror() : OIIO::geterror()) + ")");
    std::printf("%s\n", dev.info().name.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "clhair_render_float: error: %s\n", e.what());
    return 1;
  }
}
