// renderer.cpp — clhair.Renderer: one device and its compiled kernels kept across frames;
// frames submitted and waited for as in C++ (Renderer::submit / wait), each returned as a
// dict of NumPy arrays that own the frame's vectors (nothing copied after the read-back).
#include <chrono>
#include <cmath>
#include <map>
#include <string>

#include <nanobind/stl/string.h>

#include "arrays.h"
#include "bindings.h"
#include "clhair/aov.h"
#include "clhair/device.h"
#include "clhair/error.h"
#include "clhair/renderer.h"
#include "stages/view_math.h"

namespace clhair::py {

namespace {

// What render() was asked, as the command's flags say it (host/cli/render_plan.cpp).
struct Request {
  double frame = 1.0;
  int msaa = 1;
  bool aovs = true;
  std::string lod = "auto", filter = "auto", quality;
  bool ao = true;
};

RenderOptions renderOptions(const Request& q) {
  RenderOptions ro;
  if (q.lod == "on")
    ro.lod = Toggle::On;
  else if (q.lod == "off")
    ro.lod = Toggle::Off;
  else if (q.lod != "auto")
    throw Error("lod must be \"on\", \"off\" or \"auto\", not \"" + q.lod + "\"");
  if (q.msaa != 1 && q.msaa != 2 && q.msaa != 4 && q.msaa != 8)
    throw Error("msaa must be 1, 2, 4 or 8, not " + std::to_string(q.msaa));
  ro.msaa = q.msaa;
  ro.ambientOcclusion = q.ao;
  ro.aovs = q.aovs;
  ro.strandIds = q.aovs && q.msaa == 1;  // one strand per pixel: MSAA 1 only (as --aov all)
  if (q.filter == "on") {
    ro.filter = Toggle::On;
  } else if (q.filter == "off") {
    ro.filter = Toggle::Off;
  } else if (q.filter == "lipp" || q.filter == "huang") {
    ro.filter = Toggle::On;
    ro.filterMethod =
        q.filter == "huang" ? FilterParams::Method::Huang : FilterParams::Method::Lipp;
  } else if (q.filter != "auto") {
    throw Error("filter must be \"on\", \"off\", \"auto\", \"lipp\" or \"huang\", not \"" +
                q.filter + "\"");
  }
  if (q.quality == "draft")
    ro.quality = Quality::Draft;
  else if (q.quality == "good")
    ro.quality = Quality::Good;
  else if (!q.quality.empty())
    throw Error(
        "quality must be \"draft\" or \"good\" (final accumulates passes: use the "
        "command), not \"" +
        q.quality + "\"");
  ro.timings = false;
  ro.readBackDepth = !q.aovs;  // the AOVs carry their own depth (z)
  return ro;
}

// The still of `frame` with the camera the command would draw (the first of "cameras").
Scene stillOf(const Scene& scene, double frame) {
  Scene still = sceneAtFrame(scene, frame);
  if (!still.views.empty()) still.camera = viewCamera(still, still.views[0]);
  return still;
}

struct Pending {
  int width = 0, height = 0;
  bool aovs = false;
  Camera camera;
};

nb::dict cameraDict(const Camera& cam, int width, int height) {
  const gpu::ClhViewGpu v = makeView(cam, width, height);
  std::vector<float> m(v.world_to_view, v.world_to_view + 12);
  nb::dict d;
  d["world_to_view"] = toNumpy(std::move(m), {3, 4});
  d["fx"] = v.fx;
  d["fy"] = v.fy;
  d["cx"] = v.cx;
  d["cy"] = v.cy;
  return d;
}

class PyRenderer {
 public:
  PyRenderer(const std::string& selector, const std::string& subgroup, const std::string& cacheDir)
      : device_(open(selector, subgroup, cacheDir)), renderer_(device_) {}

  FrameTicket submit(const SceneHandle& s, const Request& q) {
    RenderOptions ro = renderOptions(q);
    if (!(q.frame >= -1e9 && q.frame <= 1e9)) throw Error("frame must be a finite number");
    Pending p;
    FrameTicket t = 0;
    {
      nb::gil_scoped_release unlocked;
      const Scene still = stillOf(*s.scene, q.frame);
      Scene previous;
      if (ro.aovs) {  // motion to the previous frame; frames 1 and before have none
        previous = q.frame > 1.0 ? stillOf(*s.scene, q.frame - 1.0) : still;
        ro.previous = &previous;
      }
      p.width = still.width;
      p.height = still.height;
      p.aovs = ro.aovs;
      p.camera = still.camera;
      t = renderer_.submit(still, ro);
    }
    pending_[t] = p;
    return t;
  }

  nb::dict wait(FrameTicket t) {
    const auto it = pending_.find(t);
    if (it == pending_.end())
      throw Error("ticket " + std::to_string(t) + " was not submitted or was waited for already");
    const Pending p = it->second;
    pending_.erase(it);
    Frame f;
    {
      nb::gil_scoped_release unlocked;
      f = renderer_.wait(t);
    }
    const auto w = static_cast<std::size_t>(p.width), h = static_cast<std::size_t>(p.height);
    nb::dict out;
    out["rgba"] = toNumpy(std::move(f.color.rgba), {h, w, 4});
    if (p.aovs) {
      // the labels hair models learn from, on the device (clhair/labels.h)
      HairLabels l;
      {
        nb::gil_scoped_release unlocked;
        l = renderer_.labels(f, p.camera);
      }
      out["mask"] = toNumpy(std::move(l.mask), {h, w}).attr("astype")("bool");
      out["orientation"] = toNumpy(std::move(l.angle), {h, w});
      out["confidence"] = toNumpy(std::move(l.confidence), {h, w});
      out["strand_map"] = toNumpy(std::move(l.strandMap), {h, w, 3});
      out["depth"] = toNumpy(std::move(f.aovs.z), {h, w});
      out["alpha"] = toNumpy(std::move(f.aovs.hairAlpha), {h, w});
      out["tangent"] = toNumpy(std::move(f.aovs.tangent), {h, w, 3});
      out["motion"] = toNumpy(std::move(f.aovs.motion), {h, w, 2});
      if (!f.aovs.strand.empty()) out["strand"] = toNumpy(std::move(f.aovs.strand), {h, w, 3});
      out["hair"] = toNumpy(std::move(f.aovs.hair), {h, w, 4});
      out["opaque"] = toNumpy(std::move(f.aovs.opaque), {h, w, 4});
    } else {
      out["depth"] = toNumpy(std::move(f.depth), {h, w});
    }
    out["camera"] = cameraDict(p.camera, p.width, p.height);
    return out;
  }

  // The library's own loop over the same frame (the benchmark's baseline): seconds for n.
  double benchLibrary(const SceneHandle& s, const Request& q, int n) {
    RenderOptions ro = renderOptions(q);
    nb::gil_scoped_release unlocked;
    const Scene still = stillOf(*s.scene, q.frame);
    if (ro.aovs) ro.previous = &still;
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < n; ++i) {
      Frame f = renderer_.render(still, ro);
      if (f.color.rgba.empty()) throw Error("empty frame");
    }
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  std::string deviceName() const { return device_.info().name; }
  std::string platformName() const { return device_.info().platformName; }
  int framesInFlight() const { return renderer_.framesInFlight(); }
  void setFramesInFlight(int n) {
    if (n < 1 || n > kMaxFramesInFlight)
      throw Error("frames_in_flight must be 1.." + std::to_string(kMaxFramesInFlight) + ", not " +
                  std::to_string(n));
    renderer_.setFramesInFlight(n);
  }
  void releaseGrooms() { renderer_.releaseGrooms(); }

 private:
  static Device open(const std::string& selector, const std::string& subgroup,
                     const std::string& cacheDir) {
    DeviceOptions o;
    o.selector = selector;
    o.subgroup = subgroup;
    o.cacheDir = cacheDir;
    nb::gil_scoped_release unlocked;
    return Device::open(DeviceOptions::fromEnvironment(o));
  }

  Device device_;
  Renderer renderer_;
  std::map<FrameTicket, Pending> pending_;
};

Request request(double frame, int msaa, bool aovs, const std::string& lod,
                const std::string& filter, const std::string& quality, bool ao) {
  Request q;
  q.frame = frame;
  q.msaa = msaa;
  q.aovs = aovs;
  q.lod = lod;
  q.filter = filter;
  q.quality = quality;
  q.ao = ao;
  return q;
}

}  // namespace

void bindRenderer(nb::module_& m) {
  nb::class_<PyRenderer>(m, "_Renderer")
      .def(nb::init<const std::string&, const std::string&, const std::string&>(),
           nb::arg("device") = "", nb::arg("subgroup") = "", nb::arg("cache_dir") = "")
      .def(
          "submit",
          [](PyRenderer& r, const SceneHandle& s, double frame, int msaa, bool aovs,
             const std::string& lod, const std::string& filter, const std::string& quality,
             bool ao) { return r.submit(s, request(frame, msaa, aovs, lod, filter, quality, ao)); },
          nb::arg("scene"), nb::arg("frame"), nb::arg("msaa"), nb::arg("aovs"), nb::arg("lod"),
          nb::arg("filter"), nb::arg("quality"), nb::arg("ao"))
      .def("wait", &PyRenderer::wait, nb::arg("ticket"))
      .def(
          "bench_library",
          [](PyRenderer& r, const SceneHandle& s, double frame, int msaa, bool aovs,
             const std::string& lod, const std::string& filter, const std::string& quality, bool ao,
             int n) {
            return r.benchLibrary(s, request(frame, msaa, aovs, lod, filter, quality, ao), n);
          },
          nb::arg("scene"), nb::arg("frame"), nb::arg("msaa"), nb::arg("aovs"), nb::arg("lod"),
          nb::arg("filter"), nb::arg("quality"), nb::arg("ao"), nb::arg("n"))
      .def_prop_ro("device_name", &PyRenderer::deviceName)
      .def_prop_ro("platform_name", &PyRenderer::platformName)
      .def_prop_rw("frames_in_flight", &PyRenderer::framesInFlight, &PyRenderer::setFramesInFlight)
      .def("release_grooms", &PyRenderer::releaseGrooms);
}

}  // namespace clhair::py
