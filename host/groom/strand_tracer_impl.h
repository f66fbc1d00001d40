// strand_tracer_impl.h — StrandTracer's state, shared by strand_tracer.cpp (the scene, the
// centre-layer trace) and path_trace.cpp (the path-traced reference). Private to host/groom.
#pragma once

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "clhair/error.h"
#include "groom/strand_tracer.h"

namespace clhair {

// The G-buffer's near plane (clh_raster_init): nothing nearer is drawn.
inline constexpr float kNearZ = 1e-4f;

inline const char* embreeErrorName(RTCError e) {
  switch (e) {
    case RTC_ERROR_NONE:
      return "no error";
    case RTC_ERROR_INVALID_ARGUMENT:
      return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION:
      return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY:
      return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU:
      return "unsupported CPU";
    case RTC_ERROR_CANCELLED:
      return "cancelled";
    default:
      return "unknown error";
  }
}

inline void xform3(const float* m, float x, float y, float z, float w, float* out) {
  out[0] = m[0] * x + m[1] * y + m[2] * z + m[3] * w;
  out[1] = m[4] * x + m[5] * y + m[6] * z + m[7] * w;
  out[2] = m[8] * x + m[9] * y + m[10] * z + m[11] * w;
}

struct StrandTracer::Impl {
  // Per point of one groom draw: world tangent, styling w, AO and the word's u, v source
  // (root uv, or the file colour with blue in place of AO).
  struct Groom {
    std::uint32_t draw = 0;
    bool fileColor = false;
    std::vector<float> tangent;            // xyz per point
    std::vector<float> attr;               // w, ao (or blue), u (or red), v (or green) per point
    std::vector<std::uint32_t> segFirst;   // first point of each segment
    gpu::ClhGroomGpu params{};             // the record the strands were placed with
    std::vector<float> axis;               // view-space points, xyz and radius (path mode)
    std::vector<std::uint32_t> strandSeg;  // per segment: its strand's first segment (path mode)
  };
  // An opaque surface of the path-traced reference (path mode): Lambertian, linear albedo.
  struct Opaque {
    bool present = false;
    float albedo[3] = {0.0f, 0.0f, 0.0f};
  };
  struct Hit {
    std::uint32_t geom = RTC_INVALID_GEOMETRY_ID;
    std::uint32_t prim = 0;
    float u = 0.0f, t = 0.0f;
  };

  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<Groom> grooms;   // by Embree geometry id
  std::vector<Opaque> opaque;  // by Embree geometry id (path mode)
  bool pathMode = false;
  std::vector<Hit> hits;
  std::uint64_t strandTotal = 0, segmentTotal = 0;
  bool committed = false;

  void check(const std::string& what) {
    const RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE)
      throw Error("Embree: " + what + " failed: " + embreeErrorName(e) +
                  (e == RTC_ERROR_OUT_OF_MEMORY ? " (the traced reference needs the strands "
                                                  "and their BVH in host memory)"
                                                : ""));
  }

  std::uint64_t wordAt(const Hit& h, const Groom& g, const gpu::ClhGroomGpu& p) const {
    using namespace gpu;
    const std::uint32_t a = g.segFirst[h.prim], b = a + 1;
    const float u = std::clamp(h.u, 0.0f, 1.0f);
    auto lerp = [u](float x, float y) { return x + (y - x) * u; };
    const float tx = lerp(g.tangent[3 * a], g.tangent[3 * b]);
    const float ty = lerp(g.tangent[3 * a + 1], g.tangent[3 * b + 1]);
    const float tz = lerp(g.tangent[3 * a + 2], g.tangent[3 * b + 2]);
    const float l1 = std::fabs(tx) + std::fabs(ty) + std::fabs(tz);
    const clh_u32 oct =
        (l1 > 1e-30f && l1 < 1e30f) ? clh_oct_encode(tx, ty, tz) : clh_oct_encode(0.0f, 1.0f, 0.0f);
    const float w = lerp(g.attr[4 * a], g.attr[4 * b]);
    const float ao = lerp(g.attr[4 * a + 1], g.attr[4 * b + 1]);
    const float cu = lerp(g.attr[4 * a + 2], g.attr[4 * b + 2]);
    const float cv = lerp(g.attr[4 * a + 3], g.attr[4 * b + 3]);
    // file colour (gpu_types.h): red, green, blue as sqrt codes in u, v, AO
    const clh_u32 u6 = g.fileColor ? clh_file_color_code(cu) : clh_unorm_bits(cu, 6u);
    const clh_u32 v6 = g.fileColor ? clh_file_color_code(cv) : clh_unorm_bits(cv, 6u);
    const clh_u32 ao6 = g.fileColor ? clh_file_color_code(ao) : clh_unorm_bits(ao, 6u);
    return clh_gbuf_pack(clh_depth_encode(h.t, p.depth_near, p.depth_far), oct, u6, v6,
                         clh_unorm_bits(w, 6u), ao6);
  }
};

}  // namespace clhair
