// tuning.cpp — see tuning.h.
#include "cl/tuning.h"

#include <algorithm>

namespace clhair {

namespace {
// Strands per work-group with one lane per strand, measured with clhair_bench on PoCL 3.1
// (2-core Xeon, groom1 at 1080p): see DESIGN.md "Lanes per strand".
constexpr std::uint32_t kCpuStrandsPerGroup = 32;
constexpr std::uint32_t kMaxStrandsPerGroup = 256;
constexpr std::uint32_t kGpuLanes = 32;
}  // namespace

StrandTuning strandTuning(const DeviceInfo& info, SubgroupBackend backend, std::uint32_t override) {
  StrandTuning t;
  if (backend != SubgroupBackend::Single) {
    t.lanes = kGpuLanes;
    t.strandsPerGroup = 1;
    return t;
  }
  t.lanes = 1;
  t.strandsPerGroup = override > 0 ? std::min(override, kMaxStrandsPerGroup)
                                   : (info.isGpu ? kGpuLanes : kCpuStrandsPerGroup);
  return t;
}

}  // namespace clhair
