// image_formats.cpp — the image formats clhair writes, as a fixed table, and the checks of an
// output's name and options before any work (see clhair/image.h and io/image_file.h). Nothing
// here asks the codec library, so a command checks its outputs without loading it.
#include <algorithm>
#include <iterator>
#include <string>
#include <vector>

#include "clhair/error.h"
#include "clhair/image.h"
#include "io/image_file.h"
#include "io/json_util.h"
#include "io/safe_write.h"

namespace clhair {

namespace {

constexpr const char* kExrCompressions[] = {"none",  "rle", "zips", "zip",  "piz",
                                            "pxr24", "b44", "b44a", "dwaa", "dwab"};

struct ImageFormat {
  const char* extension;
  bool alpha;  // whether the format stores an alpha channel (else RGB is written)
};
constexpr ImageFormat kImageFormats[] = {{".png", true},  {".exr", true},  {".tif", true},
                                         {".tiff", true}, {".tga", true},  {".bmp", true},
                                         {".webp", true}, {".jpg", false}, {".jpeg", false},
                                         {".hdr", false}, {".ppm", false}, {".pnm", false}};

const ImageFormat* imageFormat(const std::string& path) {
  const std::string ext = lowerExtension(path);
  for (const ImageFormat& f : kImageFormats)
    if (ext == f.extension) return &f;
  return nullptr;
}

}  // namespace

bool imageFormatIsFloat(const std::string& path) {
  const std::string ext = lowerExtension(path);
  return ext == ".exr" || ext == ".hdr";
}

void checkImageWriteOptions(const ImageWriteOptions& o) {
  if (o.pngCompression < 0 || o.pngCompression > 9)
    throw Error("PNG compression " + std::to_string(o.pngCompression) +
                " is outside 0..9 (zlib levels: 0 none, 1 fast, 9 smallest)");
  if (std::find_if(std::begin(kExrCompressions), std::end(kExrCompressions), [&](const char* n) {
        return o.exrCompression == n;
      }) == std::end(kExrCompressions)) {
    std::string known;
    for (const char* n : kExrCompressions) known += std::string(known.empty() ? "" : ", ") + n;
    throw Error("EXR compression \"" + o.exrCompression + "\" is not one of " + known);
  }
}

std::vector<std::string> imageFormatExtensions() {
  std::vector<std::string> out;
  for (const ImageFormat& f : kImageFormats) out.push_back(f.extension);
  return out;
}

void checkImageToWrite(const Image& image, const std::string& path) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgba.size() != static_cast<std::size_t>(image.width) * image.height * 4)
    throw Error(path + ": refusing to write an empty or inconsistent image");
}

int imageBandRows(int width) { return std::max(16, (1 << 20) / std::max(1, width * 4)); }

bool imageFormatWritable(const std::string& path) { return imageFormat(path) != nullptr; }

bool imageFormatHasAlpha(const std::string& path) {
  const ImageFormat* f = imageFormat(path);
  return f && f->alpha;
}

void checkImageOutput(const std::string& path) {
  checkOutputPath(path);
  checkImageFormat(path);
}

void checkImageFormat(const std::string& path) {
  if (!imageFormatWritable(path)) {
    const std::string ext = lowerExtension(path);
    throw Error(path + ": " +
                (ext.empty() ? std::string("has no extension to choose an image format by")
                             : "no image writer for extension \"" + ext + "\"") +
                " (use .png, .exr, .jpg, .tif, .hdr, .tga, .bmp, .webp or .ppm)");
  }
}

}  // namespace clhair
