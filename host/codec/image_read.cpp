// image_read.cpp — reading an image as linear RGBA (clhair/image.h, readImage; io/image_file.h).
//
// The file is opened as a regular file (io/regular_file.h: FIFOs, devices and folders refused
// unopened), read into memory and decoded from there through OpenImageIO's IOProxy, so what
// is decoded is what was checked. A PNG is walked first (io/png_check.h) so libpng never
// prints; the header's declared size is checked against kMaxImagePixels and against the
// file's size (kMaxImageExpansion) before the pixels are allocated; scanline files are
// decoded a band of rows at a time straight into the RGBA result. Codec messages, also those
// of a read that "succeeded" with a complaint (a damaged JPEG), become one clhair::Error line.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "clhair/error.h"
#include "clhair/image.h"
#include "io/image_file.h"
#include "io/png_check.h"
#include "io/regular_file.h"

namespace clhair {

namespace {

constexpr std::uint64_t kMaxImageFileBytes = std::uint64_t(4) << 30;
constexpr std::size_t kBandBytes = 4u << 20;  // floats of one band of decoded rows

float srgbToLinear(float x) {
  return x <= 0.04045f ? x / 12.92f : std::pow((x + 0.055f) / 1.055f, 2.4f);
}

std::string oneLine(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  for (std::size_t p = text.find('\n'); p != std::string::npos; p = text.find('\n', p))
    text.replace(p, 1, "; ");
  return text;
}

// Decoded samples of `rows` rows (nch floats per pixel) into rows [y0, y0 + rows) of `img`.
void toRgba(const float* src, int nch, bool srgb, int y0, int rows, Image& img) {
  const std::size_t n = static_cast<std::size_t>(rows) * img.width;
  float* dst = img.rgba.data() + static_cast<std::size_t>(y0) * img.width * 4;
  for (std::size_t p = 0; p < n; ++p)
    for (int c = 0; c < 4; ++c) {
      float v;
      if (c < nch)
        v = src[p * nch + c];
      else if (c < 3)
        v = src[p * nch];  // grey images
      else
        v = 1.0f;
      if (c < 3 && srgb) v = srgbToLinear(v);
      dst[p * 4 + c] = v;
    }
}

}  // namespace

Image readImageFile(const std::string& path) {
  RegularFile file(path, "image");
  const std::string bytes = file.readAll(kMaxImageFileBytes);
  if (looksLikePng(bytes)) checkPng(bytes, path, kMaxImagePixels);
  OIIO::Filesystem::IOMemReader proxy(bytes.data(), bytes.size());
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path, nullptr, &proxy);
  if (!in) {
    std::string err = oneLine(OIIO::geterror());
    // a format without in-memory reading: decoded from the path, which is a regular file
    auto probe = OIIO::ImageInput::create(path);
    OIIO::geterror();
    if (probe && !probe->supports("ioproxy")) {
      probe.reset();
      in = OIIO::ImageInput::open(path);
      if (!in) err = oneLine(OIIO::geterror());
    }
    if (!in) throw Error(path + ": cannot read image (" + err + ")");
  }
  const OIIO::ImageSpec spec = in->spec();
  const std::string size = std::to_string(spec.width) + "x" + std::to_string(spec.height);
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.nchannels > 64 ||
      spec.deep)
    throw Error(path + ": image size " + size + " with " + std::to_string(spec.nchannels) +
                " channels is not supported");
  const std::uint64_t pixels = std::uint64_t(spec.width) * std::uint64_t(spec.height);
  if (pixels > kMaxImagePixels)
    throw Error(path + ": image size " + size + " is over the limit of " +
                std::to_string(kMaxImagePixels) + " pixels");
  const std::uint64_t declared =
      pixels * spec.nchannels * std::max<std::size_t>(1, spec.format.size());
  if (declared > kMaxImageExpansion * bytes.size() + (1u << 20))
    throw Error(path + ": the header declares a " + size + " image of " +
                std::to_string(declared >> 20) + " MiB in a file of " +
                std::to_string(bytes.size()) + " bytes (damaged or truncated?)");
  const int nch = spec.nchannels;
  const bool srgb = spec.format.basetype == OIIO::TypeDesc::UINT8 ||
                    spec.format.basetype == OIIO::TypeDesc::UINT16;
  Image img;
  img.width = spec.width;
  img.height = spec.height;
  img.rgba.assign(static_cast<std::size_t>(pixels) * 4, 0.0f);
  bool ok = true;
  if (spec.tile_width > 0) {
    // tiled: the whole image at once (tiles do not follow rows)
    std::vector<float> data(static_cast<std::size_t>(pixels) * nch);
    ok = in->read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, data.data());
    if (ok) toRgba(data.data(), nch, srgb, 0, img.height, img);
  } else {
    const int band = static_cast<int>(std::clamp<std::size_t>(
        kBandBytes / (sizeof(float) * nch * static_cast<std::size_t>(spec.width)), 1,
        static_cast<std::size_t>(img.height)));
    std::vector<float> data(static_cast<std::size_t>(band) * spec.width * nch);
    for (int y = 0; y < img.height && ok; y += band) {
      const int rows = std::min(band, img.height - y);
      ok = in->read_scanlines(0, 0, spec.y + y, spec.y + y + rows, 0, 0, nch, OIIO::TypeDesc::FLOAT,
                              data.data());
      if (ok) toRgba(data.data(), nch, srgb, y, rows, img);
    }
  }
  const std::string err = oneLine(in->geterror());
  if (!ok || !err.empty())
    throw Error(path + ": reading pixels failed (" +
                (err.empty() ? std::string("the decoder gave no reason") : err) + ")");
  return img;
}

}  // namespace clhair
