// cryptomatte.h — ID mattes for compositors: the Cryptomatte layers of a frame
// (RenderOptions::cryptomatte, `--aov cryptomatte`, docs/aovs.md "Cryptomatte").
//
// Cryptomatte (Psyop's specification, v1.2) names every object of a layer, hashes the name
// with MurmurHash3_x86_32 (seed 0) and stores the hash as a 32-bit float whose exponent is
// moved off 0 and 255 (no denormal, infinity or NaN id). Each pixel keeps its ids ranked by
// coverage, two (id, coverage) pairs per RGBA channel set: <layer>00.R/G/B/A holds ranks 0
// and 1, <layer>01 ranks 2 and 3, and so on. The file's header names the layer under
// cryptomatte/<key>/ (key: the first 7 hex digits of the layer name's hash) with its name,
// hash, conversion and a JSON manifest of every name to its id's bits in hex.
//
// clhair writes two layers: CryptoGroom (one name per groom instance: its name in the scene)
// and CryptoStrand (one name per strand: "<groom>/<strand index at full detail>"). The
// coverages of a pixel sum to its hair alpha (the alpha layer): a groom's coverage is its
// alpha in the composite order, each later groom keeping (1 - its alpha) of it.
// Inputs and outputs only: nothing here touches the device.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace clhair {

// Ranks per pixel and layer: three RGBA channel sets, the depth the specification's
// reference implementations write by default.
constexpr int kCryptomatteRanks = 6;
// The layers' names (their channels' prefixes).
constexpr const char* kCryptoGroomLayer = "CryptoGroom";
constexpr const char* kCryptoStrandLayer = "CryptoStrand";

// MurmurHash3_x86_32 of the bytes of `text` (Appleby's reference, little-endian blocks).
std::uint32_t murmurHash3(const std::string& text, std::uint32_t seed = 0);
// The id's bits for a hash: bit 23 flipped where the exponent would be 0 or 255.
std::uint32_t cryptomatteIdBits(std::uint32_t hash);
// The id as the float stored in the channels.
float cryptomatteId(const std::string& name);
// The layer's key in the header: the first 7 hex digits of its name's hash.
std::string cryptomatteKey(const std::string& layerName);

// One layer of a frame: per rank a plane of width * height ids and coverages (rank-major:
// rank r of pixel p at r * pixels + p), ranks sorted by coverage, largest first; an empty
// rank has id 0 and coverage 0. `manifest`: every name that appears, to its id's bits.
struct CryptomatteLayer {
  std::string name;
  std::vector<float> ids, coverage;
  std::map<std::string, std::uint32_t> manifest;
};

// The matte of `name` in `layer`: per pixel the coverage of the ranks holding its id.
std::vector<float> cryptomatteMatte(const CryptomatteLayer& layer, const std::string& name);

}  // namespace clhair
