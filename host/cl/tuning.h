// tuning.h — the one table of per-device launch shapes for the strand kernels.
//
// A strand is drawn by `lanes` work-items (one logical sub-group, kernels/common/
// subgroup.h) and a work-group holds `strandsPerGroup` strands. GPUs use 32 cooperating
// lanes and one strand per group (Lipp et al. §3.1.1). CPUs use the single-lane backend:
// one work-item per strand and many strands per group, so a CPU compiler sees plain
// sequential code without barriers and a work-group amortises the runtime's per-group
// cost over many strands. Values come from measurements (DESIGN.md, "Lanes per strand");
// CLHAIR_STRANDS_PER_GROUP (or DeviceOptions::strandsPerGroup) overrides the table.
#pragma once

#include <cstdint>

#include "clhair/device.h"

namespace clhair {

struct StrandTuning {
  std::uint32_t lanes = 32;           // work-items per strand (SG_SIZE)
  std::uint32_t strandsPerGroup = 1;  // strands per work-group (SG_STRANDS)
  std::uint32_t groupSize() const { return lanes * strandsPerGroup; }
};

// The launch shape for `backend` on the device `info` describes; `override` > 0 replaces
// the table's strands per group (single-lane backend only; others keep one strand).
StrandTuning strandTuning(const DeviceInfo& info, SubgroupBackend backend,
                          std::uint32_t override = 0);

}  // namespace clhair
