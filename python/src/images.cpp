// images.cpp — images and multi-channel EXR files written through the library's checked
// writers (the command's: sRGB 8-bit for PNG, linear float or half for EXR), sRGB encoding
// as the 8-bit writers do it, and image files read back as stored (8-bit codes or floats).
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "arrays.h"
#include "bindings.h"
#include "clhair/aov.h"
#include "clhair/error.h"
#include "clhair/image.h"
#include "io/srgb_encode.h"

namespace clhair::py {

namespace {

// (H, W, 4) float32 linear RGBA, checked.
Image imageOf(const nb::ndarray<>& rgba, const std::string& what) {
  if (rgba.ndim() != 3 || rgba.shape(2) != 4)
    throw Error(what + ": shape " + shapeText(rgba) + ", expected (H, W, 4)");
  Image im;
  im.height = static_cast<int>(rgba.shape(0));
  im.width = static_cast<int>(rgba.shape(1));
  if (im.width < 1 || im.height < 1) throw Error(what + ": the image is empty");
  std::vector<float> v(static_cast<std::size_t>(im.width) * im.height * 4);
  if (rgba.dtype() != nb::dtype<float>())
    throw Error(what + ": dtype " + dtypeName(rgba) + ", expected float32");
  const auto* base = static_cast<const float*>(rgba.data());
  std::size_t k = 0;
  for (std::size_t y = 0; y < rgba.shape(0); ++y)
    for (std::size_t x = 0; x < rgba.shape(1); ++x)
      for (std::size_t c = 0; c < 4; ++c)
        v[k++] = base[static_cast<std::int64_t>(y) * rgba.stride(0) +
                      static_cast<std::int64_t>(x) * rgba.stride(1) +
                      static_cast<std::int64_t>(c) * rgba.stride(2)];
  im.rgba = std::move(v);
  return im;
}

}  // namespace

void bindImages(nb::module_& m) {
  m.def(
      "_write_image",
      [](const std::string& path, const nb::ndarray<>& rgba) {
        Image im = imageOf(rgba, "rgba");
        nb::gil_scoped_release unlocked;
        writeImage(im, path);
      },
      nb::arg("path"), nb::arg("rgba"));
  m.def(
      "_encode_srgb8",
      [](const nb::ndarray<>& rgba) {
        Image im = imageOf(rgba, "rgba");
        std::vector<std::uint8_t> bytes(im.rgba.size());
        encodeSrgb8(im.rgba.data(), im.rgba.size() / 4, 4, bytes.data());
        return toNumpy(std::move(bytes), {static_cast<std::size_t>(im.height),
                                          static_cast<std::size_t>(im.width), 4});
      },
      nb::arg("rgba"));
  m.def(
      "_write_channels",
      [](const std::string& path, const std::vector<std::string>& names,
         const std::vector<nb::ndarray<>>& planes, const std::vector<bool>& half) {
        if (names.size() != planes.size() || names.size() != half.size() || names.empty())
          throw Error(path + ": channel names, planes and half flags must match in number");
        std::vector<ImageChannel> channels;
        int width = 0, height = 0;
        for (std::size_t i = 0; i < names.size(); ++i) {
          const nb::ndarray<>& a = planes[i];
          if (a.ndim() != 2)
            throw Error(names[i] + ": shape " + shapeText(a) + ", expected (H, W)");
          const int h = static_cast<int>(a.shape(0)), w = static_cast<int>(a.shape(1));
          if (i == 0) {
            width = w;
            height = h;
          } else if (w != width || h != height) {
            throw Error(names[i] + ": shape " + shapeText(a) + " differs from the first channel's");
          }
          // a (H, W) plane read as rows of W floats (NaN is allowed: written as it is)
          if (a.dtype() != nb::dtype<float>())
            throw Error(names[i] + ": dtype " + dtypeName(a) + ", expected float32");
          std::vector<float> v(static_cast<std::size_t>(w) * h);
          const auto* base = static_cast<const float*>(a.data());
          for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
              v[static_cast<std::size_t>(y) * w + x] = base[y * a.stride(0) + x * a.stride(1)];
          channels.push_back({names[i], std::move(v), half[i]});
        }
        nb::gil_scoped_release unlocked;
        writeChannels(channels, width, height, path);
      },
      nb::arg("path"), nb::arg("names"), nb::arg("planes"), nb::arg("half"));
  m.def(
      "_read_image",
      [](const std::string& path) {
        auto in = OIIO::ImageInput::open(path);
        if (!in) throw Error(path + ": cannot open (" + OIIO::geterror() + ")");
        const OIIO::ImageSpec spec = in->spec();
        const auto w = static_cast<std::size_t>(spec.width),
                   h = static_cast<std::size_t>(spec.height);
        const auto c = static_cast<std::size_t>(spec.nchannels);
        std::vector<std::string> names(spec.channelnames.begin(), spec.channelnames.end());
        const bool bytes = spec.format == OIIO::TypeDesc::UINT8;
        nb::object pixels;
        if (bytes) {
          std::vector<std::uint8_t> v(w * h * c);
          if (!in->read_image(0, 0, 0, static_cast<int>(c), OIIO::TypeDesc::UINT8, v.data()))
            throw Error(path + ": cannot read (" + in->geterror() + ")");
          pixels = toNumpy(std::move(v), {h, w, c});
        } else {
          std::vector<float> v(w * h * c);
          if (!in->read_image(0, 0, 0, static_cast<int>(c), OIIO::TypeDesc::FLOAT, v.data()))
            throw Error(path + ": cannot read (" + in->geterror() + ")");
          pixels = toNumpy(std::move(v), {h, w, c});
        }
        return std::make_pair(names, pixels);
      },
      nb::arg("path"));
}

}  // namespace clhair::py
