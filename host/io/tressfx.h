// tressfx.h — AMD TressFX `.tfx` strand files, binary layouts of TressFX 3.x and 4.x.
//
// Both layouts are little endian: a fixed header, then arrays found through byte offsets
// in the header (relative to the start of the file, 0 = array absent). Every strand has the
// same number of vertices. The first field, a float, tells the layouts apart:
//
//   3.x (version 3.0 <= v < 4.0), 296-byte header
//     0  float version          4  u32 strands            8  u32 vertices per strand
//    12  u32 follow hairs per guide (ignored)   16  u8 both ends immovable (ignored), 3 pad
//    20  u32 reserved[31]
//   144  u32 vertex positions   float xyz per vertex
//   148  u32 strand thickness   float per strand          (checked to fit, not read)
//   152  u32 strand uv          float uv per strand
//   156  u32 vertex colour      float rgba per vertex     (checked to fit, not read)
//   160  u32 guide strand index u32 per strand            (checked to fit, not read)
//   164  u32 vertex uv          float uv per vertex       (checked to fit, not read)
//   168  u32 reserved[32]
//
//   4.x (version 4.0 <= v < 5.0), 160-byte header
//     0  float version          4  u32 strands            8  u32 vertices per strand
//    12  u32 vertex positions   float xyzw per vertex, w = inverse mass (0: pinned)
//    16  u32 strand uv          float uv per strand
//    20  u32 vertex uv          float uv per vertex       (checked to fit, not read)
//    24  u32 strand thickness   float per strand          (checked to fit, not read)
//    28  u32 vertex colour      float rgba per vertex     (checked to fit, not read)
//    32  u32 reserved[32]
//
// AMD's runtime wants 4, 8, 16, 32 or 64 vertices per strand; the reader takes any count
// of 2 or more. The older text layout of TressFX 1.x/2.x is refused with a message that
// says so. Reading trusts nothing in the header: every array it names must lie inside the
// file and past the header, and the arrays kept must fit the caller's byte limit, before
// anything is allocated; every float read (w included) must be finite. Bytes after the
// last array are counted in `hair.trailingBytes` so that a caller can warn.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "io/cyhair.h"

namespace clhair {

struct TressFxHair {
  CyHair hair;                  // every strand has verticesPerStrand points; no colours
  std::vector<float> strandUv;  // u, v per strand, or empty (the file has none)
  float version = 4.0f;         // as read; the writer always writes 4.0
};

// Throws clhair::Error, one line naming the file, for a file shorter than its header, an
// unknown version (or the text layout), zero strands, fewer than 2 vertices per strand, an
// array offset inside the header or an array that runs past the end of the file, a
// non-finite float, or arrays that would take more than `maxBytes` in memory (4 bytes per
// strand, 12 per point, 8 per strand for uv). Pass the device's largest allocation.
TressFxHair readTressFx(const std::string& path, std::uint64_t maxBytes);

// Writes the 4.0 layout: header, positions (w = 0 for each strand's first two vertices,
// which TressFX's simulation pins, 1 elsewhere), then strand uv when given. Every strand
// must have the same point count (resampleStrands makes it so); thickness, transparency
// and colours have no place here and are dropped. The file is replaced atomically. Throws
// clhair::Error for unequal counts, fewer than 2 points, a uv array of the wrong length,
// or a file that would be 4 GiB or more (the offsets are 32-bit).
void writeTressFx(const TressFxHair& tfx, const std::string& path);

// The point count export-strands resamples to: the largest of 4, 8, 16, 32 and 64 that is
// not above the longest strand's point count (4 for shorter strands), since AMD's runtime
// takes only those.
std::uint32_t tressFxVertexCount(const CyHair& hair);

// Every strand resampled to `points` points (>= 2) evenly spaced along its arc length: the
// root and the tip are kept exactly, the points between are linear interpolations of the
// polyline. A strand of zero length (or a single point) becomes `points` copies of its
// root. Per-point thickness, transparency and colours are dropped.
CyHair resampleStrands(const CyHair& hair, std::uint32_t points);

}  // namespace clhair
