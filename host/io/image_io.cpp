// image_io.cpp — writing and reading images through OpenImageIO (see clhair/image.h).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include "clhair/error.h"
#include "clhair/image.h"
#include "io/image_file.h"
#include "io/json_util.h"

namespace clhair {

namespace {

float linearToSrgb(float x) {
  x = std::min(std::max(x, 0.0f), 1.0f);
  return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}

float srgbToLinear(float x) {
  return x <= 0.04045f ? x / 12.92f : std::pow((x + 0.055f) / 1.055f, 2.4f);
}

bool isFloatFormat(const std::string& ext) { return ext == ".exr" || ext == ".hdr"; }

}  // namespace

void writeImageFile(const std::string& path, OIIO::ImageSpec spec, OIIO::TypeDesc format,
                    const void* pixels, const std::string& noWriter) {
  // The temporary keeps the extension so OpenImageIO picks the right writer.
  std::filesystem::path target(path);
  std::filesystem::path tmp = target.parent_path() / (".tmp-" + std::to_string(::getpid()) + "-" +
                                                      target.filename().string());
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw Error(path + ": " + noWriter);
  // No time stamp: OpenImageIO's EXR writer adds the current time unless one is given, and
  // a file must depend on its pixels only (a frame of a range is byte-identical however and
  // whenever it is rendered).
  spec.attribute("DateTime", "");
  bool ok = out->open(tmp.string(), spec);
  if (ok) ok = out->write_image(format, pixels);
  ok = out->close() && ok;
  std::error_code ec;
  if (!ok) {
    std::string err = out->geterror();
    std::filesystem::remove(tmp, ec);
    throw Error(path + ": writing the image failed (" + err + ")");
  }
  std::filesystem::rename(tmp, target, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw Error(path + ": cannot move the finished image into place (" + ec.message() + ")");
  }
}

void writeImage(const Image& image, const std::string& path) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgba.size() != static_cast<std::size_t>(image.width) * image.height * 4)
    throw Error(path + ": refusing to write an empty or inconsistent image");
  const std::string ext = lowerExtension(path);
  const std::string noWriter = "no image writer for extension \"" + ext + "\" (try .png or .exr)";
  const bool floating = isFloatFormat(ext);
  OIIO::ImageSpec spec(image.width, image.height, 4,
                       floating ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:ColorSpace", floating ? "Linear" : "sRGB");
  if (floating) {
    writeImageFile(path, spec, OIIO::TypeDesc::FLOAT, image.rgba.data(), noWriter);
    return;
  }
  std::vector<unsigned char> bytes(image.rgba.size());
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    float v =
        (i % 4 == 3) ? std::min(std::max(image.rgba[i], 0.0f), 1.0f) : linearToSrgb(image.rgba[i]);
    bytes[i] = static_cast<unsigned char>(std::lround(v * 255.0f));
  }
  writeImageFile(path, spec, OIIO::TypeDesc::UINT8, bytes.data(), noWriter);
}

Image readImage(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw Error(path + ": cannot read image (" + OIIO::geterror() + ")");
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.width > 65536 || spec.height > 65536)
    throw Error(path + ": image size " + std::to_string(spec.width) + "x" +
                std::to_string(spec.height) + " is not supported");
  int channels = spec.nchannels;
  std::vector<float> data(static_cast<std::size_t>(spec.width) * spec.height * channels);
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, data.data()))
    throw Error(path + ": reading pixels failed (" + in->geterror() + ")");
  bool srgb = spec.format.basetype == OIIO::TypeDesc::UINT8 ||
              spec.format.basetype == OIIO::TypeDesc::UINT16;
  Image img;
  img.width = spec.width;
  img.height = spec.height;
  img.rgba.assign(static_cast<std::size_t>(img.width) * img.height * 4, 1.0f);
  for (std::size_t p = 0; p < static_cast<std::size_t>(img.width) * img.height; ++p) {
    for (int c = 0; c < 4; ++c) {
      float v;
      if (c < channels)
        v = data[p * channels + c];
      else if (c < 3)
        v = data[p * channels];  // grey images
      else
        v = 1.0f;
      if (c < 3 && srgb) v = srgbToLinear(v);
      img.rgba[p * 4 + c] = v;
    }
  }
  return img;
}

}  // namespace clhair
