// image_file.h — the one way clhair writes an image file: OpenImageIO into a temporary in
// the target's folder, renamed into place, so a reader or a killed job never sees half a
// file; no time stamp, so a file depends on its pixels only.
#pragma once

#include <string>

#include <OpenImageIO/imageio.h>

namespace clhair {

// Writes `pixels` (interleaved, of type `format`, laid out as `spec` says) to `path`.
// `noWriter` is the error when OpenImageIO has no writer for the path's extension.
void writeImageFile(const std::string& path, OIIO::ImageSpec spec, OIIO::TypeDesc format,
                    const void* pixels, const std::string& noWriter);

}  // namespace clhair
