// ply_layout.h — how a PLY strand file says which vertices form a strand (ply_strands.h): the
// names the strand element's count goes by, and strands from edges, or strand counts checked
// against edges when a file has both (as hapPLY-based scan tools write them).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace clhair {

// What a strand element's count property counts, by its name.
enum class PlyCountKind { Unknown, Segments, Vertices };

// Segments: nsegs, segment_count, segments, num_segments, nsegments; vertices:
// vertex_count, point_count, num_vertices, num_points, nverts, nvertices, npoints.
PlyCountKind plyCountKind(const std::string& name);

// The names plyCountKind knows, for error lines.
const char* plyCountNames();

// Points per strand from the edges: `next[i]` is 1 when an edge joins vertices i and i + 1;
// a strand is a run of joined vertices (a lone vertex is a strand of one point).
std::vector<std::uint32_t> plyStrandsFromEdges(const std::vector<unsigned char>& next);

// Checks that the edges join exactly the neighbouring vertices inside each strand of
// `pointsPer` (points per strand, in vertex order); throws one clhair::Error line naming the
// first strand and vertex where they do not agree.
void plyCheckEdgesAgree(const std::vector<std::uint32_t>& pointsPer,
                        const std::vector<unsigned char>& next, const std::string& path,
                        const std::string& strandElement);

}  // namespace clhair
