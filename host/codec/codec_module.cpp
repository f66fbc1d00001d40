// codec_module.cpp — the image codec's table (io/image_codec.h), the one symbol the codec
// module exports to the command's loader (cli/image_codec_loader.cpp). Every entry catches
// what the codec throws and returns its message: no exception crosses the module's edge.
#include <algorithm>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "clhair/error.h"
#include "io/image_codec.h"
#include "io/image_file.h"

namespace {

// Runs f(); 0, or 1 with the message of what it threw in `error`.
template <typename F>
int guarded(F&& f, char* error, std::size_t capacity) noexcept {
  std::string message;
  try {
    f();
    return 0;
  } catch (const std::exception& e) {
    message = e.what();
  } catch (...) {
    message = "the image codec failed";
  }
  if (error && capacity > 0) {
    const std::size_t n = std::min(message.size(), capacity - 1);
    std::memcpy(error, message.data(), n);
    error[n] = '\0';
  }
  return 1;
}

}  // namespace

extern "C" __attribute__((visibility("default"))) const clhair::ImageCodec* clhair_image_codec() {
  using clhair::Image;
  using clhair::ImageAttribute;
  using clhair::ImageChannel;
  using clhair::ImageWriteOptions;
  static const clhair::ImageCodec table = {
      clhair::kImageCodecAbi,
      [](const Image& image, const std::string& path, const ImageWriteOptions& options, char* error,
         std::size_t capacity) noexcept {
        return guarded([&] { clhair::encodeImage(image, path, options); }, error, capacity);
      },
      [](const std::vector<ImageChannel>& channels, int width, int height, const std::string& path,
         const ImageWriteOptions& options, const std::vector<ImageAttribute>& attributes,
         char* error, std::size_t capacity) noexcept {
        return guarded(
            [&] { clhair::writeChannels(channels, width, height, path, options, attributes); },
            error, capacity);
      },
      [](const std::string& path, Image* out, char* error, std::size_t capacity) noexcept {
        return guarded([&] { *out = clhair::readImageFile(path); }, error, capacity);
      }};
  return &table;
}
