// image_codec_loader.cpp — the command's image codec: the three codec functions of
// io/image_codec.h, defined here to load the codec module on first use and call through its
// table. The command links every layer but the codec (CMakeLists.txt), so OpenImageIO and the
// libraries it brings are loaded by the first image read or written, not at start.
//
// The module is CLHAIR_IMAGE_CODEC when set (a path), else the file beside the command
// (/proc/self/exe's folder) when there is one, else the one where the build put it. A module
// that cannot be loaded, that lacks the table or whose table differs is one clhair::Error
// naming the path and why; the next image tries again. The codec's own errors come back
// through the table as messages and are thrown here as the clhair::Error they were. The module is
// not loaded ahead of the first image: a command built with another writer for plain images
// (../shared/gpu/bundle.sh swaps io/image_io.cpp for a PPM writer on machines without the codec's
// libraries) never needs it.
#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "clhair/error.h"
#include "io/image_codec.h"
#include "io/image_file.h"

namespace clhair {

namespace {

std::string commandFolder() {
  std::vector<char> buf(4096);
  const ssize_t n = ::readlink("/proc/self/exe", buf.data(), buf.size() - 1);
  if (n <= 0) return {};
  const std::string exe(buf.data(), static_cast<std::size_t>(n));
  const std::size_t slash = exe.rfind('/');
  return slash == std::string::npos ? std::string() : exe.substr(0, slash);
}

// The places to look, in order.
std::vector<std::string> modulePaths() {
  if (const char* p = std::getenv("CLHAIR_IMAGE_CODEC"); p && *p) return {p};
  std::vector<std::string> paths;
  if (const std::string dir = commandFolder(); !dir.empty())
    paths.push_back(dir + "/" + kImageCodecModule);
#ifdef CLHAIR_IMAGE_CODEC_BUILT
  paths.push_back(CLHAIR_IMAGE_CODEC_BUILT);
#endif
  return paths;
}

// The codec of the first place that holds a file: that file is the codec, or the error says
// why not (a broken module beside the command is not passed over for another build's). A
// refused module stays loaded: its libraries may have started threads.
const ImageCodec* loadCodec() {
  const std::vector<std::string> paths = modulePaths();
  for (const std::string& path : paths) {
    if (::access(path.c_str(), F_OK) != 0 && paths.size() > 1) continue;
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* e = ::dlerror();
      throw Error("cannot load the image codec: " + (e ? std::string(e) : path));
    }
    using Entry = const ImageCodec* (*)();
    auto entry = reinterpret_cast<Entry>(::dlsym(handle, kImageCodecEntry));
    const ImageCodec* codec = entry ? entry() : nullptr;
    if (!codec)
      throw Error("cannot load the image codec: " + path + " is not clhair's image codec (no " +
                  kImageCodecEntry + ")");
    if (codec->abi != kImageCodecAbi)
      throw Error("cannot load the image codec: " + path +
                  " was built for another clhair (rebuild clhair)");
    return codec;  // kept loaded for the process
  }
  std::string where;
  for (const std::string& path : paths) where += (where.empty() ? "" : ", ") + path;
  throw Error("cannot load the image codec: " + std::string(kImageCodecModule) + " is in none of " +
              (where.empty() ? std::string("(no place to look)") : where));
}

// Loaded once, by the first caller (a static's initialisation is thread-safe; one that throws
// is tried again by the next call).
const ImageCodec& codec() {
  static const ImageCodec* const loaded = loadCodec();
  return *loaded;
}

// Throws the codec's message as the clhair::Error it was.
void check(int failed, const char* message) {
  if (failed) throw Error(message);
}

constexpr std::size_t kMessageBytes = 4096;

}  // namespace

void encodeImage(const Image& image, const std::string& path, const ImageWriteOptions& options) {
  char message[kMessageBytes] = "";
  check(codec().encodeImage(image, path, options, message, sizeof(message)), message);
}

void writeChannels(const std::vector<ImageChannel>& channels, int width, int height,
                   const std::string& path, const ImageWriteOptions& options,
                   const std::vector<ImageAttribute>& attributes) {
  char message[kMessageBytes] = "";
  check(codec().writeChannels(channels, width, height, path, options, attributes, message,
                              sizeof(message)),
        message);
}

Image readImageFile(const std::string& path) {
  char message[kMessageBytes] = "";
  Image image;
  check(codec().readImageFile(path, &image, message, sizeof(message)), message);
  return image;
}

}  // namespace clhair
