// scene.h — what one frame shows: camera, lights, opaque primitives, triangle meshes and
// grooms.
//
// Scenes are JSON files (docs/scene-format.md). Groom and mesh files are resolved relative
// to the scene file; a groom is a hair mesh or a strand file (cyHair .hair, USC-HairSalon
// .data), a mesh an OBJ file (a head, a body).
// A camera can be given explicitly or as a preset that frames all grooms at about 60 %
// (close), 20 % (mid) or 5 % (far) of the image height.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "clhair/animation.h"
#include "clhair/hair_mesh.h"
#include "clhair/strand_groom.h"
#include "clhair/triangle_mesh.h"
#include "clhair/visibility.h"

namespace clhair {

struct Camera {
  glm::vec3 position{0.0f, 0.0f, 1.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fovYDegrees = 35.0f;
};

struct Light {
  enum class Type { Point, Directional };
  Type type = Type::Directional;
  glm::vec3 position{0.0f};               // point lights
  glm::vec3 direction{0.0f, 1.0f, 0.0f};  // directional: toward the light
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
  // deep opacity map from this light, with the light scattered through the hair (at most
  // CLH_MAX_SHADOWS = 4 lights). A scene file's lights have one unless they say false; a
  // Light built in code says so itself.
  bool shadows = false;
};

// Deep opacity maps (Yuksel & Keyser 2008) of the shadowed lights.
struct ShadowParams {
  int resolution = 512;                       // texels per side
  float layers[3] = {0.004f, 0.012f, 0.03f};  // layer ends past the first hair, world units
  float density = 1.0f;                       // transmittance = exp(-density * coverage)
  bool lodCorrection = true;                  // Lipp §3.2.3 depth shift under LOD
  float bias = 2.0f;                          // opaque shadow-map bias, texels
  // Opaque surfaces look the maps up with percentage-closer filtering over 4x4 texels, so
  // shadow edges on them spread over three texels; false: the bilinear blend of the four
  // nearest texels' tests (a one-texel ramp, stair steps where a texel covers pixels).
  bool pcf = true;
  // Multiplies the LOD's lambda (Lipp Eq. 2) in the lights' passes: below 1 the maps are
  // built from fewer strands and control points (the LOD's coverage compensation keeps
  // their opacity), which is most of the cost of rebuilding them. 0.25 by measurement: a
  // third of the strands of 1 at a FLIP against the path reference 3-4 % lower in the median
  // cell (DESIGN.md, "Light-pass LOD from the camera").
  float lodScale = 0.25f;
};

// The procedural default sky: a sun disc, a horizon -> zenith gradient and a ground.
struct SkyParams {
  float sunElevationDeg = 35.0f;       // above the horizon, [-90, 90]
  float sunAzimuthDeg = 30.0f;         // about +y: 0 = toward -z, 90 = toward +x
  float sunAngularDiameterDeg = 3.0f;  // (0, 45]; the real sun is 0.53, wider reads better
  glm::vec3 sunColor{1.0f, 0.95f, 0.85f};
  float sunIrradiance = 3.0f;             // irradiance of the disc on a surface facing it
  glm::vec3 zenith{0.20f, 0.35f, 0.75f};  // linear rgb radiance
  glm::vec3 horizon{0.75f, 0.80f, 0.90f};
  glm::vec3 ground{0.20f, 0.18f, 0.16f};
  float gradientExponent = 0.5f;  // sky = mix(horizon, zenith, y^exponent)
  float groundBlend = 0.05f;      // horizon -> ground over -y in [0, groundBlend]
  int width = 512;                // generated map width, even, [16, 4096]
};

// Environment ("probe") lighting: an equirectangular map or the procedural sky, prefiltered
// at load (host/lighting/environment.h). When enabled it replaces the constant ambient.
struct EnvironmentDesc {
  bool enabled = false;
  std::string file;  // equirectangular map (EXR/HDR/...), or empty for the sky
  SkyParams sky;
  float intensity = 1.0f;
  float rotateYDegrees = 0.0f;
  bool visible = false;  // drawn as the background
};

struct Sphere {
  glm::vec3 center{0.0f};
  float radius = 1.0f;
  glm::vec3 color{0.5f};
};

struct Plane {
  glm::vec3 normal{0.0f, 1.0f, 0.0f};
  float offset = 0.0f;  // dot(normal, x) = offset
  glm::vec3 color{0.5f};
};

// An opaque triangle mesh placed in the scene, shaded like the spheres and planes.
struct MeshInstance {
  std::string name;
  std::shared_ptr<const TriangleMesh> mesh;
  glm::mat4 transform{1.0f};  // object -> world (includes the entry's scale and up axis)
  glm::vec3 color{0.5f};      // linear albedo
};

// Temporal reprojection of the hair (clhair/temporal.h, DESIGN.md "Temporal reprojection"):
// a frame's hair is blended with the hair of the `history` frames before it, carried to it
// along the motion vectors; history that the depth or the current neighbourhood contradicts
// is dropped. Off by default.
struct TemporalParams {
  int history = 0;     // frames before this one in the blend, 0 (off) .. kMaxTemporalHistory
  float blend = 0.5f;  // weight of the newer frame at each step of the window, (0, 1]
  // History is dropped where the nearest depth around the pixel and around where it was
  // differ by more than this share of the depth (or one of them is the background).
  float depthTolerance = 0.05f;
  // Study switches (the benchmark turns them off to show what they prevent):
  bool clamp = true;        // the carried history clamped to the current 3x3 range
  bool rejectDepth = true;  // the depth rule above
};
constexpr int kMaxTemporalHistory = 8;

// Reconstruction filter (Lipp et al. 2026 §3.3), defaults from the paper where it gives them.
struct FilterParams {
  bool enabled = true;
  int radius = 5;                // (2r + 1)^2 window
  float sPar = 0.5f;             // sigma_parallel = radius * sPar
  float sPerp = 0.1f;            // sigma_perp = radius * sPerp
  float sigmaC = 0.9f;           // colour similarity
  float depthReject = 1.45e-3f;  // relative depth beyond which neighbours are ignored
  float depthMismatch = 5e-4f;   // relative depth: a nearer conservative strand is blended on top
  float strip = 0.5f;  // alpha strip: neighbours within this many pixels of the tangent line
  bool promote =
      true;  // promote conservative-only pixels (Lipp §3.3.2); off: only center hits are drawn

  // Which filter runs: "lipp" (the reconstruction filter above), "huang" (hair linking,
  // alpha fix and the orientation-aware anisotropic filter of Huang et al. 2025, §4;
  // kernels/link.cl, whose parts can be switched off one by one) or "auto" (the default):
  // Huang's in a frame of one view, Lipp's in a render of several views, whose shared
  // strand pass writes no identity layer for the linking (DESIGN.md, "The default filter").
  // Either runs only at one sample per pixel with the lines raster.
  enum class Method { Auto, Lipp, Huang };
  Method method = Method::Auto;
  bool link = true;            // Huang §4.1: fill empty pixels along source strands
  float linkThreshold = 0.5f;  // epsilon_align of Eq. 5
  float linkSigma = 1.5f;      // sigma of Eq. 4's proximity term, pixels
  int linkMaxSteps = 64;       // pixels one propagation may fill
  bool alphaFix = true;        // Huang §4.2: alpha = M / (M + N) per strand
  int linkTable = 0;           // hash-table entries (0: twice the groom's strands, see link_stage)
  bool aniso = true;           // Huang §4.3: the orientation-aware filter
  // Eq. 11-13 with the values measured best here (DESIGN.md; the paper's 0.1, 0.1, 0.9 and
  // k = 0.01 leave the filter's weights at zero one pixel away)
  float sigmaD = 0.5f;       // Eq. 11, distance in units of the major axis r
  float sigmaTheta = 0.6f;   // Eq. 11, radians
  float sigmaCAniso = 0.9f;  // Eq. 11, colour
  float kernelK = 0.02f;     // Eq. 13: r = k sqrt(Bx By), clamped to 2..3 pixels
};

// Exactly one of `mesh` and `strands` is set.
struct GroomInstance {
  GroomInstance() = default;
  GroomInstance(std::string n, std::shared_ptr<const HairMesh> m,
                const glm::mat4& t = glm::mat4(1.0f))
      : name(std::move(n)), mesh(std::move(m)), transform(t) {}
  GroomInstance(std::string n, std::shared_ptr<const StrandGroom> s,
                const glm::mat4& t = glm::mat4(1.0f))
      : name(std::move(n)), strands(std::move(s)), transform(t) {}

  std::string name;
  std::shared_ptr<const HairMesh> mesh;        // a hair mesh: strands generated per frame
  std::shared_ptr<const StrandGroom> strands;  // explicit strands, uploaded once
  glm::mat4 transform{
      1.0f};               // object -> world (strand files: includes the file's scale and up axis)
  bool hasFilter = false;  // true: `filter` overrides the scene's
  FilterParams filter;

  // Animation (evaluated by sceneAtFrame). transformKeys: translate x, y, z, rotate_y
  // (degrees), scale; when set, transform = keyed TRS * fileTransform at each frame.
  KeyTrack transformKeys;
  glm::mat4 fileTransform{1.0f};  // strand files: the file's scale and up axis
  // Strand files given per frame: sceneAtFrame reads the frame's file (frames before the
  // first and after the last found hold those), keeping `strands`' appearance, LOD and children.
  std::shared_ptr<const StrandFrames> strandFrames;
  // Hair meshes: the cage per frame (cage-animation file) starting at scene frame
  // cageStartFrame, and the wind on the cage.
  std::shared_ptr<const CageAnimation> cage;
  double cageStartFrame = 1.0;
  WindParams wind;
  // The cage this still frame draws (layer-major like HairMesh::positions, the mesh's object
  // space); null: the mesh's own positions. Set by sceneAtFrame.
  std::shared_ptr<const std::vector<glm::vec3>> deformed;
  // Baked spherical visibility (clhair bake-visibility, include/clhair/visibility.h): shading
  // multiplies every light without a deep opacity map by exp(-visibilityAbsorption * events),
  // events the bake's clamped SH toward the light. Null: no bake (today's shading).
  std::shared_ptr<const VisibilityBake> visibility;
  float visibilityAbsorption = 0.5f;
};

enum class CameraPreset { Close, Mid, Far };

// How the strand pass draws (scene key "raster", `clhair render --raster`): Lines, one
// centre sample and a conservative layer per pixel (Lipp 2026, the default); Coverage,
// segments as trapezoids with analytic pixel coverage into three depth-ordered layers and
// an additive coverage layer whose alpha is reconstructed when compositing (Kulikov 2025;
// clhair/coverage.h).
enum class RasterMode { Lines, Coverage };

// Quality levels (scene key "quality", `clhair render --quality`; README "Quality"):
//   Draft  one sample per pixel with the scene's filter (Huang's by default);
//   Good   kGoodMsaa samples per pixel, each sample shaded (kGoodPointShading), no filter;
//   Final  jittered passes accumulated (`spp` of them, kDefaultFinalPasses when 0), each the
//          path kFinalPassGood says (ProgressiveStill, clhair/progressive.h).
// The choices are measured in bench/cpu-results.md ("Quality levels").
enum class Quality { Draft, Good, Final };
constexpr int kGoodMsaa = 4;
// Whether good shades once per visible strand point rather than every sample. Per sample:
// per-point shading at MSAA 4 measured 1.26x the per-sample FLIP on the curly groom at
// close (its colour interpolated along a segment misses the highlights a turning tangent
// moves), and on PoCL it cost more than shading every sample (DESIGN.md).
constexpr bool kGoodPointShading = false;
constexpr int kDefaultFinalPasses = 64;
constexpr int kMaxFinalPasses = 4096;
struct QualityParams {
  Quality level = Quality::Draft;
  int spp = 0;  // final: passes (0: kDefaultFinalPasses)
};

// The per-asset strand cap (Kulikov 2025: at most so many strands per model, applied at
// load): a groom of more than `cap` strands keeps `cap` of them, spread evenly over the
// groom (a hair mesh: the first `cap` of its progressive root sets; a strand file: every
// (N / cap)-th strand), and its fibres widen by N / cap (strand width, minimum hit diameter
// up to 3 pixels, file thicknesses) so the groom covers about what it covered. Returns the
// widening (1: nothing changed). cap 0: no cap.
float capStrands(HairMesh& mesh, std::uint64_t cap);
float capStrands(StrandGroom& groom, std::uint64_t cap);

// Scene::segmentBudget's least default, and its largest accepted value.
constexpr std::uint64_t kDefaultSegmentBudget = 2'000'000;
constexpr std::uint64_t kMaxSegmentBudget = 4'000'000'000;
// The default budget per pixel of the image: a safety limit that a frame of LOD from the
// screen does not reach (DESIGN.md, "LOD from the screen": the default scene asks for at
// most 21 segments per pixel at the sizes measured; LOD off, 62 at 480x270).
constexpr std::uint64_t kBudgetSegmentsPerPixel = 64;

// The image height LOD's λ is tuned at (DESIGN.md, "LOD defaults by image size"): above it
// λ grows with the image height, so a bundle's control points span the same pixels.
constexpr int kLodReferenceWidth = 960, kLodReferenceHeight = 540;

// The budget of a scene that gives none: kBudgetSegmentsPerPixel times the image's pixels,
// at least kDefaultSegmentBudget (33.2 M at 960x540, 132.7 M at 1920x1080).
std::uint64_t defaultSegmentBudget(int width, int height);

// The factor on every groom's λ (Lipp Eq. 2) in a view of this height: the height over
// kLodReferenceHeight where that is more, else 1.
float lodResolutionScale(int height);

// A keyed camera: either explicit keys (position x, y, z, target x, y, z, up x, y, z, fov)
// or keys of a preset framing (azimuth, elevation, fov), as the scene's camera was given.
struct CameraAnimation {
  KeyTrack keys;  // empty: the camera does not move
  bool preset = false;
  CameraPreset framing = CameraPreset::Mid;
};

// One named view of a scene with several ("cameras", docs/scene-format.md): a camera of its
// own, or (relative) the scene's camera moved by `offset` in that camera's view space (x
// right, y up, z back), so it follows the camera's keys (a stereo rig).
struct View {
  std::string name;
  bool relative = false;
  glm::vec3 offset{0.0f};
  Camera camera;  // when not relative
};
constexpr int kMaxViews = 16;

struct Scene {
  int width = 1280;
  int height = 720;
  Camera camera;
  std::vector<View> views;  // "cameras": empty for a scene of one view, `camera`
  glm::vec3 background{0.05f, 0.06f, 0.08f};
  std::string backgroundImage;  // an image behind everything, stretched over the frame
  glm::vec3 ambient{0.05f};
  std::vector<Light> lights;
  std::vector<Sphere> spheres;
  std::vector<Plane> planes;
  std::vector<MeshInstance> meshes;
  std::vector<GroomInstance> grooms;
  FilterParams filter;
  ShadowParams shadows;
  TemporalParams temporal;
  EnvironmentDesc environment;
  CameraAnimation cameraAnimation;
  double frameRate = 24.0;  // frames per second: the wind's clock
  // The most segments all grooms drawn with LOD together draw in one frame (Kulikov 2025):
  // over it, every such groom's strands are cut in proportion and far ones drop every
  // other control point (host/frame/frame_lod.h). Grooms drawn without LOD keep every
  // strand and do not count. 0: no budget; unset: defaultSegmentBudget(width, height).
  std::optional<std::uint64_t> segmentBudget;
  RasterMode raster = RasterMode::Lines;  // "raster": "lines" or "coverage"
  // "quality": "draft", "good" or "final", or {"level": ..., "spp": N}
  QualityParams quality;
  // Problems found while loading that do not stop the scene from rendering, one line each
  // naming the file (the CLI prints them as "clhair: warning: ...").
  std::vector<std::string> warnings;
  // What loading chose for the scene (one line each, e.g. a "scale": "auto" factor).
  std::vector<std::string> notes;
  // Every file the scene named and loading read (strand and hair-mesh files, meshes, images,
  // baked visibility, animation caches): the inputs a command must not write over.
  std::vector<std::string> files;
};

// Frames the world bounds of all grooms and meshes together (the grooms at 60 / 20 / 5 %
// of the image height when there is no mesh; a head mesh is never cut off), seen from
// the direction given by azimuth (degrees about +y, 0 looks along -z) and elevation.
Camera framePreset(const Scene& scene, CameraPreset preset, float azimuthDeg = 0.0f,
                   float elevationDeg = 10.0f, float fovYDeg = 35.0f);
// The same framing seen from the direction of the scene's camera (from its target toward
// its position), keeping its field of view and up vector: a preset chosen after loading
// (`clhair render --camera`) changes the distance and the framing, not the viewing angle.
Camera reframeCamera(const Scene& scene, CameraPreset preset);
CameraPreset parseCameraPreset(const std::string& name);

// Warnings about the grooms' scale in the scene's final view (camera and resolution as they
// will render), one line per groom at most, starting with `where` (the scene file): a
// groom whose fibres are implausibly thin for its size (fibre width below 3e-5 of the
// groom's extent: a centimetre or millimetre file without "scale") or that is implausibly
// large (over 50 units across), or that covers less than a pixel of the image.
std::vector<std::string> viewWarnings(const Scene& scene, const std::string& where);

// Largest accepted image side; larger requests are refused as absurd.
constexpr int kMaxImageSide = 16384;

// Strand files larger than this (as CyHair arrays in memory) are refused by default.
constexpr std::uint64_t kDefaultStrandFileLimit = 2ull << 30;

// Loads a scene and every groom and mesh file it names. Strand and mesh files are checked
// against `maxStrandBytes` before anything is allocated: pass the device's largest
// allocation (Device::info().maxAlloc) when a device is open.
Scene loadScene(const std::string& path, std::uint64_t maxStrandBytes = kDefaultStrandFileLimit);

// The camera of view `v` of the scene (its own, or the scene's camera moved by the offset).
Camera viewCamera(const Scene& scene, const View& v);

// True when some frame of the scene differs from another (keys, a cage animation, wind).
bool isAnimated(const Scene& scene);

// The still scene at `frame`: keyed camera and groom transforms interpolated, each hair
// mesh's cage taken from its cage animation and swayed by its wind, each per-frame strand
// file read (the nearest whole frame). Depends only on `scene`, `frame` and those files.
// Throws clhair::Error when the interpolated camera is degenerate or a frame's strand file
// cannot be read.
Scene sceneAtFrame(const Scene& scene, double frame);

}  // namespace clhair
