// strand_groom_io.cpp — StrandGroom from strand files (cyHair, USC-HairSalon, TressFX), its
// validation and the per-file placement transform.
//
// The readers (cyhair_read.cpp, usc_hair.cpp, tressfx_read.cpp) already refuse truncated files,
// counts that do not add up, non-finite numbers, zero strands and sizes beyond the caller's limit,
// before allocating. Here single-point strands are dropped (nothing to draw) and the
// result is validated like any StrandGroom built in memory.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "clhair/error.h"
#include "clhair/strand_groom.h"
#include "io/binary_file.h"
#include "io/cyhair.h"
#include "io/json_util.h"
#include "io/ply_strands.h"
#include "io/tressfx.h"
#include "io/usc_hair.h"

namespace clhair {

namespace {

bool finite3(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

bool inUnit(const glm::vec3& v) {
  return v.x >= 0.0f && v.x <= 1.0f && v.y >= 0.0f && v.y <= 1.0f && v.z >= 0.0f && v.z <= 1.0f;
}

StrandGroom fromCyHair(const CyHair& h, std::uint64_t* skipped) {
  StrandGroom g;
  const std::size_t strands = h.segments.size();
  std::size_t kept = 0, keptPoints = 0;
  for (std::uint32_t seg : h.segments)
    if (seg >= 1) {
      ++kept;
      keptPoints += seg + 1;
    }
  g.pointCounts.reserve(kept);
  g.points.reserve(keptPoints);
  // a cyHair header's defaults stand for missing arrays, unless they are the format's own
  // initial values (thickness 1, transparency 0, white), which writers leave when nothing
  // was set (Yuksel's cyHairFile)
  const bool defThickness = h.thickness.empty() && h.defaultThickness != 1.0f &&
                            std::isfinite(h.defaultThickness) && h.defaultThickness > 0.0f;
  const bool defTransparency = h.transparency.empty() && h.defaultTransparency != 0.0f;
  const bool defColor =
      h.colors.empty() &&
      !(h.defaultColor[0] == 1.0f && h.defaultColor[1] == 1.0f && h.defaultColor[2] == 1.0f);
  if (!h.thickness.empty() || defThickness) g.thickness.reserve(keptPoints);
  if (!h.colors.empty() || defColor) g.colors.reserve(keptPoints);
  if (!h.transparency.empty() || defTransparency) g.transparency.reserve(keptPoints);
  std::size_t at = 0;  // first point of the current strand
  for (std::size_t s = 0; s < strands; ++s) {
    const std::size_t n = static_cast<std::size_t>(h.segments[s]) + 1;
    if (n >= 2) {
      g.pointCounts.push_back(static_cast<std::uint32_t>(n));
      for (std::size_t k = at; k < at + n; ++k) {
        g.points.emplace_back(h.points[3 * k], h.points[3 * k + 1], h.points[3 * k + 2]);
        if (!h.thickness.empty()) g.thickness.push_back(h.thickness[k]);
        if (defThickness) g.thickness.push_back(h.defaultThickness);
        if (!h.colors.empty())
          g.colors.emplace_back(h.colors[3 * k], h.colors[3 * k + 1], h.colors[3 * k + 2]);
        if (defColor)
          g.colors.emplace_back(h.defaultColor[0], h.defaultColor[1], h.defaultColor[2]);
        if (!h.transparency.empty()) g.transparency.push_back(h.transparency[k]);
        if (defTransparency) g.transparency.push_back(h.defaultTransparency);
      }
    }
    at += n;
  }
  if (skipped) *skipped = strands - kept;
  return g;
}

// A TressFX file's strand uv become the groom's root uv when all lie in [0, 1] (the range
// the G-buffer stores); otherwise they are left out with one warning naming the first.
void rootUvFromFile(const std::vector<float>& uv, const std::string& path, StrandGroom& g,
                    std::vector<std::string>* warnings) {
  if (uv.empty()) return;
  for (std::size_t s = 0; s < uv.size() / 2; ++s) {
    const float u = uv[2 * s], v = uv[2 * s + 1];
    if (!(u >= 0.0f && u <= 1.0f && v >= 0.0f && v <= 1.0f)) {
      if (warnings)
        warnings->push_back(path + ": strand " + std::to_string(s) + " has uv (" + showFloat(u) +
                            ", " + showFloat(v) +
                            ") outside [0, 1]; the file's strand uv are ignored and " +
                            "hashed per strand instead");
      return;
    }
  }
  g.rootUv.reserve(uv.size() / 2);
  for (std::size_t s = 0; s < uv.size() / 2; ++s) g.rootUv.emplace_back(uv[2 * s], uv[2 * s + 1]);
}

}  // namespace

void validateStrandGroom(const StrandGroom& g, const std::string& where) {
  auto fail = [&](const std::string& what) { throw Error(where + ": " + what); };
  if (g.pointCounts.empty()) fail("has no strands");
  std::uint64_t total = 0;
  for (std::size_t s = 0; s < g.pointCounts.size(); ++s) {
    if (g.pointCounts[s] < 2)
      fail("strand " + std::to_string(s) + " has " + std::to_string(g.pointCounts[s]) +
           " point(s), need at least 2");
    total += g.pointCounts[s];
  }
  if (total > kMaxStrandPoints)
    fail(std::to_string(total) + " points, at most " + std::to_string(kMaxStrandPoints) +
         " are supported");
  if (total != g.points.size())
    fail("the strands' point counts add up to " + std::to_string(total) + " but " +
         std::to_string(g.points.size()) + " points are given");
  if (!g.thickness.empty() && g.thickness.size() != g.points.size())
    fail(std::to_string(g.thickness.size()) + " thickness values for " +
         std::to_string(g.points.size()) + " points");
  if (!g.colors.empty() && g.colors.size() != g.points.size())
    fail(std::to_string(g.colors.size()) + " colours for " + std::to_string(g.points.size()) +
         " points");
  if (!g.transparency.empty() && g.transparency.size() != g.points.size())
    fail(std::to_string(g.transparency.size()) + " transparencies for " +
         std::to_string(g.points.size()) + " points");
  for (std::size_t i = 0; i < g.transparency.size(); ++i)
    if (!std::isfinite(g.transparency[i]))
      fail("transparency " + std::to_string(i) + " is not finite");
  if (!g.rootUv.empty() && g.rootUv.size() != g.pointCounts.size())
    fail(std::to_string(g.rootUv.size()) + " root uv pairs for " +
         std::to_string(g.pointCounts.size()) + " strands");
  for (std::size_t i = 0; i < g.points.size(); ++i)
    if (!finite3(g.points[i])) fail("point " + std::to_string(i) + " is not finite");
  for (std::size_t i = 0; i < g.thickness.size(); ++i)
    if (!std::isfinite(g.thickness[i])) fail("thickness " + std::to_string(i) + " is not finite");
  for (std::size_t i = 0; i < g.colors.size(); ++i)
    if (!finite3(g.colors[i])) fail("colour " + std::to_string(i) + " is not finite");
  for (std::size_t s = 0; s < g.rootUv.size(); ++s) {
    const glm::vec2 uv = g.rootUv[s];
    if (!(uv.x >= 0.0f && uv.x <= 1.0f && uv.y >= 0.0f && uv.y <= 1.0f))
      fail("root uv of strand " + std::to_string(s) + " is outside [0, 1]");
  }
  const AppearanceParams& a = g.appearance;
  if (!inUnit(a.rootColor) || !inUnit(a.tipColor))
    fail("appearance colours must be linear rgb in [0, 1]");
  if (!(a.strandWidth >= 1e-9f && a.strandWidth <= 1e3f))
    fail("appearance strand_width must be in 1e-9..1e3");
  if (!(a.minHitDiameterPx >= 0.0f && a.minHitDiameterPx <= 3.0f))
    fail("appearance min_hit_diameter_px must be in 0..3");
  if (!(a.transparency >= 0.0f && a.transparency < 1.0f))
    fail("appearance transparency must be in 0..0.99");
  if (!(g.lod.lambda >= 1e-3f && g.lod.lambda <= 1e3f)) fail("lod lambda must be in 0.001..1000");
  if (!(g.lod.morphWindow >= 0.0f && g.lod.morphWindow <= 1.0f))
    fail("lod morph_window must be in 0..1");
  const ChildrenParams& c = g.children;
  if (c.count > kMaxChildren)
    fail("children count " + std::to_string(c.count) + " is above " + std::to_string(kMaxChildren) +
         " per guide");
  const std::uint64_t copies = std::uint64_t(c.count) + 1;
  if (copies * g.pointCounts.size() > 0x7FFFFFFFull || copies * total > kMaxStrandPoints)
    fail(std::to_string(g.pointCounts.size()) + " guides with " + std::to_string(c.count) +
         " children each draw more strands or points than the strand tables can address");
  if (!std::isfinite(c.radius) || std::fabs(c.radius) > 1e30f)
    fail("children radius must be a finite number");
  if (!(c.tipSpread >= 0.0f && c.tipSpread <= 1000.0f))
    fail("children tip_spread must be in 0..1000");
  if (!(c.clump >= -1.0f && c.clump <= 1.0f)) fail("children clump must be in -1..1");
}

StrandGroom loadStrandGroom(const std::string& path, std::uint64_t maxBytes,
                            std::uint64_t* skippedStrands, std::vector<std::string>* warnings) {
  const std::string ext = lowerExtension(path);
  StrandGroom g;
  std::uint64_t skipped = 0, trailing = 0;
  if (ext == ".hair") {
    const CyHair h = readCyHair(path, maxBytes);
    g = fromCyHair(h, &skipped);
    trailing = h.trailingBytes;
  } else if (ext == ".data") {
    UscHair u = readUscHair(path, maxBytes);
    g = fromCyHair(u.hair, &skipped);
    skipped += u.skippedStrands;
    trailing = u.hair.trailingBytes;
  } else if (ext == ".tfx") {
    const TressFxHair t = readTressFx(path, maxBytes);
    g = fromCyHair(t.hair, &skipped);  // every strand has 2 or more points: none skipped
    trailing = t.hair.trailingBytes;
    rootUvFromFile(t.strandUv, path, g, warnings);
  } else if (ext == ".ply" || ext == ".bin") {
    PlyStrands p = ext == ".ply" ? readPlyStrands(path, maxBytes) : readCt2HairBin(path, maxBytes);
    g = fromCyHair(p.hair, &skipped);
    skipped += p.skippedStrands;
    trailing = p.hair.trailingBytes;
  } else {
    throw Error(path + ": unknown strand file type \"" + ext +
                "\"; expected .hair (cyHair), .data (USC-HairSalon), .tfx (TressFX), .ply or " +
                ".bin (CT2Hair)");
  }
  if (g.pointCounts.empty())
    throw Error(path + ": no strand has 2 or more points (" + std::to_string(skipped) +
                " single-point strands), nothing to draw");
  g.name = std::filesystem::path(path).stem().string();
  validateStrandGroom(g, path);
  if (skippedStrands) *skippedStrands = skipped;
  if (trailing > 0 && warnings)
    warnings->push_back(
        path + ": " + std::to_string(trailing) + " byte" + (trailing == 1 ? "" : "s") +
        " after the end of the strand data, ignored (is the file complete and of the " +
        "type its extension says?)");
  return g;
}

glm::mat4 strandFileTransform(float scale, UpAxis up) {
  glm::mat4 m(scale);
  m[3][3] = 1.0f;
  // r[i] is the image of file axis i (glm is column-major); both are rotations, so the
  // handedness of the data is kept
  glm::mat4 r(0.0f);
  r[3][3] = 1.0f;
  if (up == UpAxis::Z) {
    // (x, y, z) -> (x, z, -y): +z becomes +y
    r[0][0] = 1.0f;   // x -> x
    r[1][2] = -1.0f;  // y -> -z
    r[2][1] = 1.0f;   // z -> y
    m = r * m;
  } else if (up == UpAxis::X) {
    // (x, y, z) -> (-y, x, z): +x becomes +y
    r[0][1] = 1.0f;   // x -> y
    r[1][0] = -1.0f;  // y -> -x
    r[2][2] = 1.0f;   // z -> z
    m = r * m;
  }
  return m;
}

}  // namespace clhair
