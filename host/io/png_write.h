// png_write.h — PNG files written with libpng, not the image codec (host/codec/): a command
// that writes a PNG then loads no OpenImageIO. 8-bit sRGB colour with linear alpha (RGBA),
// the same bytes per pixel as the codec's 8-bit formats (io/srgb_encode.h), sRGB, gAMA and cHRM
// chunks, zlib at the options' level; encoded a band of rows at a time straight into an
// io/safe_write.h AtomicFile, which takes the target's place only when every write succeeded.
#pragma once

#include <string>

#include "clhair/image.h"

namespace clhair {

void writePng(const Image& image, const std::string& path, const ImageWriteOptions& options);

}  // namespace clhair
