// image_codec.h — the image codec (host/codec/: OpenImageIO and the many libraries it brings)
// as a table of three functions, so a program can load it on first use instead of at start.
//
// The codec writes images of every format but PNG (encodeImage, io/image_file.h; PNG is libpng's,
// io/png_write.cpp, which needs no module), multi-channel OpenEXR files
// (writeChannels, clhair/aov.h) and reads images (readImageFile, io/image_file.h). Everything
// else about images (the formats written, the checks of names and options) lives in io/ and
// needs no codec. clhair_core links the codec itself: the tests, the benchmark and the Python
// module call it directly. The command links every layer but the codec and defines the three
// functions in cli/image_codec_loader.cpp, which loads the codec module (the codec's objects
// built as libclhair_image_codec.so beside the command) on the first image it reads or writes
// and calls through this table. OpenImageIO's 250 or so libraries cost about 0.2 s of dynamic
// linking at every start (bench/suite.md); a command that writes no image no longer pays it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "clhair/aov.h"
#include "clhair/image.h"

namespace clhair {

// Each entry returns 0 when it succeeds and 1 with the clhair::Error's message in `error`
// (at most `capacity` bytes with its terminating zero) when it fails: no exception crosses
// the module's edge, so the command and the module need not share a C++ runtime (a command
// linked with a static libstdc++, as ../shared/gpu/bundle.sh links it, may load the module).
struct ImageCodec {
  std::uint64_t abi;  // kImageCodecAbi of the build that made the module
  int (*encodeImage)(const Image& image, const std::string& path, const ImageWriteOptions& options,
                     char* error, std::size_t capacity) noexcept;
  int (*writeChannels)(const std::vector<ImageChannel>& channels, int width, int height,
                       const std::string& path, const ImageWriteOptions& options,
                       const std::vector<ImageAttribute>& attributes, char* error,
                       std::size_t capacity) noexcept;
  int (*readImageFile)(const std::string& path, Image* out, char* error,
                       std::size_t capacity) noexcept;
};

// Changes with the table's version and with the layout of what it passes: a module whose
// table or types differ from the command's is refused, not called. (It does not tell two
// builds of the same layout apart: the command looks for the module beside itself first.)
constexpr std::uint64_t kImageCodecAbi =
    (std::uint64_t(3) << 56) ^ (std::uint64_t(sizeof(ImageCodec)) << 44) ^
    (std::uint64_t(sizeof(Image)) << 34) ^ (std::uint64_t(sizeof(ImageWriteOptions)) << 24) ^
    (std::uint64_t(sizeof(ImageChannel)) << 12) ^
    std::uint64_t(sizeof(ImageAttribute) + sizeof(std::string));

// The module's file name, and the one function it exports (extern "C", no mangling).
constexpr const char* kImageCodecModule = "libclhair_image_codec.so";
constexpr const char* kImageCodecEntry = "clhair_image_codec";

}  // namespace clhair
