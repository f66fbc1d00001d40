// aov_io.cpp — the --aov list and a frame's layers as named channels (see clhair/aov.h,
// docs/aovs.md); codec/aov_write.cpp writes them as one multi-channel OpenEXR file.
#include <algorithm>
#include <cmath>

#include "clhair/aov.h"
#include "clhair/error.h"
#include "clhair/renderer.h"
#include "io/cryptomatte_io.h"
#include "io/json_util.h"

namespace clhair {

namespace {

constexpr Aov kAllAovs[] = {Aov::Rgba,   Aov::Z,      Aov::Alpha,      Aov::Tangent,
                            Aov::Motion, Aov::Strand, Aov::Cryptomatte};

std::string knownNames() {
  std::string names;
  for (Aov a : kAllAovs) names += std::string(names.empty() ? "" : ", ") + aovName(a);
  return names + " or all";
}

// Channel c of n interleaved per pixel.
std::vector<float> component(const std::vector<float>& data, int n, int c) {
  std::vector<float> out(data.size() / n);
  for (std::size_t p = 0; p < out.size(); ++p) out[p] = data[p * n + c];
  return out;
}

}  // namespace

const char* aovName(Aov aov) {
  switch (aov) {
    case Aov::Rgba:
      return "rgba";
    case Aov::Z:
      return "z";
    case Aov::Alpha:
      return "alpha";
    case Aov::Tangent:
      return "tangent";
    case Aov::Motion:
      return "motion";
    case Aov::Strand:
      return "strand";
    case Aov::Cryptomatte:
      return "cryptomatte";
  }
  return "?";
}

std::vector<Aov> parseAovList(const std::string& list) {
  std::vector<bool> want(std::size(kAllAovs), false);
  std::size_t begin = 0;
  while (true) {
    const std::size_t end = list.find(',', begin);
    const std::string name = list.substr(begin, end == std::string::npos ? end : end - begin);
    if (name == "all") {  // every layer but the ID mattes, which are asked for by name
      for (std::size_t k = 0; k < want.size(); ++k)
        want[k] = want[k] || kAllAovs[k] != Aov::Cryptomatte;
    } else {
      std::size_t k = 0;
      while (k < std::size(kAllAovs) && name != aovName(kAllAovs[k])) ++k;
      if (k == std::size(kAllAovs))
        throw Error(
            "--aov \"" + list + "\": " +
            (name.empty() ? std::string("an empty name") : "unknown layer \"" + name + "\"") +
            "; expected a comma-separated list of " + knownNames());
      want[k] = true;
    }
    if (end == std::string::npos) break;
    begin = end + 1;
  }
  std::vector<Aov> out;
  for (std::size_t k = 0; k < want.size(); ++k)
    if (want[k]) out.push_back(kAllAovs[k]);
  return out;
}

namespace {

// Frame `before`'s hair alpha carried to `now`'s pixels along `now`'s motion (scaled by
// `scale`: 1 warps, 0 does not), thresholded, against `now`'s hair mask: intersection over
// union.
double warpIoU(const FrameAovs& now, const FrameAovs& before, int width, int height, float scale) {
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (now.hairAlpha.size() != n || before.hairAlpha.size() != n || now.motion.size() != 2 * n ||
      now.z.size() != n)
    throw Error("mask IoU: both frames need their AOVs at " + std::to_string(width) + "x" +
                std::to_string(height));
  // frame t's alpha, bilinear between pixel centres, 0 outside the image
  auto alphaAt = [&](float x, float y) {
    x -= 0.5f;
    y -= 0.5f;
    const float fx0 = std::floor(x), fy0 = std::floor(y);
    const int x0 = static_cast<int>(fx0), y0 = static_cast<int>(fy0);
    const float tx = x - fx0, ty = y - fy0;
    float sum = 0.0f;
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const int xx = x0 + dx, yy = y0 + dy;
        if (xx < 0 || yy < 0 || xx >= width || yy >= height) continue;
        sum += (dx ? tx : 1.0f - tx) * (dy ? ty : 1.0f - ty) *
               before.hairAlpha[static_cast<std::size_t>(yy) * width + xx];
      }
    return sum;
  };
  std::size_t both = 0, either = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      // the motion of the nearest surface around the pixel, so that background the hair has
      // just uncovered follows the hair (the reprojection of temporal filters)
      std::size_t q = static_cast<std::size_t>(y) * width + x;
      float best = now.z[q];
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= width || yy >= height) continue;
          const std::size_t k = static_cast<std::size_t>(yy) * width + xx;
          if (now.z[k] < best) {
            best = now.z[k];
            q = k;
          }
        }
      const float px = static_cast<float>(x) + 0.5f + scale * now.motion[2 * q];
      const float py = static_cast<float>(y) + 0.5f - scale * now.motion[2 * q + 1];
      const bool a = alphaAt(px, py) >= 0.5f;
      const bool b = now.hairAlpha[static_cast<std::size_t>(y) * width + x] >= 0.5f;
      both += a && b;
      either += a || b;
    }
  return either == 0 ? 1.0 : static_cast<double>(both) / static_cast<double>(either);
}

// The frame's Cryptomatte layers. A frame rendered with AOVs in which no groom was drawn
// has none (the pass runs with the grooms): its layers are empty, as nothing covers a pixel.
std::vector<CryptomatteLayer> cryptomatteOf(const Frame& frame) {
  if (!frame.cryptomatte.empty()) return frame.cryptomatte;
  const bool bare = std::all_of(frame.aovs.hairAlpha.begin(), frame.aovs.hairAlpha.end(),
                                [](float a) { return a == 0.0f; });
  if (!bare)
    throw Error("the layer \"cryptomatte\" needs a frame rendered with RenderOptions::cryptomatte");
  const std::size_t pixels =
      static_cast<std::size_t>(frame.color.width) * static_cast<std::size_t>(frame.color.height);
  std::vector<CryptomatteLayer> layers(2);
  layers[0].name = kCryptoGroomLayer;
  layers[1].name = kCryptoStrandLayer;
  for (CryptomatteLayer& l : layers) {
    l.ids.assign(pixels * kCryptomatteRanks, 0.0f);
    l.coverage.assign(pixels * kCryptomatteRanks, 0.0f);
  }
  return layers;
}

}  // namespace

double motionWarpIoU(const FrameAovs& now, const FrameAovs& before, int width, int height) {
  return warpIoU(now, before, width, height, 1.0f);
}

double maskIoU(const FrameAovs& now, const FrameAovs& before, int width, int height) {
  return warpIoU(now, before, width, height, 0.0f);
}

std::vector<ImageChannel> aovChannels(const Frame& frame, const std::vector<Aov>& layers) {
  const std::size_t pixels =
      static_cast<std::size_t>(frame.color.width) * static_cast<std::size_t>(frame.color.height);
  std::vector<ImageChannel> out;
  for (Aov a : layers) {
    if (a != Aov::Rgba && frame.aovs.z.size() != pixels)
      throw Error(std::string("the layer \"") + aovName(a) +
                  "\" needs a frame rendered with RenderOptions::aovs");
    if (a == Aov::Strand && frame.aovs.strand.size() != pixels * 3)
      throw Error("the layer \"strand\" needs a frame rendered with RenderOptions::strandIds");
    switch (a) {
      case Aov::Rgba:
        for (int c = 0; c < 4; ++c)
          out.push_back({std::string(1, "RGBA"[c]), component(frame.color.rgba, 4, c), true});
        break;
      case Aov::Z:
        out.push_back({"Z", frame.aovs.z, false});
        break;
      case Aov::Alpha:
        out.push_back({"hair.A", frame.aovs.hairAlpha, true});
        break;
      case Aov::Tangent:
        for (int c = 0; c < 3; ++c)
          out.push_back(
              {std::string("tangent.") + "XYZ"[c], component(frame.aovs.tangent, 3, c), true});
        break;
      case Aov::Motion:
        for (int c = 0; c < 2; ++c)
          out.push_back(
              {std::string("motion.") + "XY"[c], component(frame.aovs.motion, 2, c), false});
        break;
      case Aov::Strand:  // full 32-bit floats: the indices are exact below 2^24
        out.push_back({"strand.groom", component(frame.aovs.strand, 3, 0), false});
        out.push_back({"strand.id", component(frame.aovs.strand, 3, 1), false});
        out.push_back({"strand.u", component(frame.aovs.strand, 3, 2), false});
        break;
      case Aov::Cryptomatte:
        for (ImageChannel& c : cryptomatteChannels(cryptomatteOf(frame), pixels))
          out.push_back(std::move(c));
        break;
    }
  }
  return out;
}

std::vector<ImageAttribute> aovAttributes(const Frame& frame, const std::vector<Aov>& layers) {
  if (std::find(layers.begin(), layers.end(), Aov::Cryptomatte) == layers.end()) return {};
  return cryptomatteAttributes(cryptomatteOf(frame));
}

}  // namespace clhair
