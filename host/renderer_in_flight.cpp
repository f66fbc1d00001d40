// renderer_in_flight.cpp — the frames a Renderer has submitted and not yet handed out: at most
// Renderer::framesInFlight() of them run on the device while the host builds the next; the
// oldest is waited for when one more would exceed that, and a frame is handed out (and its
// results decoded) by Renderer::wait.
#include <algorithm>

#include "cl/buffers.h"
#include "renderer_impl.h"

namespace clhair {

cl::Buffer& Renderer::Impl::statsBuffer(std::size_t words) {
  ensureCapacity<cl_uint>(dev, frameStats, frameStatsCap, "frame statistics", words);
  return frameStats;
}

std::uint64_t Renderer::Impl::enqueue(std::unique_ptr<PendingFrame> p) {
  p->ticket = nextTicket++;
  const std::uint64_t ticket = p->ticket;
  inFlight.push_back(std::move(p));
  drainTo(static_cast<std::size_t>(maxInFlight));
  return ticket;
}

void Renderer::Impl::drainTo(std::size_t limit) {
  std::size_t running = 0;
  for (const auto& p : inFlight) running += p->complete ? 0 : 1;
  for (auto& p : inFlight) {
    if (running <= limit) break;
    if (p->complete) continue;
    p->finish(dev, pinned);
    --running;
  }
}

std::vector<Frame> Renderer::Impl::waitFor(std::uint64_t ticket) {
  auto it = std::find_if(inFlight.begin(), inFlight.end(),
                         [&](const auto& p) { return p->ticket == ticket; });
  if (it == inFlight.end())
    throw Error("frame " + std::to_string(ticket) + " was not submitted or was already waited for");
  std::unique_ptr<PendingFrame> p = std::move(*it);
  inFlight.erase(it);
  p->finish(dev, pinned);
  for (Frame& f : p->frames) f.stats.hostWaits = p->waits;
  return std::move(p->frames);
}

}  // namespace clhair
