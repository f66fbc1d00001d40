// groom_cache.cpp — see groom_cache.h.
#include "groom/groom_cache.h"

#include <algorithm>
#include <vector>

namespace clhair {

GroomGpu& GroomCache::get(const GroomInstance& gi) {
  const std::shared_ptr<const void> key =
      gi.strands ? std::shared_ptr<const void>(gi.strands) : std::shared_ptr<const void>(gi.mesh);
  auto it = entries_.find(key.get());
  if (it == entries_.end()) {
    Entry e;
    e.groom = makeGroomGpu(gi, stages_);
    e.held = key;
    it = entries_.emplace(key.get(), std::move(e)).first;
  }
  Entry& e = it->second;
  e.groom->deform(gi.deformed);
  e.lastFrame = frame_;
  return *e.groom;
}

void GroomCache::trim() {
  std::vector<std::pair<std::uint64_t, const void*>> unused;
  for (const auto& [key, e] : entries_)
    if (e.lastFrame != frame_) unused.push_back({e.lastFrame, key});
  if (unused.size() <= keepUnused_) return;
  std::sort(unused.begin(), unused.end());
  for (std::size_t i = 0; i + keepUnused_ < unused.size(); ++i) entries_.erase(unused[i].second);
}

void GroomCache::releaseUnused() {
  for (auto it = entries_.begin(); it != entries_.end();)
    it = it->second.lastFrame == frame_ ? std::next(it) : entries_.erase(it);
}

}  // namespace clhair
