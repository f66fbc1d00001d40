// image.h — a linear float RGBA image and writing it to disk through OpenImageIO.
//
// PNG and other 8-bit formats receive sRGB-encoded colour; EXR keeps linear half/float.
// Writes go to a temporary file in the target folder and are renamed into place, so a
// failed render never leaves a half-written image behind.
#pragma once

#include <string>
#include <vector>

namespace clhair {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<float> rgba;  // row-major, top row first, linear

  float* pixel(int x, int y) { return &rgba[(static_cast<std::size_t>(y) * width + x) * 4]; }
  const float* pixel(int x, int y) const {
    return &rgba[(static_cast<std::size_t>(y) * width + x) * 4];
  }
};

void writeImage(const Image& image, const std::string& path);
Image readImage(const std::string& path);  // returns linear RGBA

}  // namespace clhair
