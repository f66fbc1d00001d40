// image_file.h — the one way clhair writes an image file: OpenImageIO encodes into memory
// (its IOProxy), the bytes go through writeFileAtomically (io/safe_write.h). No time stamp, so
// a file depends on its pixels and options only. The codec's messages end up in the one
// clhair::Error line, never on stderr; safe from several threads on different paths.
#pragma once

#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "clhair/image.h"

namespace clhair {

// Writes `pixels` (interleaved, of type `format`, laid out as `spec` says) to `path`, with
// `options`' compression for PNG and OpenEXR.
void writeImageFile(const std::string& path, OIIO::ImageSpec spec, OIIO::TypeDesc format,
                    const void* pixels, const ImageWriteOptions& options);

// Whether the path's extension is one of the formats written (a fixed table, ".png", ".exr",
// ...), and whether that format stores an alpha channel; the table's extensions.
bool imageFormatWritable(const std::string& path);
bool imageFormatHasAlpha(const std::string& path);
std::vector<std::string> imageFormatExtensions();

// readImage's work (io/image_read.cpp); readImage (io/image_io.cpp) calls it.
Image readImageFile(const std::string& path);

}  // namespace clhair
