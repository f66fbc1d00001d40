// cryptomatte_io.cpp — MurmurHash3, the id conversion, the layers from the device's ranks and
// their channels and header (clhair/cryptomatte.h, io/cryptomatte_io.h).
#include "io/cryptomatte_io.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <unordered_map>

#include "clhair/error.h"

namespace clhair {

namespace {

std::uint32_t rotl32(std::uint32_t x, int r) { return (x << r) | (x >> (32 - r)); }

std::uint32_t fmix32(std::uint32_t h) {
  h ^= h >> 16;
  h *= 0x85ebca6bu;
  h ^= h >> 13;
  h *= 0xc2b2ae35u;
  h ^= h >> 16;
  return h;
}

std::string hex8(std::uint32_t v) {
  char s[9];
  std::snprintf(s, sizeof s, "%08x", v);
  return s;
}

float bitsToFloat(std::uint32_t bits) {
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

constexpr std::uint64_t kNoKey = ~std::uint64_t(0);

}  // namespace

std::uint32_t murmurHash3(const std::string& text, std::uint32_t seed) {
  constexpr std::uint32_t c1 = 0xcc9e2d51u, c2 = 0x1b873593u;
  const auto* data = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t len = text.size(), blocks = len / 4;
  std::uint32_t h = seed;
  for (std::size_t i = 0; i < blocks; ++i) {  // little-endian blocks, whatever the host
    const unsigned char* b = data + 4 * i;
    std::uint32_t k = std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 |
                      std::uint32_t(b[3]) << 24;
    k *= c1;
    k = rotl32(k, 15);
    k *= c2;
    h ^= k;
    h = rotl32(h, 13);
    h = h * 5 + 0xe6546b64u;
  }
  const unsigned char* tail = data + 4 * blocks;
  std::uint32_t k = 0;
  switch (len & 3) {
    case 3:
      k ^= std::uint32_t(tail[2]) << 16;
      [[fallthrough]];
    case 2:
      k ^= std::uint32_t(tail[1]) << 8;
      [[fallthrough]];
    case 1:
      k ^= tail[0];
      k *= c1;
      k = rotl32(k, 15);
      k *= c2;
      h ^= k;
  }
  h ^= static_cast<std::uint32_t>(len);
  return fmix32(h);
}

std::uint32_t cryptomatteIdBits(std::uint32_t hash) {
  const std::uint32_t exponent = (hash >> 23) & 0xffu;
  // an exponent of 0 (denormals) or 255 (infinity, NaN) moves to 1 or 254
  return exponent == 0 || exponent == 255 ? hash ^ (1u << 23) : hash;
}

float cryptomatteId(const std::string& name) {
  return bitsToFloat(cryptomatteIdBits(murmurHash3(name)));
}

std::string cryptomatteKey(const std::string& layerName) {
  return hex8(murmurHash3(layerName)).substr(0, 7);
}

std::vector<float> cryptomatteMatte(const CryptomatteLayer& layer, const std::string& name) {
  const std::size_t pixels = layer.coverage.size() / kCryptomatteRanks;
  const float id = cryptomatteId(name);
  std::vector<float> matte(pixels, 0.0f);
  for (std::size_t r = 0; r < static_cast<std::size_t>(kCryptomatteRanks); ++r)
    for (std::size_t p = 0; p < pixels; ++p)
      if (layer.coverage[r * pixels + p] > 0.0f && layer.ids[r * pixels + p] == id)
        matte[p] += layer.coverage[r * pixels + p];
  return matte;
}

CryptomatteLayer cryptomatteLayer(const std::string& name, std::size_t pixels,
                                  const std::vector<std::uint64_t>& keys,
                                  const std::vector<float>& coverage,
                                  const std::function<std::string(std::uint64_t)>& nameOf) {
  const std::size_t ranks = kCryptomatteRanks;
  if (keys.size() != ranks * pixels || coverage.size() != ranks * pixels)
    throw Error("cryptomatte layer " + name + ": " + std::to_string(keys.size()) + " keys and " +
                std::to_string(coverage.size()) + " coverages for " + std::to_string(pixels) +
                " pixels of " + std::to_string(ranks) + " ranks");
  CryptomatteLayer out;
  out.name = name;
  out.ids.assign(ranks * pixels, 0.0f);
  out.coverage.assign(ranks * pixels, 0.0f);
  std::unordered_map<std::uint64_t, std::uint32_t> bits;  // key -> id bits
  std::vector<std::pair<std::uint32_t, float>> pix;
  for (std::size_t p = 0; p < pixels; ++p) {
    pix.clear();
    for (std::size_t r = 0; r < ranks; ++r) {
      const std::uint64_t key = keys[r * pixels + p];
      const float c = coverage[r * pixels + p];
      if (key == kNoKey || !(c > 0.0f)) continue;
      auto it = bits.find(key);
      if (it == bits.end()) {
        const std::string n = nameOf(key);
        it = bits.emplace(key, cryptomatteIdBits(murmurHash3(n))).first;
        out.manifest.emplace(n, it->second);
      }
      auto same = std::find_if(pix.begin(), pix.end(),
                               [&](const auto& e) { return e.first == it->second; });
      if (same != pix.end())
        same->second += c;
      else
        pix.emplace_back(it->second, c);
    }
    std::stable_sort(pix.begin(), pix.end(),
                     [](const auto& a, const auto& b) { return a.second > b.second; });
    for (std::size_t r = 0; r < pix.size(); ++r) {
      out.ids[r * pixels + p] = bitsToFloat(pix[r].first);
      out.coverage[r * pixels + p] = pix[r].second;
    }
  }
  return out;
}

std::vector<ImageChannel> cryptomatteChannels(const std::vector<CryptomatteLayer>& layers,
                                              std::size_t pixels) {
  std::vector<ImageChannel> out;
  for (const CryptomatteLayer& layer : layers) {
    if (layer.ids.size() != pixels * kCryptomatteRanks ||
        layer.coverage.size() != pixels * kCryptomatteRanks)
      throw Error("cryptomatte layer " + layer.name + " is not sized for " +
                  std::to_string(pixels) + " pixels");
    for (int set = 0; set < kCryptomatteRanks / 2; ++set) {
      char suffix[8];
      std::snprintf(suffix, sizeof suffix, "%02d.", set);
      for (int c = 0; c < 4; ++c) {
        const std::size_t rank = static_cast<std::size_t>(2 * set + c / 2);
        const std::vector<float>& from = c % 2 == 0 ? layer.ids : layer.coverage;
        out.push_back(
            {layer.name + suffix + "RGBA"[c],
             std::vector<float>(from.begin() + rank * pixels, from.begin() + (rank + 1) * pixels),
             false});
      }
    }
  }
  return out;
}

std::vector<ImageAttribute> cryptomatteAttributes(const std::vector<CryptomatteLayer>& layers) {
  std::vector<ImageAttribute> out;
  for (const CryptomatteLayer& layer : layers) {
    const std::string at = "cryptomatte/" + cryptomatteKey(layer.name) + "/";
    nlohmann::ordered_json manifest = nlohmann::ordered_json::object();
    for (const auto& [name, bits] : layer.manifest) manifest[name] = hex8(bits);
    out.push_back({at + "conversion", "uint32_to_float32"});
    out.push_back({at + "hash", "MurmurHash3_32"});
    out.push_back({at + "manifest", manifest.dump()});
    out.push_back({at + "name", layer.name});
  }
  return out;
}

}  // namespace clhair
