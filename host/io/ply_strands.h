// ply_strands.h — strands in PLY files (the layout of the CT2Hair scans' strand exports) and
// in CT2Hair's own `.bin` files.
//
// PLY (`.ply`, ascii, binary_little_endian or binary_big_endian 1.0): an `element vertex`
// with scalar properties x, y, z (any numeric type) and optionally red, green, blue (uchar:
// 8-bit sRGB, turned linear; float or double: linear in [0, 1]); other vertex properties are
// skipped. The strands are given by
//   - an element `strand` (or `curve`) with a scalar integer count (uchar to uint32) named
//     for segments (`nsegs`, `segment_count`, ...: points = segments + 1) or for points
//     (`vertex_count`, `num_vertices`, ...; the full lists in ply_layout.h), other properties
//     skipped, strands taking consecutive vertices in order, which must add up to the vertex
//     count; and/or
//   - an element `edge` with scalar integer properties vertex1 and vertex2 (or its only two
//     properties), each edge joining two consecutive vertices; a strand is a run of vertices
//     joined by edges, its root the lower index (vertices in no edge are single points, left
//     out).
// A file with both (hapPLY-based scan tools write vertex, strand and edge in one file) is
// read by its counts, and its edges must join exactly the neighbours inside each strand.
// Other elements (faces, ...) are skipped, list properties included. Anything else — no
// vertex element or no x, y, z, neither strand nor edge, a count of an unknown name, a list
// where a scalar is needed, counts that disagree with the vertices or the edges, an index out
// of range or an edge between vertices that are not neighbours, a non-finite number, a file
// shorter than its header says, counts whose arrays exceed the caller's byte limit — is one
// clhair::Error line naming the file.
//
// CT2Hair `.bin` (little endian, no signature): int32 strand count, then per strand an int32
// point count and that many points of 7 float32: x, y, z, three floats CT2Hair writes as
// tangent or colour (ignored) and a label (ignored). A strand with a non-finite coordinate is
// left out and counted (CT2Hair's own loader drops such strands), as are strands of fewer
// than 2 points.
#pragma once

#include <cstdint>
#include <string>

#include "io/cyhair.h"

namespace clhair {

struct PlyStrands {
  CyHair hair;  // segments, points, colours (linear rgb) when the file has them
  std::uint64_t skippedStrands = 0;  // strands left out (single points; .bin: non-finite)
};

// Reads a `.ply` strand file (above). `maxBytes`: the device's largest allocation.
PlyStrands readPlyStrands(const std::string& path, std::uint64_t maxBytes);

// Reads a CT2Hair `.bin` strand file (above).
PlyStrands readCt2HairBin(const std::string& path, std::uint64_t maxBytes);

// Writes binary little-endian PLY: vertex float x, y, z (and uchar red, green, blue, sRGB,
// when the strands have colours), element strand with uint segment_count. Atomic; throws
// clhair::Error for arrays that do not match the segments.
void writePlyStrands(const CyHair& hair, const std::string& path);

}  // namespace clhair
