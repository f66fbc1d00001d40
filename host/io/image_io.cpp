// image_io.cpp — the two image functions a build without OpenImageIO replaces: writeImage with
// the default options and readImage. They only forward to codec/image_write.cpp and
// codec/image_read.cpp (in the command, through the codec module: io/image_codec.h);
// ../shared/gpu/bundle.sh (scripts/gpu-check.sh) swaps this one object for a PPM writer to run
// clhair on machines that lack the codec libraries, so nothing else may live here.
#include "clhair/image.h"
#include "io/image_file.h"

namespace clhair {

void writeImage(const Image& image, const std::string& path) {
  writeImage(image, path, ImageWriteOptions{});
}

Image readImage(const std::string& path) { return readImageFile(path); }

}  // namespace clhair
