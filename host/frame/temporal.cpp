// temporal.cpp — see clhair/temporal.h. Everything here runs on the host over planes read back
// with the frame's AOVs: the reprojection is a study option, and doing it on the CPU keeps the
// device pipeline (and every frame rendered without it) exactly as it is.
#include "clhair/temporal.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "clhair/aov.h"
#include "clhair/error.h"

namespace clhair {

namespace {

bool isBackground(float z) { return !(z < kAovBackgroundZ); }

// Index of the smallest z in the 3x3 neighbourhood of (x, y) inside the image; ties keep the
// first in row order, so the choice does not depend on anything but the plane.
std::size_t nearestAround(const std::vector<float>& z, int width, int height, int x, int y) {
  std::size_t best = static_cast<std::size_t>(y) * width + x;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int qx = x + dx, qy = y + dy;
      if (qx < 0 || qy < 0 || qx >= width || qy >= height) continue;
      const std::size_t q = static_cast<std::size_t>(qy) * width + qx;
      if (z[q] < z[best]) best = q;
    }
  return best;
}

void checkPlane(const std::vector<float>& plane, std::size_t want, const char* what) {
  if (plane.size() != want)
    throw Error(std::string("temporal reprojection: ") + what + " holds " +
                std::to_string(plane.size()) + " values, need " + std::to_string(want) +
                " (render the frames with RenderOptions::aovs)");
}

}  // namespace

std::vector<float> reprojectHair(const FrameAovs& now, const FrameAovs& before,
                                 const std::vector<float>& history, int width, int height,
                                 const TemporalParams& params, TemporalStats* stats) {
  if (width < 1 || height < 1) throw Error("temporal reprojection: empty image");
  const std::size_t pixels = static_cast<std::size_t>(width) * height;
  checkPlane(now.hair, pixels * 4, "this frame's hair layer");
  checkPlane(now.z, pixels, "this frame's Z");
  checkPlane(now.motion, pixels * 2, "this frame's motion");
  checkPlane(before.z, pixels, "the previous frame's Z");
  checkPlane(history, pixels * 4, "the history");
  if (!(params.blend > 0.0f && params.blend <= 1.0f))
    throw Error("temporal reprojection: blend must be in (0, 1], not " +
                std::to_string(params.blend));
  const float keep = 1.0f - params.blend;
  TemporalStats local;
  std::vector<float> out(pixels * 4);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * width + x;
      const float* own = &now.hair[p * 4];
      float* o = &out[p * 4];
      std::copy(own, own + 4, o);
      // the nearest surface around p gives the motion: faint hair edges move with the hair
      const std::size_t near = nearestAround(now.z, width, height, x, y);
      const float zc = now.z[near];
      const float sx = static_cast<float>(x) + 0.5f + now.motion[near * 2];
      const float sy = static_cast<float>(y) + 0.5f - now.motion[near * 2 + 1];  // y up
      if (!(sx >= 0.0f && sy >= 0.0f && sx <= static_cast<float>(width) &&
            sy <= static_cast<float>(height))) {
        ++local.outside;
        continue;
      }
      if (params.rejectDepth) {
        const int px = std::min(static_cast<int>(sx), width - 1);
        const int py = std::min(static_cast<int>(sy), height - 1);
        const float zp = before.z[nearestAround(before.z, width, height, px, py)];
        const bool bgNow = isBackground(zc), bgBefore = isBackground(zp);
        if (bgNow != bgBefore ||
            (!bgNow && std::fabs(zp - zc) > params.depthTolerance * std::min(zp, zc))) {
          ++local.rejected;
          continue;
        }
      }
      // bilinear between the four pixel centres around the sample (clamped to the border)
      const float fx = sx - 0.5f, fy = sy - 0.5f;
      const float x0f = std::floor(fx), y0f = std::floor(fy);
      const float tx = fx - x0f, ty = fy - y0f;
      const int x0 = std::clamp(static_cast<int>(x0f), 0, width - 1);
      const int y0 = std::clamp(static_cast<int>(y0f), 0, height - 1);
      const int x1 = std::clamp(static_cast<int>(x0f) + 1, 0, width - 1);
      const int y1 = std::clamp(static_cast<int>(y0f) + 1, 0, height - 1);
      const float* h00 = &history[(static_cast<std::size_t>(y0) * width + x0) * 4];
      const float* h10 = &history[(static_cast<std::size_t>(y0) * width + x1) * 4];
      const float* h01 = &history[(static_cast<std::size_t>(y1) * width + x0) * 4];
      const float* h11 = &history[(static_cast<std::size_t>(y1) * width + x1) * 4];
      float h[4];
      for (int c = 0; c < 4; ++c)
        h[c] = (h00[c] * (1.0f - tx) + h10[c] * tx) * (1.0f - ty) +
               (h01[c] * (1.0f - tx) + h11[c] * tx) * ty;
      if (params.clamp) {
        float lo[4] = {own[0], own[1], own[2], own[3]}, hi[4] = {own[0], own[1], own[2], own[3]};
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int qx = x + dx, qy = y + dy;
            if (qx < 0 || qy < 0 || qx >= width || qy >= height) continue;
            const float* q = &now.hair[(static_cast<std::size_t>(qy) * width + qx) * 4];
            for (int c = 0; c < 4; ++c) {
              lo[c] = std::min(lo[c], q[c]);
              hi[c] = std::max(hi[c], q[c]);
            }
          }
        bool changed = false;
        for (int c = 0; c < 4; ++c) {
          const float v = std::clamp(h[c], lo[c], hi[c]);
          changed = changed || v != h[c];
          h[c] = v;
        }
        if (changed) ++local.clamped;
      }
      for (int c = 0; c < 4; ++c) o[c] = params.blend * own[c] + keep * h[c];
      ++local.blended;
    }
  if (stats) {
    stats->blended += local.blended;
    stats->outside += local.outside;
    stats->rejected += local.rejected;
    stats->clamped += local.clamped;
  }
  return out;
}

Image recomposeHair(const Frame& frame, const std::vector<float>& hair) {
  const std::size_t pixels = frame.color.rgba.size() / 4;
  checkPlane(frame.aovs.hair, pixels * 4, "the frame's hair layer");
  checkPlane(frame.aovs.opaque, pixels * 4, "the frame's opaque colour");
  checkPlane(hair, pixels * 4, "the blended hair");
  Image out = frame.color;
  for (std::size_t p = 0; p < pixels; ++p) {
    const float* h = &hair[p * 4];
    const float* own = &frame.aovs.hair[p * 4];
    if (std::equal(h, h + 4, own)) continue;  // unchanged: the rendered colour, exactly
    const float* under = &frame.aovs.opaque[p * 4];
    for (int c = 0; c < 3; ++c) out.rgba[p * 4 + c] = h[c] + (1.0f - h[3]) * under[c];
  }
  return out;
}

FrameSequence::FrameSequence(Renderer& renderer, std::function<Scene(long long)> stillAt,
                             const RenderOptions& options, long long firstFrame)
    : renderer_(renderer), stillAt_(std::move(stillAt)), options_(options), first_(firstFrame) {
  options_.previous = nullptr;
}

const Frame& FrameSequence::own(long long n, const Scene* still) {
  auto it = held_.find(n);
  if (it != held_.end()) return it->second;
  Scene mine, previous;
  if (!still) {
    mine = stillAt_(n);
    still = &mine;
  }
  previous = n > first_ ? stillAt_(n - 1) : *still;
  RenderOptions o = options_;
  o.aovs = true;
  o.previous = &previous;
  Frame f = renderer_.render(*still, o);
  // per-frame strand files are new grooms every frame: their device forms go with it
  renderer_.releaseGrooms();
  ++rendered_;
  return held_.emplace(n, std::move(f)).first->second;
}

Frame FrameSequence::render(long long n) {
  const Scene still = stillAt_(n);
  const int history = options_.temporal >= 0 ? options_.temporal : still.temporal.history;
  if (history < 0 || history > kMaxTemporalHistory)
    throw Error("temporal reprojection: history of " + std::to_string(history) +
                " frames; expected 0.." + std::to_string(kMaxTemporalHistory));
  stats_ = TemporalStats{};
  lastHistory_ = history;
  if (history == 0) {
    held_.clear();
    RenderOptions o = options_;
    Scene previous;
    if (o.aovs) {
      previous = n > first_ ? stillAt_(n - 1) : still;
      o.previous = &previous;
    }
    ++rendered_;
    return renderer_.render(still, o);
  }
  const long long start = n > first_ ? std::max(first_, n - history) : n;
  for (auto it = held_.begin(); it != held_.end();)  // keep only this window's frames
    it = it->first < start || it->first > n ? held_.erase(it) : std::next(it);
  for (long long j = start; j < n; ++j) own(j, nullptr);
  const Frame& mine = own(n, &still);
  std::vector<float> blended = held_.at(start).aovs.hair;
  for (long long j = start + 1; j <= n; ++j)
    blended = reprojectHair(held_.at(j).aovs, held_.at(j - 1).aovs, blended, still.width,
                            still.height, still.temporal, &stats_);
  Frame out = mine;
  out.color = recomposeHair(mine, blended);
  if (options_.aovs) {
    for (std::size_t p = 0; p < out.aovs.hairAlpha.size(); ++p)
      out.aovs.hairAlpha[p] = std::clamp(blended[p * 4 + 3], 0.0f, 1.0f);
    out.aovs.hair = std::move(blended);
  } else {
    out.aovs = FrameAovs{};
  }
  return out;
}

}  // namespace clhair
