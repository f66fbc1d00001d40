// animation.h — what changes from frame to frame: keyframed values, a hair mesh's cage given
// per frame (a cage-animation file) and the procedural wind on a cage.
//
// A scene (docs/scene-format.md, "Animation") holds these next to its still values;
// sceneAtFrame (clhair/scene.h) evaluates them at one frame number and returns a still
// Scene. Evaluation depends only on the scene and the frame number, never on frames
// evaluated before, so any frame of a range renders the same alone or in any order.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace clhair {

enum class Interpolation {
  Linear,  // piecewise linear between keys
  // Cubic Hermite through every key: Catmull-Rom tangents (p[i+1] - p[i-1]) / (f[i+1] - f[i-1])
  // at inner keys, zero tangents at the first and last key (motion eases in and out there;
  // with two keys this is smoothstep).
  Smooth
};

// Keys of `width` numbers each at strictly increasing frame numbers. Before the first key
// the first key's values hold, after the last key the last key's.
struct KeyTrack {
  Interpolation interpolation = Interpolation::Linear;
  int width = 0;
  std::vector<double> frames;  // strictly increasing
  std::vector<double> values;  // frames.size() * width, key-major

  bool empty() const { return frames.empty(); }
  // The `width` values at `frame`.
  std::vector<double> evaluate(double frame) const;
};

// A hair mesh's layer vertices per frame (docs/cage-animation-format.md): frame k holds
// `vertices` positions, layer-major like HairMesh::positions, in the mesh's object space.
struct CageAnimation {
  std::uint32_t frames = 0;
  std::uint32_t vertices = 0;
  std::vector<glm::vec3> positions;  // frames * vertices

  const glm::vec3* frame(std::uint32_t k) const {
    return positions.data() + static_cast<std::size_t>(k) * vertices;
  }
};

// Largest accepted counts of a cage-animation file (larger headers are refused as absurd).
constexpr std::uint32_t kMaxCageFrames = 1000000;
constexpr std::uint32_t kMaxCageVertices = 1u << 26;

// Reads and checks a cage-animation file completely: header, counts against the file size
// and against `maxBytes` (the positions as float32), every coordinate finite. Every failure
// is one clhair::Error line naming the file.
CageAnimation loadCageAnimation(const std::string& path, std::uint64_t maxBytes);
// Writes atomically (temporary file, then rename).
void saveCageAnimation(const CageAnimation& cage, const std::string& path);

// A path pattern with a frame number: the last run of '#' in the file name replaced by
// `frame`, zero-padded to the run's length ("out.####.exr", 7 -> "out.0007.exr"); a pattern
// without '#' in its file name is returned as it is.
std::string framePath(const std::string& pattern, long long frame);

// Strand files given one per frame ("bob.####.hair"): the pattern (an absolute or
// scene-relative path resolved at load), the first and last frame numbers found when the
// scene loaded, and the byte limit each file is read with.
struct StrandFrames {
  std::string pattern;
  long long first = 0, last = 0;
  std::uint64_t maxBytes = 0;
};

// Procedural sway of a hair mesh's cage (docs/scene-format.md, "Wind"). A layer vertex at
// height h = layer / (layers - 1) moves by
//   strength * h^2 * (0.5 + 0.5 sin(2 pi (frequency * t - dot(root, direction) / wavelength)))
// world units along the unit `direction` (world space), t = frame / frame rate and `root`
// the world position of its root vertex: roots stay put, tips lean downwind and sway, and
// the gust travels along the wind.
struct WindParams {
  float strength = 0.0f;  // world units at the tips; 0: no wind
  glm::vec3 direction{1.0f, 0.0f, 0.0f};
  float frequency = 0.5f;   // sways per second
  float wavelength = 1.0f;  // world units between gust fronts
};

}  // namespace clhair
