// hair_mesh.h — a groom given as a hair mesh (Yuksel et al. 2009; Bhokare et al. 2024).
//
// The scalp (root layer) is a polygon mesh of quads and triangles over `vertexCount` root
// vertices, each with a uv styling coordinate. Every root vertex is extruded through
// `layerCount` >= 2 layers; a scalp face and its extrusions form one bundle. Positions are
// stored layer-major: positions[layer * vertexCount + vertex]. Tangents (dP/d layer), the
// styling coordinate w and baked ambient occlusion are optional per layer vertex.
// Strands are never stored: the renderer generates them from this description.
// The file format is documented in docs/hair-mesh-format.md.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace clhair {

// Procedural styling applied in the consistent per-vertex u/v/w frames (Bhokare §3.4).
struct StyleParams {
  float clumpStrength = 0.0f;     // 0..1, how far tips move toward their clump center
  float clumpFrequency = 10.0f;   // clump cells per unit of root uv
  float clumpShape = 1.5f;        // profile exponent of w (> 0)
  float curlAmplitude = 0.0f;     // object units
  float curlFrequency = 0.0f;     // turns along the strand
  float curlHelix = 1.0f;         // 1 helical curl, 0 planar wave
  float curlPhaseJitter = 0.15f;  // 0: a clump curls in phase; 1: each strand random
  float frizzAmplitude = 0.0f;    // object units at the tip
  float frizzFrequency = 6.0f;    // noise cells along the strand
  float flyawayFraction = 0.0f;   // fraction of strands with extra frizz
  float flyawayAmplitude = 0.0f;  // object units of that extra frizz at the tip
  float lengthVariation = 0.0f;   // strands shortened by up to this fraction (0..0.95)
};

struct AppearanceParams {
  // Fibre colour: melanin concentrations (Chiang et al. 2016; ~0.3 blond, ~1.3 brown, ~8
  // black eumelanin; pheomelanin reddens), blended from root to tip. With useMelanin
  // false the absorption is derived from rootColor/tipColor instead.
  bool useMelanin = true;
  float eumelanin[2] = {1.3f, 1.0f};         // root, tip
  float pheomelanin[2] = {0.1f, 0.1f};       // root, tip
  glm::vec3 rootColor{0.08f, 0.05f, 0.03f};  // linear rgb: colour mode, and cyHair export
  glm::vec3 tipColor{0.25f, 0.17f, 0.10f};
  float betaM = 0.3f;           // longitudinal roughness
  float betaN = 0.3f;           // azimuthal roughness
  float cuticleTiltDeg = 2.0f;  // scale tilt alpha
  float ior = 1.55f;            // keratin
  float variation = 0.2f;       // per-strand melanin varies by up to +-20 %
  float strandWidth = 7.0e-5f;  // world-space fibre diameter
  // Smallest diameter, in pixels, within which a strand covers a pixel's center sample.
  // 0 keeps the true projected width (sub-pixel strands then hit few centers; the
  // reconstruction filter rebuilds coverage from them); 1 draws gap-free 1-pixel lines.
  float minHitDiameterPx = 0.0f;
  // Strand files only: draw the file's own look where it has one (per-point arrays or, in
  // cyHair, header defaults): its colours (linear rgb, instead of the melanin or root/tip
  // colours), thicknesses (file units, scaled like the points, instead of strandWidth) and
  // transparencies. A scene entry's appearance turns each off by giving its own (colour keys,
  // strand_width, transparency: the scene wins per key, docs/scene-format.md).
  bool useFileColor = true;
  bool useFileThickness = true;
  bool useFileTransparency = true;
  // Strand files only: fibre transparency in [0, 1) where the file gives none; a fibre is
  // drawn (1 - transparency) times as wide, its share of a pixel's coverage.
  float transparency = 0.0f;
};

// Strands per pixel of a bundle's projected width that LOD keeps by default (DESIGN.md,
// "LOD from the screen": the value measured against the references).
constexpr float kLodStrandsPerPixel = 8.0f;

// A groom's level of detail. Files turn it on unless they say otherwise (a hair-mesh file's
// "lod", a scene's strand-file entry: docs/scene-format.md); code that builds a groom says
// what it wants, and `enabled` here starts false so a groom built in code is drawn in full.
struct LodParams {
  bool enabled = false;
  float lambda = 3.0f;       // Lipp Eq. 2: L, which sets the control points (Eq. 4-5)
  float morphWindow = 0.5f;  // Bhokare Eq. 10 transition window
  // strands kept per pixel of a bundle's projected width (0: Lipp Eq. 1 from L instead)
  float strandsPerPixel = kLodStrandsPerPixel;
};

struct HairMesh {
  std::string name;
  int layerCount = 0;
  int vertexCount = 0;
  std::vector<std::array<int, 4>> faces;  // counter-clockwise; triangles have [3] == -1
  std::vector<glm::vec2> uv;              // per root vertex
  std::vector<glm::vec3> positions;       // layerCount * vertexCount, layer-major
  std::vector<glm::vec3> tangents;        // empty, or like positions (dP/d layer)
  std::vector<float> w;                   // empty, or per layer vertex styling w
  std::vector<float> ao;                  // empty, or per layer vertex ambient occlusion
  std::int64_t strandCount = 0;           // strands at full detail, spread by face area
  int controlPoints = 65;                 // C without LOD: 2^k + 1 (3..129)
  std::uint32_t seed = 1;
  StyleParams style;
  AppearanceParams appearance;
  LodParams lod;

  const glm::vec3& position(int layer, int vertex) const {
    return positions[static_cast<std::size_t>(layer) * vertexCount + vertex];
  }
};

// Strands one bundle may hold at full detail: its roots are the first samples of a
// progressive blue-noise set of at most this size (host/groom/blue_noise.h).
constexpr std::uint32_t kMaxBundleStrands = 1u << 16;
// The largest layer-vertex coordinate, either sign (1000 km in clhair's metres): products of
// coordinates (areas, styling frames) stay far inside float range. Cage animations too.
constexpr float kMaxCoordinate = 1e6f;

// The strands of each bundle at full detail: mesh.strandCount spread over the scalp faces by
// their object-space area (layer 0), the largest remainders rounded up so they add up.
std::vector<std::uint32_t> bundleStrandCounts(const HairMesh& mesh);

// Throws clhair::Error naming `where` and the offending element when the mesh is not
// renderable: counts, index ranges, finite numbers within kMaxCoordinate, parameter ranges,
// degenerate uv, and a bundle given more than kMaxBundleStrands strands.
void validateHairMesh(const HairMesh& mesh, const std::string& where);

// The version of the hair-mesh file format this build reads and writes.
constexpr int kHairMeshFormatVersion = 1;

HairMesh loadHairMesh(const std::string& path);
// Writes atomically (temporary file, then rename).
void saveHairMesh(const HairMesh& mesh, const std::string& path);

}  // namespace clhair
