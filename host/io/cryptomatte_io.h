// cryptomatte_io.h — the Cryptomatte layers of a frame (clhair/cryptomatte.h) from the ranked
// lists the device gathered, and as the channels and header attributes of an OpenEXR file.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "clhair/aov.h"
#include "clhair/cryptomatte.h"

namespace clhair {

// The layer `name` from the device's ranks (rank-major, kCryptomatteRanks planes of `pixels`):
// keys (all ones: an empty rank) named by `nameOf`, and their coverages. Names are hashed
// once each; ranks whose keys hash alike are merged and re-sorted.
CryptomatteLayer cryptomatteLayer(const std::string& name, std::size_t pixels,
                                  const std::vector<std::uint64_t>& keys,
                                  const std::vector<float>& coverage,
                                  const std::function<std::string(std::uint64_t)>& nameOf);

// The layers' channels: per layer kCryptomatteRanks / 2 RGBA sets <name>00, <name>01, ...,
// each holding two ranks (id, coverage, id, coverage) as 32-bit floats.
std::vector<ImageChannel> cryptomatteChannels(const std::vector<CryptomatteLayer>& layers,
                                              std::size_t pixels);
// The layers' header attributes: cryptomatte/<key>/name, hash, conversion and manifest.
std::vector<ImageAttribute> cryptomatteAttributes(const std::vector<CryptomatteLayer>& layers);

}  // namespace clhair
