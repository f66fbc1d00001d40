// strand_groom.h — a groom given as explicit strands (a cyHair `.hair`, USC-HairSalon
// `.data` or TressFX `.tfx` file, or strands built in memory), rendered through the same raster,
// shading, filter and compositing passes as a hair mesh.
//
// Strand s owns pointCounts[s] consecutive entries of `points` (root first); every strand
// has at least 2 points. Optional per-point thickness, colour and transparency are kept from
// the file (a cyHair header's defaults fill them where the file has no array) and drawn
// unless the appearance turns them off (useFileThickness, useFileColor,
// useFileTransparency: then the fibre width is `appearance.strandWidth` and the colour the
// appearance's). Optional per-strand root uv in [0,
// 1]^2 fills the G-buffer's u, v fields; without it they come from a per-strand hash. The styling
// coordinate w of a stored point k of an n-point strand is k / (n - 1). The renderer reorders the
// strands once (docs/scene-format.md, "Strand files") for LOD; a StrandGroom itself is never
// changed.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "clhair/hair_mesh.h"

namespace clhair {

// Children grown from the strands of a groom taken as guides, generated on the device in
// the strand stage and never stored (docs/scene-format.md, "Children"). Lengths are in the
// groom's object units.
struct ChildrenParams {
  enum class Mode { Follow, Interpolated };
  Mode mode = Mode::Follow;
  std::uint32_t count = 0;  // children per guide; 0: the guides alone
  // Half side of the square of root offsets across the guide's root direction (TressFX's
  // maxRadiusAroundGuideHair); <= 0 with Interpolated: half the median distance from a
  // guide's root to the nearest other guide root.
  float radius = 0.0f;
  float tipSpread = 0.0f;  // TressFX's tipSeparationFactor: offsets grow by 1 + s k / n
  float clump = 0.0f;      // Blender's clump factor in [-1, 1]: > 0 tips, < 0 roots
  std::uint32_t seed = 1;
};

// TressFX's runtime defaults: four follow hairs per guide, tip separation 2, and offsets up
// to 0.5 of its centimetre assets (5 mm).
constexpr std::uint32_t kTressFxFollowHairs = 4;
constexpr float kTressFxTipSeparation = 2.0f;
constexpr float kTressFxFollowRadiusMetres = 0.005f;

struct StrandGroom {
  std::string name;
  std::vector<std::uint32_t> pointCounts;  // per strand, each >= 2
  std::vector<glm::vec3> points;           // object space, strand after strand
  std::vector<float> thickness;            // empty, or per point (drawn with useFileThickness)
  std::vector<glm::vec3> colors;    // empty, or per point linear rgb (drawn with useFileColor)
  std::vector<float> transparency;  // empty, or per point in [0, 1] (useFileTransparency)
  std::vector<glm::vec2> rootUv;    // empty, or per strand in [0, 1]
  std::uint32_t seed = 1;           // root-uv hash, LOD offsets, LOD order
  AppearanceParams appearance;
  LodParams lod;  // morphWindow: Bhokare Eq. 10 on point skipping
  ChildrenParams children;
};

// Largest point count the strand tables can address (32-bit offsets).
constexpr std::uint64_t kMaxStrandPoints = 0xFFFFFFF0ull;
// Most children per guide.
constexpr std::uint32_t kMaxChildren = 1024;

// Throws clhair::Error naming `where` and the offending element when the groom is not
// renderable: no strands, a strand of fewer than 2 points, counts that do not add up to
// the points, optional arrays of the wrong length, non-finite numbers, uv outside [0, 1],
// appearance, LOD or children parameters out of range, more than kMaxStrandPoints points
// (children included).
void validateStrandGroom(const StrandGroom& groom, const std::string& where);

// Reads a strand file by extension: `.hair` (cyHair), `.data` (USC-HairSalon) or `.tfx`
// (TressFX 3.x/4.x binary; its strand uv become rootUv when all lie in [0, 1]). Sizes are
// checked against `maxBytes` (pass the device's largest allocation) before anything is
// allocated. Strands of a single point (legal in cyHair, skipped by the USC reader) are
// left out and counted in *skippedStrands when given. The result has the default
// appearance and LOD parameters and the file's stem as its name. Errors are one line that
// names the file. Problems that do not stop the file from being drawn (bytes after the end
// of its data, TressFX strand uv outside [0, 1]) are appended to *warnings when given, one line
// each naming the file.
StrandGroom loadStrandGroom(const std::string& path, std::uint64_t maxBytes,
                            std::uint64_t* skippedStrands = nullptr,
                            std::vector<std::string>* warnings = nullptr);

// The up axis of a strand file's data: clhair is +y up; many USC-HairSalon files are +z up,
// some scanned or simulated data sets +x up.
enum class UpAxis { X, Y, Z };

// The per-file placement of a strand file in a scene: uniform `scale`, then a rotation that
// turns the file's up axis into clhair's +y (handedness kept):
//   Y: identity;  Z: (x, y, z) -> (x, z, -y), -90 degrees about +x;
//   X: (x, y, z) -> (-y, x, z), +90 degrees about +z.
glm::mat4 strandFileTransform(float scale, UpAxis up);

// Generated strands read back from the device (export-strands, tests, the traced
// reference): what the strand kernels draw, point for point, with the attributes their
// G-buffer words carry.
struct StrandSet {
  std::vector<std::uint32_t> pointCounts;   // per strand
  std::vector<float> points;                // xyz per point, object space
  std::vector<float> tangents;              // xyz per point
  std::vector<float> w;                     // styling w per point
  std::vector<float> ao;                    // ambient occlusion per point (1: open)
  std::vector<float> uv;                    // root styling u, v per strand (the words' u, v)
  std::vector<std::uint32_t> bundleOf;      // bundle of each strand (explicit strands: LOD chunk)
  std::vector<std::uint32_t> sourceStrand;  // explicit strands only: index in the StrandGroom
  // Explicit strands with per-point file colour or thickness (appearance.useFileColor):
  // linear rgb and thickness (object units) per point; empty otherwise.
  std::vector<float> look;
};

}  // namespace clhair
