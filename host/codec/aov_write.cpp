// aov_write.cpp — a frame's layers as one multi-channel OpenEXR file through OpenImageIO (see
// clhair/aov.h, docs/aovs.md); part of the image codec (io/image_codec.h).
#include <OpenImageIO/imageio.h>

#include <string>
#include <vector>

#include "clhair/aov.h"
#include "clhair/error.h"
#include "codec/image_encode.h"
#include "io/image_file.h"
#include "io/json_util.h"

namespace clhair {

void writeChannels(const std::vector<ImageChannel>& channels, int width, int height,
                   const std::string& path, const ImageWriteOptions& options,
                   const std::vector<ImageAttribute>& attributes) {
  const std::string ext = lowerExtension(path);
  if (ext != ".exr")
    throw Error(path + ": layers for compositing (--aov) need an OpenEXR file (.exr), not \"" +
                ext + "\"");
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (width <= 0 || height <= 0 || channels.empty())
    throw Error(path + ": refusing to write an empty image");
  for (const ImageChannel& c : channels)
    if (c.values.size() != pixels)
      throw Error(path + ": channel " + c.name + " has " + std::to_string(c.values.size()) +
                  " values for " + std::to_string(pixels) + " pixels");
  const int n = static_cast<int>(channels.size());
  OIIO::ImageSpec spec(width, height, n, OIIO::TypeDesc::FLOAT);
  spec.channelnames.clear();
  spec.channelformats.clear();
  for (const ImageChannel& c : channels) {
    spec.channelnames.push_back(c.name);
    spec.channelformats.push_back(c.half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
  }
  spec.alpha_channel = -1;
  spec.z_channel = -1;
  for (int c = 0; c < n; ++c) {
    if (channels[c].name == "A") spec.alpha_channel = c;
    if (channels[c].name == "Z") spec.z_channel = c;
  }
  spec.attribute("oiio:ColorSpace", "Linear");
  for (const ImageAttribute& a : attributes) spec.attribute(a.name, a.value);
  std::vector<float> interleaved(pixels * n);
  for (std::size_t p = 0; p < pixels; ++p)
    for (int c = 0; c < n; ++c) interleaved[p * n + c] = channels[c].values[p];
  writeImageFile(path, spec, OIIO::TypeDesc::FLOAT, interleaved.data(), options);
}

}  // namespace clhair
