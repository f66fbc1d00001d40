// image_write.cpp — writing images (see clhair/image.h and io/image_file.h): OpenImageIO encodes
// them a band of rows at a time straight into an io/safe_write.h AtomicFile (through an I/O
// proxy), so the memory a write takes beyond the float image is one band and the codec's own
// state, not the whole encoded file nor an 8-bit copy of the frame. The formats written are a
// fixed table (io/image_formats.cpp), so a name is checked before any work without asking the
// codec library (tests/test_image_io.cpp checks that OpenImageIO writes each of them). This
// file, aov_write.cpp and image_read.cpp are the image codec: the command loads them as a
// module on first use (io/image_codec.h).
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <functional>
#include <memory>

#include "clhair/error.h"
#include "clhair/image.h"
#include "codec/image_encode.h"
#include "io/image_file.h"
#include "io/json_util.h"
#include "io/safe_write.h"
#include "io/srgb_encode.h"

namespace clhair {

namespace {

// A codec's message on one line.
std::string oneLine(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  for (std::size_t p = text.find('\n'); p != std::string::npos; p = text.find('\n', p))
    text.replace(p, 1, "; ");
  return text;
}

// A writer for the path's extension that writes through an I/O proxy, or null.
std::unique_ptr<OIIO::ImageOutput> proxyWriter(const std::string& path) {
  const std::string ext = lowerExtension(path);
  if (ext.size() < 2) return nullptr;
  auto out = OIIO::ImageOutput::create(ext.substr(1));
  OIIO::geterror();  // "no writer" is ours to report; clear this thread's message
  if (out && !out->supports("ioproxy")) out.reset();
  return out;
}

// The codec's file: an AtomicFile. Codecs are C libraries underneath, so a failed write is
// kept here (its message names the cause: "no space left on device") and reported as a short
// count, never thrown through them.
class AtomicFileProxy final : public OIIO::Filesystem::IOProxy {
 public:
  AtomicFileProxy(AtomicFile& file, const std::string& path) : IOProxy(path, Write), file_(file) {}
  const char* proxytype() const override { return "clhair-atomic-file"; }
  size_t write(const void* buf, size_t size) override {
    const size_t k = pwrite(buf, size, m_pos);
    m_pos += static_cast<int64_t>(k);
    return k;
  }
  size_t pwrite(const void* buf, size_t size, int64_t offset) override {
    if (!failure_.empty() || offset < 0) return 0;
    try {
      file_.write(buf, size, static_cast<std::uint64_t>(offset));
      return size;
    } catch (const Error& e) {
      failure_ = e.what();
      return 0;
    }
  }
  size_t read(void* buf, size_t size) override {
    const size_t k = pread(buf, size, m_pos);
    m_pos += static_cast<int64_t>(k);
    return k;
  }
  size_t pread(void* buf, size_t size, int64_t offset) override {
    if (!failure_.empty() || offset < 0) return 0;
    try {
      return file_.read(buf, size, static_cast<std::uint64_t>(offset));
    } catch (const Error& e) {
      failure_ = e.what();
      return 0;
    }
  }
  size_t size() const override { return static_cast<size_t>(file_.size()); }
  const std::string& failure() const { return failure_; }

 private:
  AtomicFile& file_;
  std::string failure_;
};

// Opens `path` (a checked temporary beside it), lets `encode` give the codec the pixels, and
// moves the file into place only when the codec and every write succeeded.
void encodeToFile(const std::string& path, OIIO::ImageSpec spec, const ImageWriteOptions& options,
                  const std::function<bool(OIIO::ImageOutput&)>& encode) {
  checkImageWriteOptions(options);
  checkImageFormat(path);
  auto out = proxyWriter(path);
  if (!out)
    throw Error(path + ": this build's OpenImageIO has no writer for \"" + lowerExtension(path) +
                "\" that writes through a proxy");
  const std::string ext = lowerExtension(path);
  // No time stamp: OpenImageIO's EXR writer adds the current time unless one is given, and
  // a file must depend on its pixels only (a frame of a range is byte-identical however and
  // whenever it is rendered).
  spec.attribute("DateTime", "");
  if (ext == ".png") spec.attribute("png:compressionLevel", options.pngCompression);
  if (ext == ".exr") spec.attribute("compression", options.exrCompression);
  AtomicFile file(path);
  AtomicFileProxy proxy(file, path);  // outlives the writer, which only borrows it
  bool ok = out->set_ioproxy(&proxy) && out->open(path, spec);
  if (ok) ok = encode(*out);
  ok = out->close() && ok;
  const std::string err = oneLine(out->geterror());
  out.reset();
  if (!proxy.failure().empty()) throw Error(proxy.failure());
  if (!ok)
    throw Error(path + ": encoding the image failed (" +
                (err.empty() ? std::string("the codec gave no reason") : err) + ")");
  file.commit();
}

}  // namespace

void writeImageFile(const std::string& path, OIIO::ImageSpec spec, OIIO::TypeDesc format,
                    const void* pixels, const ImageWriteOptions& options) {
  encodeToFile(path, std::move(spec), options,
               [&](OIIO::ImageOutput& out) { return out.write_image(format, pixels); });
}

void encodeImage(const Image& image, const std::string& path, const ImageWriteOptions& options) {
  checkImageToWrite(image, path);
  checkImageOutput(path);
  const bool floating = imageFormatIsFloat(path);
  const int channels = imageFormatHasAlpha(path) ? 4 : 3;
  const std::size_t width = static_cast<std::size_t>(image.width);
  OIIO::ImageSpec spec(image.width, image.height, channels,
                       floating ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:ColorSpace", floating ? "Linear" : "sRGB");
  const int band = imageBandRows(image.width);
  // one band of rows at a time: the float rows as they are (RGBA), or converted (RGB, 8 bit)
  std::vector<float> rgb;
  std::vector<std::uint8_t> bytes;
  encodeToFile(path, spec, options, [&](OIIO::ImageOutput& out) {
    for (int y0 = 0; y0 < image.height; y0 += band) {
      const int y1 = std::min(image.height, y0 + band);
      const std::size_t first = std::size_t(y0) * width, n = std::size_t(y1 - y0) * width;
      const float* src = image.rgba.data() + first * 4;
      bool ok = true;
      if (floating && channels == 4) {
        ok = out.write_scanlines(y0, y1, 0, OIIO::TypeDesc::FLOAT, src);
      } else if (floating) {
        rgb.resize(n * 3);
        for (std::size_t p = 0; p < n; ++p)
          for (int c = 0; c < 3; ++c) rgb[p * 3 + c] = src[p * 4 + c];
        ok = out.write_scanlines(y0, y1, 0, OIIO::TypeDesc::FLOAT, rgb.data());
      } else {
        bytes.resize(n * channels);
        encodeSrgb8(src, n, channels, bytes.data());
        ok = out.write_scanlines(y0, y1, 0, OIIO::TypeDesc::UINT8, bytes.data());
      }
      if (!ok) return false;
    }
    return true;
  });
}

}  // namespace clhair
