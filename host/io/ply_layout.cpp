// ply_layout.cpp — which vertices of a PLY strand file form a strand (ply_layout.h): the
// count property's names, runs of edges, and the agreement of strand counts with edges in
// files that hold both (hapPLY-based scan tools write vertex, strand and edge elements in
// one file). Input: counts or the edge flags the reader collected; output: points per strand
// or one error line.
#include "io/ply_layout.h"

#include <cstddef>

#include "clhair/error.h"

namespace clhair {

namespace {

constexpr const char* kSegmentNames[] = {"nsegs", "segment_count", "segments", "num_segments",
                                         "nsegments"};
constexpr const char* kVertexNames[] = {"vertex_count", "point_count", "num_vertices", "num_points",
                                        "nverts",       "nvertices",   "npoints"};

}  // namespace

PlyCountKind plyCountKind(const std::string& name) {
  for (const char* n : kSegmentNames)
    if (name == n) return PlyCountKind::Segments;
  for (const char* n : kVertexNames)
    if (name == n) return PlyCountKind::Vertices;
  return PlyCountKind::Unknown;
}

const char* plyCountNames() {
  return "segments: nsegs, segment_count, segments, num_segments, nsegments; points: "
         "vertex_count, point_count, num_vertices, num_points, nverts, nvertices, npoints";
}

std::vector<std::uint32_t> plyStrandsFromEdges(const std::vector<unsigned char>& next) {
  std::vector<std::uint32_t> pointsPer;
  std::uint32_t run = 1;
  for (std::size_t i = 0; i < next.size(); ++i) {
    if (i + 1 < next.size() && next[i]) {
      ++run;
      continue;
    }
    pointsPer.push_back(run);
    run = 1;
  }
  return pointsPer;
}

void plyCheckEdgesAgree(const std::vector<std::uint32_t>& pointsPer,
                        const std::vector<unsigned char>& next, const std::string& path,
                        const std::string& strandElement) {
  std::uint64_t at = 0;
  for (std::size_t s = 0; s < pointsPer.size(); ++s) {
    const std::uint64_t n = pointsPer[s];
    const std::string strand = strandElement + " " + std::to_string(s) + " (vertices " +
                               std::to_string(at) + " to " + std::to_string(at + n - 1) + ")";
    for (std::uint64_t i = at; i + 1 < at + n; ++i)
      if (!next[static_cast<std::size_t>(i)])
        throw Error(path + ": the edge and " + strandElement + " elements disagree: " + strand +
                    " has no edge joining vertices " + std::to_string(i) + " and " +
                    std::to_string(i + 1) + " (give one of the two elements, or fix the other)");
    if (n > 0 && at + n < next.size() && next[static_cast<std::size_t>(at + n - 1)])
      throw Error(path + ": the edge and " + strandElement + " elements disagree: an edge joins " +
                  "vertices " + std::to_string(at + n - 1) + " and " + std::to_string(at + n) +
                  ", but " + strand + " ends at the first (give one of the two elements, or " +
                  "fix the other)");
    at += n;
  }
}

}  // namespace clhair
