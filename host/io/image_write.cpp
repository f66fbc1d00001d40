// image_write.cpp — writing images (see clhair/image.h and io/image_file.h): encoded in memory by
// OpenImageIO, then written through io/safe_write.h. The formats written are a fixed table, so
// a name is checked before any work without asking the codec library (tests/test_image_io.cpp
// checks that OpenImageIO writes each of them into memory).
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <memory>

#include "clhair/error.h"
#include "clhair/image.h"
#include "io/image_file.h"
#include "io/json_util.h"
#include "io/safe_write.h"
#include "io/srgb_encode.h"

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

bool isFloatFormat(const std::string& ext) { return ext == ".exr" || ext == ".hdr"; }

// A codec's message on one line.
std::string oneLine(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  for (std::size_t p = text.find('\n'); p != std::string::npos; p = text.find('\n', p))
    text.replace(p, 1, "; ");
  return text;
}

// A writer for the path's extension that encodes into memory, or null.
std::unique_ptr<OIIO::ImageOutput> memoryWriter(const std::string& path) {
  const std::string ext = lowerExtension(path);
  if (ext.size() < 2) return nullptr;
  auto out = OIIO::ImageOutput::create(ext.substr(1));
  OIIO::geterror();  // "no writer" is ours to report; clear this thread's message
  if (out && !out->supports("ioproxy")) out.reset();
  return out;
}

}  // namespace

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

void writeImageFile(const std::string& path, OIIO::ImageSpec spec, OIIO::TypeDesc format,
                    const void* pixels, const ImageWriteOptions& options) {
  checkImageWriteOptions(options);
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput proxy(bytes);  // outlives the writer, which only borrows it
  checkImageFormat(path);
  auto out = memoryWriter(path);
  if (!out)
    throw Error(path + ": this build's OpenImageIO has no writer for \"" + lowerExtension(path) +
                "\" that encodes into memory");
  const std::string ext = lowerExtension(path);
  // No time stamp: OpenImageIO's EXR writer adds the current time unless one is given, and
  // a file must depend on its pixels only (a frame of a range is byte-identical however and
  // whenever it is rendered).
  spec.attribute("DateTime", "");
  if (ext == ".png") spec.attribute("png:compressionLevel", options.pngCompression);
  if (ext == ".exr") spec.attribute("compression", options.exrCompression);
  bool ok = out->set_ioproxy(&proxy) && out->open(path, spec);
  if (ok) ok = out->write_image(format, pixels);
  ok = out->close() && ok;
  const std::string err = oneLine(out->geterror());
  if (!ok)
    throw Error(path + ": encoding the image failed (" +
                (err.empty() ? std::string("the codec gave no reason") : err) + ")");
  writeFileAtomically(path, bytes.data(), bytes.size());
}

void writeImage(const Image& image, const std::string& path, const ImageWriteOptions& options) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgba.size() != static_cast<std::size_t>(image.width) * image.height * 4)
    throw Error(path + ": refusing to write an empty or inconsistent image");
  checkImageOutput(path);
  const std::string ext = lowerExtension(path);
  const bool floating = isFloatFormat(ext);
  const int channels = imageFormatHasAlpha(path) ? 4 : 3;
  const std::size_t pixels = static_cast<std::size_t>(image.width) * image.height;
  OIIO::ImageSpec spec(image.width, image.height, channels,
                       floating ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:ColorSpace", floating ? "Linear" : "sRGB");
  if (floating) {
    if (channels == 4) {
      writeImageFile(path, spec, OIIO::TypeDesc::FLOAT, image.rgba.data(), options);
      return;
    }
    std::vector<float> rgb(pixels * 3);
    for (std::size_t p = 0; p < pixels; ++p)
      for (int c = 0; c < 3; ++c) rgb[p * 3 + c] = image.rgba[p * 4 + c];
    writeImageFile(path, spec, OIIO::TypeDesc::FLOAT, rgb.data(), options);
    return;
  }
  std::vector<std::uint8_t> bytes(pixels * channels);
  encodeSrgb8(image.rgba.data(), pixels, channels, bytes.data());
  writeImageFile(path, spec, OIIO::TypeDesc::UINT8, bytes.data(), options);
}

}  // namespace clhair
