// strand_tracer.cpp — see strand_tracer.h.
#include "groom/strand_tracer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>
#include <thread>

#include "clhair/error.h"
#include "groom/strand_tracer_impl.h"

namespace clhair {

StrandTracer::StrandTracer(bool pathMode) : impl_(std::make_unique<Impl>()) {
  impl_->pathMode = pathMode;
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device)
    throw Error("Embree: creating a device failed: " +
                std::string(embreeErrorName(rtcGetDeviceError(nullptr))));
  impl_->scene = rtcNewScene(impl_->device);
  impl_->check("creating a scene");
  // thin fibres seen from afar: robust traversal leaves no holes at BVH node boundaries
  // (path mode: paths leaving a fibre skip that fibre through a context filter)
  rtcSetSceneFlags(impl_->scene,
                   pathMode ? RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION
                            : RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_MEDIUM);
}

StrandTracer::~StrandTracer() {
  if (impl_->scene) rtcReleaseScene(impl_->scene);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

void StrandTracer::addGroom(std::uint32_t draw, const StrandSet& s, const gpu::ClhGroomGpu& p) {
  Impl& r = *impl_;
  if (r.committed) throw Error("StrandTracer::addGroom after commit()");
  const std::size_t P = s.points.size() / 3;
  if (s.tangents.size() != 3 * P || s.w.size() != P || s.ao.size() != P ||
      s.uv.size() != 2 * s.pointCounts.size() || (!s.look.empty() && s.look.size() != 4 * P))
    throw Error("traced reference: the exported strands of groom " + std::to_string(draw) +
                " have inconsistent array sizes");
  const bool fileColor = p.look[2] > 0.5f && !s.look.empty();
  const bool fileThickness = p.look[3] > 0.0f && !s.look.empty();
  const bool fileOpacity = p.look[3] < 0.0f && !s.look.empty();  // width times -look.w
  Impl::Groom g;
  g.draw = draw;
  g.fileColor = fileColor;
  g.params = p;
  if (r.pathMode) g.axis.resize(4 * P);
  g.tangent.resize(3 * P);
  g.attr.resize(4 * P);
  std::vector<float> vertices(4 * P);
  std::vector<unsigned char> flags;
  std::size_t at = 0;
  for (std::size_t st = 0; st < s.pointCounts.size(); ++st) {
    const std::uint32_t n = s.pointCounts[st];
    if (at + n > P) throw Error("traced reference: point counts exceed the exported points");
    for (std::uint32_t k = 0; k < n; ++k) {
      const std::size_t i = at + k;
      float v[3];
      xform3(p.obj_to_view, s.points[3 * i], s.points[3 * i + 1], s.points[3 * i + 2], 1.0f, v);
      const float diameter = fileThickness ? s.look[4 * i + 3] * p.look[3]
                             : fileOpacity ? -s.look[4 * i + 3] * p.strand_width
                                           : p.strand_width;
      vertices[4 * i] = v[0];
      vertices[4 * i + 1] = v[1];
      vertices[4 * i + 2] = v[2];
      vertices[4 * i + 3] = 0.5f * std::max(diameter, 0.0f);
      if (r.pathMode) std::copy(&vertices[4 * i], &vertices[4 * i] + 4, &g.axis[4 * i]);
      xform3(p.obj_to_world, s.tangents[3 * i], s.tangents[3 * i + 1], s.tangents[3 * i + 2], 0.0f,
             &g.tangent[3 * i]);
      float* a = &g.attr[4 * i];
      a[0] = s.w[i];
      a[1] = fileColor ? s.look[4 * i + 2] : s.ao[i];
      a[2] = fileColor ? s.look[4 * i] : s.uv[2 * st];
      a[3] = fileColor ? s.look[4 * i + 1] : s.uv[2 * st + 1];
      if (k + 1 < n) {
        if (r.pathMode) g.strandSeg.push_back(static_cast<std::uint32_t>(g.segFirst.size() - k));
        g.segFirst.push_back(static_cast<std::uint32_t>(i));
        flags.push_back(
            static_cast<unsigned char>((k > 0 ? RTC_CURVE_FLAG_NEIGHBOR_LEFT : 0) |
                                       (k + 2 < n ? RTC_CURVE_FLAG_NEIGHBOR_RIGHT : 0)));
      }
    }
    at += n;
  }
  if (g.segFirst.empty()) return;
  RTCGeometry geom = rtcNewGeometry(r.device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
  r.check("creating the curves of groom " + std::to_string(draw));
  auto* vb = static_cast<float*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 16, P));
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0,
                                                            RTC_FORMAT_UINT, 4, g.segFirst.size()));
  auto* fb = static_cast<unsigned char*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_FLAGS, 0, RTC_FORMAT_UCHAR, 1, flags.size()));
  if (!vb || !ib || !fb) {
    rtcReleaseGeometry(geom);
    r.check("allocating the curves of groom " + std::to_string(draw));
    throw Error("Embree: allocating the curves of groom " + std::to_string(draw) + " failed");
  }
  std::copy(vertices.begin(), vertices.end(), vb);
  std::copy(g.segFirst.begin(), g.segFirst.end(), ib);
  std::copy(flags.begin(), flags.end(), fb);
  rtcCommitGeometry(geom);
  const unsigned id = rtcAttachGeometry(r.scene, geom);
  rtcReleaseGeometry(geom);
  r.check("adding the curves of groom " + std::to_string(draw));
  if (r.grooms.size() <= id) r.grooms.resize(id + 1);
  r.strandTotal += s.pointCounts.size();
  r.segmentTotal += g.segFirst.size();
  r.grooms[id] = std::move(g);
}

void StrandTracer::commit() {
  rtcCommitScene(impl_->scene);
  impl_->check("building the BVH");
  impl_->committed = true;
}

void StrandTracer::trace(const gpu::ClhViewGpu& view, const std::vector<float>& depth) {
  Impl& r = *impl_;
  if (!r.committed) throw Error("StrandTracer::trace before commit()");
  const std::uint32_t W = view.width, H = view.height;
  const std::size_t pixels = static_cast<std::size_t>(W) * H;
  if (depth.size() != pixels)
    throw Error("traced reference: " + std::to_string(depth.size()) + " depth values for " +
                std::to_string(pixels) + " pixels");
  r.hits.assign(pixels, Impl::Hit{});
  std::atomic<std::uint32_t> nextRow{0};
  auto work = [&] {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (std::uint32_t y = nextRow++; y < H; y = nextRow++) {
      for (std::uint32_t x = 0; x < W; ++x) {
        const std::size_t idx = static_cast<std::size_t>(y) * W + x;
        RTCRayHit rh;
        rh.ray.org_x = rh.ray.org_y = rh.ray.org_z = 0.0f;
        // view space (gpu_types.h): x_px = cx + fx x / z, y_px = cy - fy y / z; dir.z = 1,
        // so the ray parameter is the view depth
        rh.ray.dir_x = (static_cast<float>(x) + 0.5f - view.cx) / view.fx;
        rh.ray.dir_y = -(static_cast<float>(y) + 0.5f - view.cy) / view.fy;
        rh.ray.dir_z = 1.0f;
        rh.ray.tnear = kNearZ;
        const float d = depth[idx];
        rh.ray.tfar =
            d < std::numeric_limits<float>::infinity() ? d : std::numeric_limits<float>::infinity();
        rh.ray.time = 0.0f;
        rh.ray.mask = 0xFFFFFFFFu;
        rh.ray.id = 0;
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        if (!(rh.ray.tfar > rh.ray.tnear)) continue;
        rtcIntersect1(r.scene, &ctx, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        Impl::Hit& h = r.hits[idx];
        h.geom = rh.hit.geomID;
        h.prim = rh.hit.primID;
        h.u = rh.hit.u;
        h.t = rh.ray.tfar;
      }
    }
  };
  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned i = 1; i < threads; ++i) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  r.check("tracing");
}

void StrandTracer::centreLayer(std::uint32_t draw, const gpu::ClhGroomGpu& params,
                               std::vector<std::uint64_t>& words) const {
  using gpu::clh_u64;
  const Impl& r = *impl_;
  words.assign(r.hits.size(), CLH_GBUF_EMPTY);
  for (std::size_t i = 0; i < r.hits.size(); ++i) {
    const Impl::Hit& h = r.hits[i];
    if (h.geom >= r.grooms.size() || r.grooms[h.geom].draw != draw) continue;
    const Impl::Groom& g = r.grooms[h.geom];
    if (h.prim >= g.segFirst.size()) continue;
    words[i] = r.wordAt(h, g, params);
  }
}

std::uint64_t StrandTracer::hits() const {
  std::uint64_t n = 0;
  for (const Impl::Hit& h : impl_->hits) n += h.geom != RTC_INVALID_GEOMETRY_ID;
  return n;
}

std::uint64_t StrandTracer::strands() const { return impl_->strandTotal; }
std::uint64_t StrandTracer::segments() const { return impl_->segmentTotal; }

}  // namespace clhair
