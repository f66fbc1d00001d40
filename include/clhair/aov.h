// aov.h — layers for compositing (arbitrary output variables) and writing them, with the
// beauty, as one multi-channel OpenEXR file (docs/aovs.md).
//
// Renderer::render fills Frame::aovs when RenderOptions::aovs is set. Every layer is a plane
// of width * height values per channel, row-major, top row first:
//   rgba     R, G, B, A   the composited frame (premultiplied; A is 1: the background is drawn)
//   z        Z            view depth of the surface in Frame::depth: the opaque scene and hair
//                         at least half opaque (composite.cl); kAovBackgroundZ where nothing
//   alpha    hair.A       the hair's own coverage, 1 - prod(1 - a_k) over the grooms drawn
//   tangent  tangent.X/Y/Z  world unit tangent (root to tip) of the nearest centre G-buffer
//                         word of any groom, decoded from its octahedral code; 0 where none
//   motion   motion.X/Y   pixels from this frame to the previous one for the surface in Z:
//                         X to the right, Y up (the compositors' convention); camera and
//                         transform keys, and deforming grooms through their motion pass
//                         (cage animation, wind, per-frame strand files); 0 on the background
//   strand   strand.groom, strand.id, strand.u  the strand of the nearest centre word of
//                         any groom: its groom (index in Scene::grooms), its index in that
//                         groom at full detail (hair meshes: bundle by bundle, strand files:
//                         file order) and its position root (0) to tip (1); -1 in all three
//                         where no strand is; 32-bit floats, exact for indices below 2^24
//                         (the identity word's limit). MSAA 1 only.
//   cryptomatte  CryptoGroom00..02.R/G/B/A, CryptoStrand00..02.R/G/B/A  ID mattes per groom
//                         and per strand (clhair/cryptomatte.h), with their manifests in the
//                         header (aovAttributes). MSAA 1 only; named alone, never by "all".
// Inputs and outputs only: nothing here touches the device.
#pragma once

#include <string>
#include <vector>

#include "clhair/image.h"

namespace clhair {

struct Frame;
struct FrameAovs;

enum class Aov { Rgba, Z, Alpha, Tangent, Motion, Strand, Cryptomatte };

// `Z` where no surface was drawn: a large finite depth (compositing arithmetic on +inf
// gives NaN, e.g. inf * 0 in a depth blend), the value Blender and others use.
constexpr float kAovBackgroundZ = 1.0e10f;

// The layers of a --aov value: a comma-separated list of rgba, z, alpha, tangent, motion,
// strand, cryptomatte, or "all" (every layer but cryptomatte, whose channels and manifests
// are asked for by name); duplicates collapse, the order is always the one above. Throws
// clhair::Error (one line naming the bad entry and the known names) for an unknown or empty entry.
std::vector<Aov> parseAovList(const std::string& list);
const char* aovName(Aov aov);

// One named channel of an image: width * height floats.
struct ImageChannel {
  std::string name;
  std::vector<float> values;
  bool half = false;  // stored as 16-bit float (values where exactness does not matter)
};

// One string attribute of an image file's header.
struct ImageAttribute {
  std::string name, value;
};

// The channels of `layers` from a frame rendered with RenderOptions::aovs (throws
// clhair::Error when a layer other than rgba is asked of a frame without them; cryptomatte
// needs RenderOptions::cryptomatte too).
std::vector<ImageChannel> aovChannels(const Frame& frame, const std::vector<Aov>& layers);
// The header attributes `layers` need: the Cryptomatte layers' name, hash, conversion and
// manifest (none for the other layers).
std::vector<ImageAttribute> aovAttributes(const Frame& frame, const std::vector<Aov>& layers);

// How well the motion layer explains the change between two frames (docs/aovs.md, "Checking
// motion"): frame t's hair alpha (`before`) warped to frame t+1 (`now`) by t+1's motion
// vectors, which point to frame t: each pixel of t+1 samples t's alpha bilinearly at
// (x + motion.X, y - motion.Y), the vector taken from the nearest surface (smallest Z) in its
// 3x3 neighbourhood so that background the hair has just uncovered follows the hair. The
// warped alpha >= 0.5 against t+1's hair.A >= 0.5: intersection over union (1 when they agree,
// also when both are empty). Both frames width x height with their AOVs.
double motionWarpIoU(const FrameAovs& now, const FrameAovs& before, int width, int height);
// The same intersection over union without moving anything (what motion 0 would give).
double maskIoU(const FrameAovs& now, const FrameAovs& before, int width, int height);

// Writes channels as one OpenEXR file (the name must end in .exr), through the same checked
// path as writeImage (options.exrCompression applies); channels are stored in the order given,
// `attributes` go into the header. Safe from several threads at once on different paths.
void writeChannels(const std::vector<ImageChannel>& channels, int width, int height,
                   const std::string& path, const ImageWriteOptions& options = {},
                   const std::vector<ImageAttribute>& attributes = {});

}  // namespace clhair
