// usc_hair.h — the USC-HairSalon `.data` strand format (Hu et al. 2015, "Single-view hair
// modeling using a hairstyle database").
//
// Layout (little endian, no signature): int32 strand count, then per strand an int32
// point count followed by that many float xyz. Strands of fewer than 2 points have no
// segment to render; they are skipped and counted. The result is a CyHair with one segment
// fewer than points per strand, no per-point thickness, transparency or colour, and info
// "USC-HairSalon".
//
// Bytes after the last strand are not an error (as for cyHair): they are counted in the
// result's `hair.trailingBytes` so that a caller can warn, since the format has no
// signature and a file of another kind may also parse.
#pragma once

#include <cstdint>
#include <string>

#include "io/cyhair.h"

namespace clhair {

struct UscHair {
  CyHair hair;
  std::uint64_t skippedStrands = 0;  // strands of 0 or 1 points, left out of `hair`
};

// Throws clhair::Error, one line naming the file, for a file too short for its counts, a
// negative count, a non-finite coordinate, no strand of 2 or more points, or arrays that would take
// more than `maxBytes` in memory (4 bytes per kept strand plus 12 per kept point). Pass the
// device's largest allocation as `maxBytes`.
UscHair readUscHair(const std::string& path, std::uint64_t maxBytes);

// Writes the strands' points (segments + 1 per strand) as a USC-HairSalon file; thickness,
// transparency and colours have no place in the format and are dropped. The file is
// replaced atomically. Throws clhair::Error for arrays that do not match the segments or
// counts beyond int32.
void writeUscHair(const CyHair& hair, const std::string& path);

}  // namespace clhair
