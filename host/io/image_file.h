// image_file.h — image files as clhair writes and reads them: the formats written (a fixed
// table, io/image_formats.cpp, checked before any work) and the codec's reader. The codec
// itself (host/codec/: OpenImageIO) is reached through the functions declared here and in
// clhair/image.h and clhair/aov.h only, so a program that links the codec's loader instead
// (the command, io/image_codec.h) loads OpenImageIO on its first image, not at start.
#pragma once

#include <string>
#include <vector>

#include "clhair/image.h"

namespace clhair {

// Whether the path's extension is one of the formats written (a fixed table, ".png", ".exr",
// ...), and whether that format stores an alpha channel; the table's extensions.
bool imageFormatWritable(const std::string& path);
bool imageFormatHasAlpha(const std::string& path);
// Whether the format stores floating-point pixels (OpenEXR, Radiance HDR): written linear.
bool imageFormatIsFloat(const std::string& path);
std::vector<std::string> imageFormatExtensions();

// Refuses an image whose size and pixels disagree (one clhair::Error naming `path`).
void checkImageToWrite(const Image& image, const std::string& path);
// Rows a writer encodes at a time: about 1 MB of 8-bit RGBA at 4K, at least 16 rows.
int imageBandRows(int width);

// writeImage's work for every format but PNG (codec/image_write.cpp); writeImage
// (io/image_write.cpp) calls it.
void encodeImage(const Image& image, const std::string& path, const ImageWriteOptions& options);

// readImage's work (codec/image_read.cpp); readImage (io/image_io.cpp) calls it.
Image readImageFile(const std::string& path);

}  // namespace clhair
