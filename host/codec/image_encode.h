// image_encode.h — the one way the codec writes an image file: OpenImageIO encodes through
// an I/O proxy straight into an io/safe_write.h AtomicFile, a band of rows at a time. No time
// stamp, so a file depends on its pixels and options only. The codec's messages end up in the
// one clhair::Error line, never on stderr; safe from several threads on different paths.
#pragma once

#include <string>

#include <OpenImageIO/imageio.h>

#include "clhair/image.h"

namespace clhair {

// Writes `pixels` (interleaved, of type `format`, laid out as `spec` says) to `path`, with
// `options`' compression for PNG and OpenEXR.
void writeImageFile(const std::string& path, OIIO::ImageSpec spec, OIIO::TypeDesc format,
                    const void* pixels, const ImageWriteOptions& options);

}  // namespace clhair
