// image.h — a linear float RGBA image, writing it to disk and reading one through OpenImageIO.
//
// PNG and other 8-bit formats receive sRGB-encoded colour; EXR keeps linear half/float.
// Formats without an alpha channel (JPEG, HDR, PPM) get RGB. An image is encoded in memory
// and written through one checked path (host/io/safe_write.h): a temporary in the target
// folder, flushed and renamed into place, so a failed or killed write never leaves a
// half-written image, and an existing file stays whole. Every function here may be called
// from several threads at once on different paths; a codec's messages are captured into the
// one clhair::Error line, never printed.
#pragma once

#include <cstdint>
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

// How images are compressed (bench/README.md, "Image writing": sizes and times per level).
struct ImageWriteOptions {
  int pngCompression = 1;  // zlib level 0 (none) .. 9 (smallest); 1: fast, a little larger
  std::string exrCompression = "zip";  // none, rle, zips, zip, piz, pxr24, b44, b44a, dwaa, dwab
};

// Refuses options outside the lists above: one clhair::Error line naming the value.
void checkImageWriteOptions(const ImageWriteOptions& options);

// Refuses, before any work, an image file name whose extension has no writer (".xyz"): one
// clhair::Error line. checkImageOutput also refuses a path whose folder is missing or that
// names a folder, FIFO or device (host/io/safe_write.h, checkOutputPath).
void checkImageFormat(const std::string& path);
void checkImageOutput(const std::string& path);

// Writes `image` to `path` (the format from its extension). The two-argument form uses the
// default options; it is the one a build without OpenImageIO replaces (host/io/image_io.cpp).
void writeImage(const Image& image, const std::string& path);
void writeImage(const Image& image, const std::string& path, const ImageWriteOptions& options);

// The largest image readImage accepts, in pixels (16384 x 16384), and the most pixel bytes it
// believes per byte of file: a header that declares more than kMaxImageExpansion times the
// file's size (plus 1 MiB) in uncompressed samples is refused before anything is allocated.
// Deflate, the densest coder of the formats read, reaches 1032:1; LZW about 2700:1.
constexpr std::uint64_t kMaxImagePixels = std::uint64_t(16384) * 16384;
constexpr std::uint64_t kMaxImageExpansion = 4096;

// Reads an image as linear RGBA (8- and 16-bit integer files are sRGB-decoded). Refuses FIFOs,
// devices and folders unopened, damaged files, and sizes over the limits above.
Image readImage(const std::string& path);

}  // namespace clhair
