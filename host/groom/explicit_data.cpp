// explicit_data.cpp — strand order, chunk table and packed points of an explicit groom.
#include "groom/explicit_data.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "clhair/gpu_types.h"
#include "groom/children.h"

namespace clhair {

static_assert(sizeof(glm::vec4) == 16 && sizeof(glm::uvec4) == 16,
              "device tables are float4 / uint4");

namespace {

// 10 bits of x spread to every third bit (Morton order).
std::uint32_t spread3(std::uint32_t x) {
  x &= 0x3FFu;
  x = (x | (x << 16)) & 0x030000FFu;
  x = (x | (x << 8)) & 0x0300F00Fu;
  x = (x | (x << 4)) & 0x030C30C3u;
  x = (x | (x << 2)) & 0x09249249u;
  return x;
}

std::uint32_t quantize(float v, float lo, float extent) {
  float t = extent > 0.0f ? (v - lo) / extent : 0.0f;
  t = std::min(std::max(t, 0.0f), 1.0f);
  return static_cast<std::uint32_t>(t * 1023.0f + 0.5f);
}

std::uint32_t unorm16(float v) {
  v = std::min(std::max(v, 0.0f), 1.0f);
  return static_cast<std::uint32_t>(v * 65535.0f + 0.5f);
}

// The width of the n strands from `first` across their length (lod.cl, LOD from the
// screen): the largest diagonal of the boxes of their points at 0, 1/4, .., 1 of each
// strand's points.
float chunkWidth(const ExplicitData& d, std::size_t first, std::size_t n) {
  float width = 0.0f;
  for (int q = 0; q <= 4; ++q) {
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (std::size_t s = first; s < first + n; ++s) {
      const std::uint32_t a = d.strandOffsets[s], e = d.strandOffsets[s + 1];
      if (e <= a) continue;
      const glm::vec3 p(d.points[a + (e - 1 - a) * q / 4]);
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    if (lo.x <= hi.x) width = std::max(width, glm::length(hi - lo));
  }
  return width;
}

}  // namespace

ExplicitData prepareExplicit(const StrandGroom& g, std::uint32_t chunkStrands) {
  ExplicitData out;
  // with children a chunk holds fewer guides, so that it draws about chunkStrands strands
  // over about the area a chunk of stored strands covers (the same L, Lipp Eq. 2)
  chunkStrands = std::max<std::uint32_t>(
      1, static_cast<std::uint32_t>(chunkStrands / (std::uint64_t(g.children.count) + 1)));
  out.chunkGuides = chunkStrands;
  const std::size_t S = g.pointCounts.size();
  std::vector<std::uint64_t> first(S + 1, 0);
  for (std::size_t s = 0; s < S; ++s) first[s + 1] = first[s] + g.pointCounts[s];
  out.totalStrands = S;
  out.totalPoints = first[S];

  // Morton order of the roots over their bounding box; ties keep the file order.
  glm::vec3 rlo(1e30f), rhi(-1e30f);
  for (std::size_t s = 0; s < S; ++s) {
    rlo = glm::min(rlo, g.points[first[s]]);
    rhi = glm::max(rhi, g.points[first[s]]);
  }
  const glm::vec3 ext = rhi - rlo;
  std::vector<std::uint32_t> code(S);
  for (std::size_t s = 0; s < S; ++s) {
    const glm::vec3& p = g.points[first[s]];
    code[s] = spread3(quantize(p.x, rlo.x, ext.x)) | spread3(quantize(p.y, rlo.y, ext.y)) << 1 |
              spread3(quantize(p.z, rlo.z, ext.z)) << 2;
  }
  std::vector<std::uint32_t> order(S);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return code[a] < code[b]; });

  // chunks of consecutive strands, shuffled inside (Fisher-Yates on a fixed hash stream)
  const std::size_t K = (S + chunkStrands - 1) / chunkStrands;
  for (std::size_t c = 0; c < K; ++c) {
    const std::size_t b = c * chunkStrands, n = std::min<std::size_t>(chunkStrands, S - b);
    for (std::size_t i = n; i > 1; --i) {
      const std::uint32_t h =
          gpu::clh_hash3(g.seed, static_cast<std::uint32_t>(c), static_cast<std::uint32_t>(i));
      std::swap(order[b + i - 1], order[b + h % i]);
    }
  }
  out.sourceStrand = order;

  out.points.resize(out.totalPoints);
  out.fileColor = g.appearance.useFileColor && !g.colors.empty();
  out.fileThickness = g.appearance.useFileThickness && !g.thickness.empty();
  out.fileOpacity = g.appearance.useFileTransparency && !g.transparency.empty();
  if (out.fileColor || out.fileThickness || out.fileOpacity) out.fileLook.resize(out.totalPoints);
  double thicknessSum = 0.0;
  out.strandOffsets.resize(S + 1);
  if (!g.rootUv.empty()) out.uv.resize(S);
  std::uint32_t at = 0;
  for (std::size_t s = 0; s < S; ++s) {
    const std::uint32_t src = order[s];
    const std::uint32_t n = g.pointCounts[src];
    out.strandOffsets[s] = at;
    for (std::uint32_t k = 0; k < n; ++k) {
      const glm::vec3& p = g.points[first[src] + k];
      out.points[at + k] = glm::vec4(p, static_cast<float>(k) / static_cast<float>(n - 1));
      if (!out.fileLook.empty()) {
        const std::size_t i = first[src] + k;
        const glm::vec3 c = out.fileColor ? g.colors[i] : g.appearance.rootColor;
        // a fibre's opacity scales its width: its share of a pixel's coverage
        const float opacity = out.fileOpacity
                                  ? 1.0f - std::min(std::max(g.transparency[i], 0.0f), 1.0f)
                                  : 1.0f - g.appearance.transparency;
        const float t = out.fileThickness ? std::fabs(g.thickness[i]) * opacity : -opacity;
        out.fileLook[at + k] = glm::vec4(c, t);
        if (out.fileThickness) thicknessSum += t;
      }
    }
    if (!g.rootUv.empty()) out.uv[s] = unorm16(g.rootUv[src].x) | unorm16(g.rootUv[src].y) << 16;
    at += n;
  }
  out.strandOffsets[S] = at;
  if (out.fileThickness)
    out.meanThickness = static_cast<float>(thicknessSum / static_cast<double>(at));

  // children: their record, the neighbour table and the radius of interpolated children
  const ChildrenParams& cp = g.children;
  gpu::ClhChildrenGpu& kids = out.kids;
  kids.count = cp.count;
  kids.mode =
      cp.mode == ChildrenParams::Mode::Interpolated ? CLH_CHILD_INTERPOLATED : CLH_CHILD_FOLLOW;
  kids.guides = static_cast<std::uint32_t>(S);
  kids.radius = cp.radius;
  kids.tip_spread = cp.tipSpread;
  kids.clump = cp.clump;
  kids.seed = cp.seed;
  if (cp.count > 0 && kids.mode == CLH_CHILD_INTERPOLATED) {
    out.neighbours = guideNeighbours(out);
    kids.neighbours = CLH_CHILD_NEIGHBOURS;
    if (!(cp.radius > 0.0f)) kids.radius = autoChildRadius(out, out.neighbours);
  }
  out.drawnStrands = S * (std::uint64_t(cp.count) + 1);

  out.chunks.resize(K);
  out.chunkBounds.resize(2 * K);
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (std::size_t c = 0; c < K; ++c) {
    const std::size_t b = c * chunkStrands, n = std::min<std::size_t>(chunkStrands, S - b);
    glm::vec3 clo(1e30f), chi(-1e30f);
    for (std::uint32_t i = out.strandOffsets[b]; i < out.strandOffsets[b + n]; ++i) {
      clo = glm::min(clo, glm::vec3(out.points[i]));
      chi = glm::max(chi, glm::vec3(out.points[i]));
    }
    // the children's points by the CPU rules, widened a little for the device's rounding
    if (kids.count > 0) {
      glm::vec3 klo = clo, khi = chi;
      for (std::size_t s = b; s < b + n; ++s)
        for (std::uint32_t c = 1; c <= kids.count; ++c)
          for (const glm::vec3& p :
               childPoints(out, kids, out.neighbours, static_cast<std::uint32_t>(s), c)) {
            klo = glm::min(klo, p);
            khi = glm::max(khi, p);
          }
      const glm::vec3 pad = (khi - klo) * 1e-4f + 1e-6f * glm::max(glm::abs(klo), glm::abs(khi));
      clo = klo - pad;
      chi = khi + pad;
    }
    const float delta =
        gpu::clh_u01(gpu::clh_hash3(g.seed, static_cast<std::uint32_t>(c), CLH_RNG_LOD_DELTA));
    std::uint32_t deltaBits;
    std::memcpy(&deltaBits, &delta, 4);
    out.chunks[c] = glm::uvec4(static_cast<std::uint32_t>(b),
                               static_cast<std::uint32_t>(n * (std::uint64_t(kids.count) + 1)),
                               deltaBits, static_cast<std::uint32_t>(n));
    out.chunkBounds[2 * c] = glm::vec4(clo, chunkWidth(out, b, n));
    out.chunkBounds[2 * c + 1] = glm::vec4(chi, 0.0f);
    lo = glm::min(lo, clo);
    hi = glm::max(hi, chi);
  }
  out.boundsMin = lo;
  out.boundsMax = hi;
  return out;
}

}  // namespace clhair
