// codec_module.cpp — the image codec's table (io/image_codec.h), the one symbol the codec
// module exports to the command's loader (cli/image_codec_loader.cpp).
#include "io/image_codec.h"
#include "io/image_file.h"

extern "C" __attribute__((visibility("default"))) const clhair::ImageCodec* clhair_image_codec() {
  static const clhair::ImageCodec table = {
      clhair::kImageCodecAbi,
      [](const clhair::Image& image, const std::string& path,
         const clhair::ImageWriteOptions& options) { clhair::writeImage(image, path, options); },
      [](const std::vector<clhair::ImageChannel>& channels, int width, int height,
         const std::string& path, const clhair::ImageWriteOptions& options,
         const std::vector<clhair::ImageAttribute>& attributes) {
        clhair::writeChannels(channels, width, height, path, options, attributes);
      },
      [](const std::string& path) { return clhair::readImageFile(path); }};
  return &table;
}
