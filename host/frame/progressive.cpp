// progressive.cpp — see clhair/progressive.h.
#include "clhair/progressive.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

#include "clhair/error.h"

namespace clhair {

namespace {
// fixed point of the sums: 2^24 steps per unit of linear radiance, values clamped to
// +-2^20 so that 2^16 passes stay within 63 bits
constexpr double kFixed = 16777216.0;
constexpr double kLimit = 1048576.0;

// Adds the stage times of `more` to `sum`, stage by stage.
void addTimings(std::vector<StageTime>& sum, const std::vector<StageTime>& more) {
  for (const StageTime& t : more) {
    auto it = std::find_if(sum.begin(), sum.end(),
                           [&](const StageTime& a) { return a.stage == t.stage; });
    if (it == sum.end()) {
      sum.push_back(t);
    } else {
      it->ms += t.ms;
      it->wallMs += t.wallMs;
      it->cpuMs += t.cpuMs;
    }
  }
}
}  // namespace

Quality qualityLevel(const Scene& scene, const RenderOptions& options) {
  return options.quality.value_or(scene.quality.level);
}

int finalPasses(const Scene& scene, const RenderOptions& options) {
  const int n = options.spp > 0 ? options.spp
                                : (scene.quality.spp > 0 ? scene.quality.spp : kDefaultFinalPasses);
  if (n > kMaxFinalPasses)
    throw Error("quality final: " + std::to_string(n) + " passes, at most " +
                std::to_string(kMaxFinalPasses));
  return n;
}

RenderOptions qualityOptions(const Scene& scene, const RenderOptions& options) {
  RenderOptions o = options;
  const Quality q = qualityLevel(scene, options);
  o.quality = Quality::Draft;
  if (q == Quality::Draft) {
    if (o.pointShading == Toggle::Default) o.pointShading = Toggle::Off;
    return o;
  }
  const bool good = q == Quality::Good || (options.finalPath == FinalPath::Default
                                               ? kFinalPassGood
                                               : options.finalPath == FinalPath::Good);
  o.quality = q == Quality::Good ? Quality::Good : Quality::Draft;
  if (good) {
    if (o.msaa <= 1) o.msaa = kGoodMsaa;
    if (o.pointShading == Toggle::Default)
      o.pointShading = kGoodPointShading ? Toggle::On : Toggle::Off;
  } else {
    o.msaa = 1;
    o.pointShading = Toggle::Off;
  }
  o.filter = Toggle::Off;
  return o;
}

void finalJitter(int pass, float& x, float& y) {
  // R2 sequence (Roberts 2018) around the pixel centre, the first at the centre (the
  // reference's, host/renderer_tools.cpp)
  const double g = 1.32471795724474602596;
  x = static_cast<float>(std::fmod(0.5 + pass / g, 1.0) - 0.5);
  y = static_cast<float>(std::fmod(0.5 + pass / (g * g), 1.0) - 0.5);
}

ProgressiveStill::ProgressiveStill(Renderer& renderer, const Scene& scene,
                                   const RenderOptions& options)
    : renderer_(renderer), scene_(scene) {
  RenderOptions o = options;
  o.quality = Quality::Final;
  options_ = qualityOptions(scene, o);
  if (options_.finalSubset < 1 || options_.finalSubset > kMaxFinalSubset)
    throw Error("quality final: a subset of one strand in " + std::to_string(options_.finalSubset) +
                "; expected 1.." + std::to_string(kMaxFinalSubset));
  static std::atomic<std::uint64_t> stills{0};
  id_ = ++stills;
}

void ProgressiveStill::add(int first, int count) {
  if (first < 0 || count < 0 || first + count > kMaxFinalPasses)
    throw Error("quality final: passes " + std::to_string(first) + ".." +
                std::to_string(first + count) + " outside 0.." + std::to_string(kMaxFinalPasses));
  for (int i = first; i < first + count; ++i) {
    RenderOptions o = options_;
    float jx = 0.0f, jy = 0.0f;
    finalJitter(i, jx, jy);
    o.jitterX += jx;
    o.jitterY += jy;
    o.still = options_.reuseAssembly ? id_ : 0;
    o.stillPass = i;
    Frame f = renderer_.render(scene_, o);
    const std::size_t n = f.color.rgba.size();
    if (passes_ == 0) {
      width_ = f.color.width;
      height_ = f.color.height;
      sums_.assign(n, 0);
      first_ = std::move(f);
      for (std::size_t k = 0; k < n; ++k)
        sums_[k] = std::llround(std::clamp<double>(first_.color.rgba[k], -kLimit, kLimit) * kFixed);
    } else {
      if (f.color.width != width_ || f.color.height != height_)
        throw Error("quality final: a pass of another size");
      for (std::size_t k = 0; k < n; ++k)
        sums_[k] += std::llround(std::clamp<double>(f.color.rgba[k], -kLimit, kLimit) * kFixed);
      for (std::size_t k = 0; k < first_.depth.size() && k < f.depth.size(); ++k)
        first_.depth[k] = std::min(first_.depth[k], f.depth[k]);
      addTimings(first_.timings, f.timings);
      first_.stats.shadowMapsBuilt += f.stats.shadowMapsBuilt;
    }
    ++passes_;
    if (progress) progress(passes_);
  }
}

void ProgressiveStill::merge(const ProgressiveStill& other) {
  if (other.passes_ == 0) return;
  if (passes_ == 0) {
    passes_ = other.passes_;
    width_ = other.width_;
    height_ = other.height_;
    sums_ = other.sums_;
    first_ = other.first_;
    return;
  }
  if (other.width_ != width_ || other.height_ != height_)
    throw Error("quality final: merging accumulations of different sizes");
  for (std::size_t k = 0; k < sums_.size(); ++k) sums_[k] += other.sums_[k];
  for (std::size_t k = 0; k < first_.depth.size() && k < other.first_.depth.size(); ++k)
    first_.depth[k] = std::min(first_.depth[k], other.first_.depth[k]);
  addTimings(first_.timings, other.first_.timings);
  first_.stats.shadowMapsBuilt += other.first_.stats.shadowMapsBuilt;
  passes_ += other.passes_;
}

Frame ProgressiveStill::frame() const {
  if (passes_ == 0) throw Error("quality final: no pass rendered");
  Frame f = first_;
  const double scale = 1.0 / (kFixed * passes_);
  for (std::size_t k = 0; k < sums_.size(); ++k)
    f.color.rgba[k] = static_cast<float>(static_cast<double>(sums_[k]) * scale);
  return f;
}

}  // namespace clhair
