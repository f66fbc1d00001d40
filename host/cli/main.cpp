// main.cpp — the `clhair` command: a thin user of the library API.
//
//   clhair devices                          list OpenCL devices and what clhair would use
//   clhair render SCENE -o OUT.png|.exr     render a scene, print per-stage times
//   clhair groom --preset NAME -o FILE      write a generated hair mesh
//   clhair export-strands GROOM -o F.hair   write the generated strands as cyHair
//
// Global options choose the device (--device, CLHAIR_DEVICE), force a sub-group backend
// (--subgroup, CLHAIR_SUBGROUP) or read kernels from a source tree (--kernel-dir,
// CLHAIR_KERNEL_DIR). Any failure prints one line "clhair: error: ..." and exits 1;
// output files are only written when the work completed.
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <CLI/CLI.hpp>

#include "cl/cl_error.h"
#include "clhair/device.h"
#include "clhair/error.h"
#include "clhair/hair_mesh.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "groom/presets.h"
#include "io/cyhair.h"

namespace {

using namespace clhair;

std::string mib(std::uint64_t bytes) { return std::to_string(bytes >> 20) + " MiB"; }

int cmdDevices(const DeviceOptions& opts) {
  std::vector<DeviceInfo> all = Device::list();
  if (all.empty()) {
    std::cout << "no OpenCL devices found (install an OpenCL driver, e.g. pocl-opencl-icd)\n";
    return 1;
  }
  for (const DeviceInfo& d : all) {
    std::cout << d.platformIndex << ":" << d.deviceIndex << "  " << d.name << "\n"
              << "    platform        " << d.platformName << "\n"
              << "    vendor          " << d.vendor << "\n"
              << "    OpenCL          " << d.version << " / " << d.clcVersion << "\n"
              << "    driver          " << d.driverVersion << "\n"
              << "    type            " << (d.isGpu ? "GPU" : "not GPU") << ", " << d.computeUnits << " compute units\n"
              << "    64-bit atomics  " << (d.int64Atomics ? "yes" : "no (clhair cannot use this device)") << "\n"
              << "    max allocation  " << mib(d.maxAlloc) << " of " << mib(d.globalMem) << "\n";
    std::string backend = "-";
    if (d.int64Atomics) {
      try {
        DeviceOptions o = opts;
        o.selector = std::to_string(d.platformIndex) + ":" + std::to_string(d.deviceIndex);
        Device dev = Device::open(o);
        backend = std::string(subgroupBackendName(dev.info().backend)) + " (" + dev.info().backendNote + ")";
      } catch (const Error& e) {
        std::string msg = e.what();
        backend = "unavailable: " + msg.substr(0, msg.find('\n'));
      }
    }
    std::string cands;
    for (SubgroupBackend b : d.candidates) cands += std::string(cands.empty() ? "" : ", ") + subgroupBackendName(b);
    std::cout << "    sub-group       " << backend << "; candidates: " << cands << "\n";
  }
  return 0;
}

struct RenderFlags {
  int width = 0, height = 0, msaa = 1;
  bool widthGiven = false, heightGiven = false;
  std::string camera, lod, dispatch = "auto";
  bool quiet = false;
};

int cmdRender(const DeviceOptions& opts, const std::string& scenePath, const std::string& out,
              const RenderFlags& f) {
  const int width = f.width, height = f.height;  // 0 = not given
  const std::string& camera = f.camera;
  const std::string& lod = f.lod;
  const bool quiet = f.quiet;
  Scene scene = loadScene(scenePath);
  if (f.widthGiven || f.heightGiven) {
    int w = f.widthGiven ? width : scene.width, h = f.heightGiven ? height : scene.height;
    if (w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide)
      throw Error("resolution " + std::to_string(w) + "x" + std::to_string(h) + " is outside 1.." +
                  std::to_string(kMaxImageSide) + " per side");
    scene.width = w;
    scene.height = h;
  }
  if (!camera.empty()) scene.camera = framePreset(scene, parseCameraPreset(camera), 0.0f, 10.0f, scene.camera.fovYDegrees);
  RenderOptions ro;
  if (lod == "on")
    ro.lod = 1;
  else if (lod == "off")
    ro.lod = 0;
  else if (!lod.empty() && lod != "auto")
    throw Error("--lod must be on, off or auto, not \"" + lod + "\"");
  if (f.msaa != 1 && f.msaa != 2 && f.msaa != 4 && f.msaa != 8)
    throw Error("--msaa must be 1, 2, 4 or 8, not " + std::to_string(f.msaa));
  ro.msaa = f.msaa;
  ro.dispatch = parseDispatchMode(f.dispatch);
  Device dev = Device::open(opts);
  Renderer renderer(dev);
  Frame frame = renderer.render(scene, ro);
  writeImage(frame.color, out);
  if (!quiet) {
    std::printf("%s: %dx%d on %s (sub-group %s), %llu strands\n", out.c_str(), scene.width, scene.height,
                dev.info().name.c_str(), subgroupBackendName(dev.info().backend),
                static_cast<unsigned long long>(frame.stats.strandsDrawn));
    for (const StageTime& t : frame.timings) std::printf("  %-10s %9.2f ms\n", t.stage.c_str(), t.ms);
    std::printf("  %-10s %9.2f ms\n", "total", frame.totalMs());
  }
  return 0;
}

int cmdGroom(const std::string& preset, const std::string& out, long long strands) {
  HairMesh m = makeGroomPreset(preset);
  if (strands >= 0) m.strandCount = strands;
  saveHairMesh(m, out);
  std::printf("%s: %s, %d bundles, %d layers, %lld strands\n", out.c_str(), m.name.c_str(),
              static_cast<int>(m.faces.size()), m.layerCount, static_cast<long long>(m.strandCount));
  return 0;
}

int cmdExport(const DeviceOptions& opts, const std::string& groomPath, const std::string& out) {
  HairMesh mesh = loadHairMesh(groomPath);
  Device dev = Device::open(opts);
  Renderer renderer(dev);
  StrandSet s = renderer.generateStrands(mesh);
  CyHair h;
  h.segments.reserve(s.pointCounts.size());
  for (std::uint32_t c : s.pointCounts) h.segments.push_back(c - 1);
  h.points = s.points;
  h.colors.reserve(s.points.size());
  for (float w : s.w) {
    glm::vec3 c = mesh.appearance.rootColor + (mesh.appearance.tipColor - mesh.appearance.rootColor) * w;
    h.colors.insert(h.colors.end(), {c.x, c.y, c.z});
  }
  h.defaultThickness = mesh.appearance.strandWidth;
  h.info = "clhair export-strands: " + mesh.name;
  writeCyHair(h, out);
  std::printf("%s: %zu strands, %zu points\n", out.c_str(), s.pointCounts.size(), s.points.size() / 3);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"clhair: real-time strand hair rendering on OpenCL"};
  app.require_subcommand(1);
  DeviceOptions opts;
  app.add_option("--device", opts.selector, "device: P:D indices or a name substring (env CLHAIR_DEVICE)");
  app.add_option("--subgroup", opts.subgroup, "force a sub-group backend: local, khr, intel, nvptx, amd (env CLHAIR_SUBGROUP)");
  app.add_option("--kernel-dir", opts.kernelDir, "read kernels from this source tree (env CLHAIR_KERNEL_DIR)");

  auto* devices = app.add_subcommand("devices", "list OpenCL devices and their capabilities");

  auto* render = app.add_subcommand("render", "render a scene to an image");
  std::string scenePath, out;
  RenderFlags rf;
  render->add_option("scene", scenePath, "scene JSON file")->required();
  render->add_option("-o,--output", out, "output image (.png, .exr, ...)")->required();
  render->add_option("--width", rf.width, "override the scene's width");
  render->add_option("--height", rf.height, "override the scene's height");
  render->add_option("--camera", rf.camera, "frame the grooms with a preset: close, mid, far");
  render->add_option("--lod", rf.lod, "LOD: on, off, or auto (as each groom says)");
  render->add_option("--msaa", rf.msaa, "software MSAA samples per pixel: 1, 2, 4, 8");
  render->add_option("--dispatch", rf.dispatch, "strand dispatch sizing: auto, readback, overlaunch, persistent");
  render->add_flag("-q,--quiet", rf.quiet, "print nothing on success");

  auto* groom = app.add_subcommand("groom", "write a generated hair mesh");
  std::string preset, groomOut;
  long long strands = -1;
  groom->add_option("--preset", preset, "long_wavy, curly_medium, fur_sphere or tiny")->required();
  groom->add_option("-o,--output", groomOut, "output hair-mesh file (.json)")->required();
  groom->add_option("--strands", strands, "override the strand count");

  auto* exportCmd = app.add_subcommand("export-strands", "write the generated strands as a cyHair .hair file");
  std::string groomPath, hairOut;
  exportCmd->add_option("groom", groomPath, "hair-mesh file")->required();
  exportCmd->add_option("-o,--output", hairOut, "output .hair file")->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  rf.widthGiven = render->count("--width") > 0;
  rf.heightGiven = render->count("--height") > 0;
  try {
    DeviceOptions resolved = DeviceOptions::fromEnvironment(opts);
    if (*devices) return cmdDevices(resolved);
    if (*render) return cmdRender(resolved, scenePath, out, rf);
    if (*groom) return cmdGroom(preset, groomOut, strands);
    if (*exportCmd) return cmdExport(resolved, groomPath, hairOut);
  } catch (const Error& e) {
    std::fprintf(stderr, "clhair: error: %s\n", e.what());
    return 1;
  } catch (const cl::Error& e) {
    std::fprintf(stderr, "clhair: error: OpenCL call %s failed with %s (%d)\n", e.what(), clErrorName(e.err()), e.err());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "clhair: error: %s\n", e.what());
    return 1;
  }
  return 1;
}
