// groom_cache.h — the device forms of the grooms a renderer has met, keyed by the identity
// of their HairMesh or StrandGroom (held, so an address is never reused while cached).
// Bounded: after a frame, grooms that frame did not draw are released, least recently
// used first, until at most `keepUnused` of them remain (a caller alternating between
// scenes keeps its grooms; one that walks through many releases them).
#pragma once

#include <cstdint>
#include <map>
#include <memory>

#include "groom/groom_gpu.h"

namespace clhair {

class GroomCache {
 public:
  explicit GroomCache(GroomStages& stages, std::size_t keepUnused = 8)
      : stages_(stages), keepUnused_(keepUnused) {}
  // The device form of `gi`'s groom, built on first use and deformed to `gi.deformed`; marks
  // it used in this frame.
  GroomGpu& get(const GroomInstance& gi);
  // Starts a frame (grooms fetched from now on count as its own).
  void beginFrame() { ++frame_; }
  // Releases unused grooms beyond the bound.
  void trim();
  // Releases every groom not used in the current frame.
  void releaseUnused();
  std::size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    std::shared_ptr<const void> held;
    std::unique_ptr<GroomGpu> groom;
    std::uint64_t lastFrame = 0;
  };
  GroomStages& stages_;
  std::size_t keepUnused_;
  std::uint64_t frame_ = 1;
  std::map<const void*, Entry> entries_;
};

}  // namespace clhair
