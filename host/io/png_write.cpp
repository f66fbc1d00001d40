// png_write.cpp — see png_write.h.
//
// libpng reports errors by longjmp back to the setjmp of the frame that started the write.
// So the one frame that calls setjmp (encodeRows) holds no object with a destructor, and the
// callbacks that libpng calls never let an exception or a live C++ object reach png_error:
// a failed file write is kept in the Sink (its message names the cause: "no space left on
// device") and turned into the clhair::Error here, after libpng has returned.
#include "io/png_write.h"

#include <png.h>

#include <algorithm>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "clhair/error.h"
#include "io/image_file.h"
#include "io/safe_write.h"
#include "io/srgb_encode.h"

namespace clhair {

namespace {

// Where libpng's bytes go and what went wrong; reached from libpng's callbacks.
struct Sink {
  AtomicFile* file = nullptr;
  std::uint64_t offset = 0;
  std::string failure;  // a failed write (the file's message)
  char codecError[256] = {};
};

void writeBytes(png_structp png, png_bytep data, png_size_t n) {
  auto* sink = static_cast<Sink*>(png_get_io_ptr(png));
  bool written = false;
  if (sink->failure.empty()) {
    try {
      sink->file->write(data, n, sink->offset);
      sink->offset += n;
      written = true;
    } catch (const Error& e) {
      sink->failure = e.what();
    } catch (const std::exception& e) {
      sink->failure = e.what();
    }
  }
  if (!written) png_error(png, "write failed");  // nothing with a destructor is live here
}

void flushBytes(png_structp) {}  // AtomicFile::commit syncs the file

void onError(png_structp png, png_const_charp message) {
  auto* sink = static_cast<Sink*>(png_get_error_ptr(png));
  std::snprintf(sink->codecError, sizeof(sink->codecError), "%s", message ? message : "");
  png_longjmp(png, 1);
}

void onWarning(png_structp, png_const_charp) {}

// The encoding itself between one setjmp and libpng's end; false when libpng stopped on an
// error. `band` holds `bandRows` rows of width * channels bytes, which `fill` fills.
bool encodeRows(png_structp png, png_infop info, int width, int height, int channels,
                int compression, void (*fill)(const void*, int, int, png_bytep), const void* ctx,
                png_bytep band, int bandRows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
               channels == 4 ? PNG_COLOR_TYPE_RGB_ALPHA : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);  // sRGB, and its gAMA and cHRM
  png_set_compression_level(png, compression);
  png_write_info(png, info);
  const std::size_t stride = static_cast<std::size_t>(width) * channels;
  for (int y0 = 0; y0 < height; y0 += bandRows) {
    const int y1 = std::min(height, y0 + bandRows);
    fill(ctx, y0, y1, band);
    for (int y = y0; y < y1; ++y) png_write_row(png, band + std::size_t(y - y0) * stride);
  }
  png_write_end(png, nullptr);
  return true;
}

struct Rows {
  const Image* image;
  int channels;
};

// Rows y0..y1 of the image as 8-bit sRGB (alpha linear), `channels` bytes a pixel.
void fillRows(const void* ctx, int y0, int y1, png_bytep out) {
  const Rows& r = *static_cast<const Rows*>(ctx);
  const std::size_t width = static_cast<std::size_t>(r.image->width);
  encodeSrgb8(r.image->rgba.data() + std::size_t(y0) * width * 4, std::size_t(y1 - y0) * width,
              r.channels, out);
}

}  // namespace

void writePng(const Image& image, const std::string& path, const ImageWriteOptions& options) {
  checkImageToWrite(image, path);
  checkImageWriteOptions(options);
  checkImageOutput(path);
  const int channels = imageFormatHasAlpha(path) ? 4 : 3;
  const int bandRows = imageBandRows(image.width);
  std::vector<png_byte> band(static_cast<std::size_t>(bandRows) * image.width * channels);
  AtomicFile file(path);
  Sink sink;
  sink.file = &file;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &sink, onError, onWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    throw Error(path + ": encoding the image failed (libpng could not start)");
  }
  png_set_write_fn(png, &sink, writeBytes, flushBytes);
  const Rows rows{&image, channels};
  const bool ok = encodeRows(png, info, image.width, image.height, channels, options.pngCompression,
                             fillRows, &rows, band.data(), bandRows);
  png_destroy_write_struct(&png, &info);
  if (!sink.failure.empty()) throw Error(sink.failure);
  if (!ok)
    throw Error(
        path + ": encoding the image failed (" +
        (sink.codecError[0] ? std::string(sink.codecError) : std::string("libpng gave no reason")) +
        ")");
  file.commit();
}

}  // namespace clhair
