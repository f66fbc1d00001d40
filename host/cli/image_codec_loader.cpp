// image_codec_loader.cpp — the command's image codec: the three codec functions of
// io/image_codec.h, defined here to load the codec module on first use and call through its
// table. The command links every layer but the codec (CMakeLists.txt), so OpenImageIO and the
// libraries it brings are loaded by the first image read or written, not at start.
//
// The module is looked for in CLHAIR_IMAGE_CODEC when set (a path), else beside the command
// (/proc/self/exe's folder), else where the build put it. A module that cannot be loaded, that
// lacks the table or that was built for another clhair is one clhair::Error naming the path
// and why; the next image tries again. The module is not loaded ahead of the first image: a
// command built with another writer for plain images (../shared/gpu/bundle.sh swaps
// io/image_io.cpp for a PPM writer on machines without the codec's libraries) never needs it.
#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
#include <mutex>
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

const ImageCodec* loadCodec() {
  std::string why;
  for (const std::string& path : modulePaths()) {
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* e = ::dlerror();
      why = e ? e : path + ": cannot be loaded";
      continue;
    }
    using Entry = const ImageCodec* (*)();
    auto entry = reinterpret_cast<Entry>(::dlsym(handle, kImageCodecEntry));
    const ImageCodec* codec = entry ? entry() : nullptr;
    if (!codec) {
      why = path + ": not clhair's image codec (no " + kImageCodecEntry + ")";
      ::dlclose(handle);
      continue;
    }
    if (codec->abi != kImageCodecAbi) {
      why = path + ": built for another clhair (rebuild clhair)";
      ::dlclose(handle);
      continue;
    }
    return codec;  // kept loaded for the process
  }
  if (why.empty()) why = "no place to look for " + std::string(kImageCodecModule);
  throw Error("cannot load the image codec: " + why);
}

const ImageCodec& codec() {
  static std::mutex m;
  static const ImageCodec* loaded = nullptr;
  std::lock_guard<std::mutex> lock(m);
  if (!loaded) loaded = loadCodec();
  return *loaded;
}

}  // namespace

void writeImage(const Image& image, const std::string& path, const ImageWriteOptions& options) {
  codec().writeImage(image, path, options);
}

void writeChannels(const std::vector<ImageChannel>& channels, int width, int height,
                   const std::string& path, const ImageWriteOptions& options,
                   const std::vector<ImageAttribute>& attributes) {
  codec().writeChannels(channels, width, height, path, options, attributes);
}

Image readImageFile(const std::string& path) { return codec().readImageFile(path); }

}  // namespace clhair
