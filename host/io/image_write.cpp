// image_write.cpp — writeImage (clhair/image.h): PNG through libpng (io/png_write.cpp), every
// other format through the image codec (encodeImage, codec/image_write.cpp; in the command,
// the codec module it loads on first use: io/image_codec.h).
#include "clhair/image.h"
#include "io/image_file.h"
#include "io/json_util.h"
#include "io/png_write.h"

namespace clhair {

void writeImage(const Image& image, const std::string& path, const ImageWriteOptions& options) {
  if (lowerExtension(path) == ".png")
    writePng(image, path, options);
  else
    encodeImage(image, path, options);
}

}  // namespace clhair
