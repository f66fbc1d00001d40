// fit_bench.cpp — clhair_fit_bench: a hair mesh fitted to strands, measured by its renders.
//
//   clhair_fit_bench --groom assets/grooms/long_wavy.hairmesh.json --out DIR   round trip
//   clhair_fit_bench --strands outside.hair --out DIR                       strands from a file
//
// Round trip (--groom): the mesh's strands are generated on the device and written as a
// cyHair file with colours (what `clhair export-strands` writes), read back, and a mesh is
// fitted to them (`clhair fit-mesh`, with the original's appearance); --strands fits a
// strand file directly and compares with the file itself drawn as explicit strands. Both
// grooms are rendered in --scene (default assets/scenes/default.json) at --width x
// --height with the --camera preset, one camera computed from the original and used for
// both, the same lights. Reported (summary.json, also printed): the fit report, hair FLIP
// (mean FLIP over the pixels where either frame has hair, hair alpha >= 1/255), the hair
// mask IoU (hair alpha >= 0.5), whole-image FLIP, and the sizes. Images in --out:
// original.png, fitted.png, error.png (FLIP, magma) and side_by_side.png (the three cropped
// to the hair and scaled to --panel-height).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "clhair/error.h"
#include "clhair/fit.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "clhair/strand_groom.h"
#include "fit/fit_error.h"
#include "fit/fit_strands.h"
#include "io/cyhair.h"
#include "io/json_util.h"
#include "metrics/image_metrics.h"

namespace {

using namespace clhair;
using nlohmann::json;

struct Args {
  std::string groom, strands,
      scene = std::string(CLHAIR_SOURCE_DIR) + "/assets/scenes/default.json";
  std::string out = "fit-bench", camera = "close", appearance, floorKernels;
  bool reuse = false;
  std::string ao = "on";
  std::string drop;  // styling terms switched off after the fit (an experiment)
  int width = 1920, height = 1080, panelHeight = 480;
  FitOptions fit;
};

// The cyHair file export-strands writes for `mesh`.
void exportStrands(Renderer& r, const HairMesh& mesh, const std::string& path) {
  const StrandSet s = r.generateStrands(mesh);
  CyHair h;
  for (std::uint32_t c : s.pointCounts) h.segments.push_back(c - 1);
  h.points = s.points;
  for (float w : s.w) {
    const glm::vec3 c =
        mesh.appearance.rootColor + (mesh.appearance.tipColor - mesh.appearance.rootColor) * w;
    h.colors.insert(h.colors.end(), {c.x, c.y, c.z});
  }
  h.defaultThickness = mesh.appearance.strandWidth;
  h.info = "clhair export-strands: " + mesh.name;
  writeCyHair(h, path);
}

// Distances from the strands of `from` to the nearest strand of `to` (fit_error.h).
std::vector<float> fitDistances(const StrandGroom& from, const StrandGroom& to, std::size_t sample,
                                int threads) {
  const fit::FitStrands in = fit::prepareFitStrands(from, kFitSamples, 0.0f, threads);
  fit::GeneratedStrands g;
  g.points = static_cast<int>(to.pointCounts[0]);
  g.data = to.points;
  g.bundle.assign(to.pointCounts.size(), 0);
  std::vector<std::size_t> measured;
  const std::size_t every = sample > 0 && sample < in.count() ? in.count() / sample : 1;
  for (std::size_t i = 0; i < in.count(); i += every) measured.push_back(i);
  return fit::strandDistances(in, measured, g, threads);
}

Image crop(const Image& im, int x0, int y0, int w, int h) {
  Image o;
  o.width = w;
  o.height = h;
  o.rgba.resize(static_cast<std::size_t>(w) * h * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) std::copy_n(im.pixel(x0 + x, y0 + y), 4, o.pixel(x, y));
  return o;
}

// Box-filtered resize to height `h`.
Image scaleTo(const Image& im, int h) {
  const double f = static_cast<double>(im.height) / h;
  Image o;
  o.height = h;
  o.width = std::max(1, static_cast<int>(im.width / f + 0.5));
  o.rgba.assign(static_cast<std::size_t>(o.width) * o.height * 4, 0.0f);
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      const int sx0 = static_cast<int>(x * f),
                sx1 = std::max(sx0 + 1, static_cast<int>((x + 1) * f));
      const int sy0 = static_cast<int>(y * f),
                sy1 = std::max(sy0 + 1, static_cast<int>((y + 1) * f));
      float acc[4] = {0, 0, 0, 0};
      int n = 0;
      for (int sy = sy0; sy < std::min(sy1, im.height); ++sy)
        for (int sx = sx0; sx < std::min(sx1, im.width); ++sx) {
          for (int c = 0; c < 4; ++c) acc[c] += im.pixel(sx, sy)[c];
          ++n;
        }
      for (int c = 0; c < 4; ++c) o.pixel(x, y)[c] = n > 0 ? acc[c] / n : 0.0f;
    }
  return o;
}

Image sideBySide(const std::vector<Image>& panels) {
  Image o;
  o.height = panels[0].height;
  for (const Image& p : panels) o.width += p.width;
  o.rgba.assign(static_cast<std::size_t>(o.width) * o.height * 4, 1.0f);
  int at = 0;
  for (const Image& p : panels) {
    for (int y = 0; y < p.height; ++y)
      for (int x = 0; x < p.width; ++x) std::copy_n(p.pixel(x, y), 4, o.pixel(at + x, y));
    at += p.width;
  }
  return o;
}

int run(const Args& a) {
  const bool roundTrip = !a.groom.empty();
  if (roundTrip == !a.strands.empty())
    throw clhair::Error("give exactly one of --groom and --strands");
  std::filesystem::create_directories(a.out);
  Device dev = Device::open(DeviceOptions::fromEnvironment({}));
  Renderer renderer(dev);
  Scene scene = loadScene(a.scene, dev.info().maxAlloc);
  const GroomInstance sceneGroom = scene.grooms.empty() ? GroomInstance() : scene.grooms[0];

  // the original groom and the strand file the fit reads
  std::shared_ptr<HairMesh> original;
  std::string strandPath = a.strands;
  if (roundTrip) {
    original = std::make_shared<HairMesh>(loadHairMesh(a.groom));
    strandPath = a.out + "/strands.hair";
    if (!(a.reuse && std::filesystem::exists(strandPath)))
      exportStrands(renderer, *original, strandPath);
  }
  auto strands = std::make_shared<StrandGroom>(loadStrandGroom(strandPath, dev.info().maxAlloc));
  HairMesh look;
  if (!a.appearance.empty()) look = loadHairMesh(a.appearance);
  if (!a.appearance.empty()) strands->appearance = look.appearance;

  auto stamp = [t0 = std::chrono::steady_clock::now()](const char* what) {
    std::fprintf(stderr, "clhair_fit_bench: %s at %.1f s\n", what,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  };
  stamp("strands read");
  FitResult fit = fitHairMesh(*strands, a.fit);
  stamp("fitted");
  if (roundTrip)
    fit.mesh.appearance = original->appearance;
  else
    fit.mesh.appearance = strands->appearance;
  StyleParams& st = fit.mesh.style;
  if (a.drop.find("curl") != std::string::npos) st.curlAmplitude = 0.0f;
  if (a.drop.find("clump") != std::string::npos) st.clumpStrength = 0.0f;
  if (a.drop.find("frizz") != std::string::npos) st.frizzAmplitude = 0.0f;
  if (a.drop.find("flyaway") != std::string::npos) st.flyawayFraction = 0.0f;
  if (a.drop.find("length") != std::string::npos) st.lengthVariation = 0.0f;
  const std::string meshPath = a.out + "/fitted.hairmesh.json";
  saveHairMesh(fit.mesh, meshPath);
  fit.report.strandFileBytes = std::filesystem::file_size(strandPath);
  fit.report.meshFileBytes = std::filesystem::file_size(meshPath);
  writeFitReport(fit.report, a.out + "/report.json");

  // renders: one camera for both, from the original
  Scene s0 = scene;
  s0.width = a.width;
  s0.height = a.height;
  s0.grooms.clear();
  if (roundTrip)
    s0.grooms.push_back(
        GroomInstance("original", std::shared_ptr<const HairMesh>(original), sceneGroom.transform));
  else
    s0.grooms.push_back(GroomInstance("original", std::shared_ptr<const StrandGroom>(strands)));
  s0.camera = reframeCamera(s0, parseCameraPreset(a.camera));
  Scene s1 = s0;
  s1.grooms[0] = GroomInstance("fitted", std::make_shared<const HairMesh>(fit.mesh),
                               roundTrip ? sceneGroom.transform : glm::mat4(1.0f));
  RenderOptions ro;
  ro.aovs = true;
  ro.ambientOcclusion = a.ao != "off";
  Frame f0;
  const std::string cache = a.out + "/original_ao" + a.ao + ".exr";
  const std::string alphaCache = a.out + "/original_ao" + a.ao + "_alpha.raw";
  if (a.reuse && std::filesystem::exists(cache) && std::filesystem::exists(alphaCache)) {
    f0.color = readImage(cache);
    f0.aovs.hairAlpha.resize(static_cast<std::size_t>(a.width) * a.height);
    std::FILE* in = std::fopen(alphaCache.c_str(), "rb");
    const std::size_t got =
        in ? std::fread(f0.aovs.hairAlpha.data(), sizeof(float), f0.aovs.hairAlpha.size(), in) : 0;
    if (in) std::fclose(in);
    if (got != f0.aovs.hairAlpha.size()) throw clhair::Error("cannot read " + alphaCache);
  } else {
    f0 = renderer.render(s0, ro);
    writeImage(f0.color, cache);
    std::FILE* o = std::fopen(alphaCache.c_str(), "wb");
    if (o) {
      std::fwrite(f0.aovs.hairAlpha.data(), sizeof(float), f0.aovs.hairAlpha.size(), o);
      std::fclose(o);
    }
  }
  renderer.releaseGrooms();
  stamp("original rendered");
  const Frame f1 = renderer.render(s1, ro);
  stamp("fitted rendered");
  const ImageComparison cmp = compareImages(f0.color, f1.color);
  std::size_t hair = 0, inter = 0, uni = 0;
  double flipSum = 0.0;
  int x0 = a.width, y0 = a.height, x1 = 0, y1 = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * a.width + x;
      const float h0 = f0.aovs.hairAlpha[i], h1 = f1.aovs.hairAlpha[i];
      if (h0 >= 1.0f / 255.0f || h1 >= 1.0f / 255.0f) {
        ++hair;
        flipSum += cmp.flip.error[i];
        x0 = std::min(x0, x);
        y0 = std::min(y0, y);
        x1 = std::max(x1, x);
        y1 = std::max(y1, y);
      }
      const bool m0 = h0 >= 0.5f, m1 = h1 >= 0.5f;
      inter += m0 && m1;
      uni += m0 || m1;
    }
  const double hairFlip = hair > 0 ? flipSum / static_cast<double>(hair) : 0.0;
  const double iou = uni > 0 ? static_cast<double>(inter) / static_cast<double>(uni) : 1.0;
  writeImage(f0.color, a.out + "/original.png");
  writeImage(f1.color, a.out + "/fitted.png");
  const Image err = flipErrorImage(cmp.flip, true);
  writeImage(err, a.out + "/error.png");
  if (hair > 0) {
    const int m = 16;
    x0 = std::max(0, x0 - m);
    y0 = std::max(0, y0 - m);
    x1 = std::min(a.width - 1, x1 + m);
    y1 = std::min(a.height - 1, y1 + m);
    const int w = x1 - x0 + 1, h = y1 - y0 + 1;
    const int ph = std::min(a.panelHeight, h);
    writeImage(sideBySide({scaleTo(crop(f0.color, x0, y0, w, h), ph),
                           scaleTo(crop(f1.color, x0, y0, w, h), ph),
                           scaleTo(crop(err, x0, y0, w, h), ph)}),
               a.out + "/side_by_side.png");
  }
  // the floor: the original again with the strand kernels' per-strand random key changed
  // (kernels from --floor-kernels), same roots and clumps: what no fit can get below
  json floor;
  if (!a.floorKernels.empty() && roundTrip) {
    DeviceOptions fo = DeviceOptions::fromEnvironment({});
    fo.kernelDir = a.floorKernels;
    fo.cacheDir = "off";
    Device fdev = Device::open(fo);
    Renderer fr(fdev);
    const Frame ff = fr.render(s0, ro);
    const ImageComparison fc = compareImages(f0.color, ff.color);
    std::size_t fh = 0, fi = 0, fu = 0;
    double fs = 0.0;
    for (std::size_t i = 0; i < ff.aovs.hairAlpha.size(); ++i) {
      const float h0 = f0.aovs.hairAlpha[i], h1 = ff.aovs.hairAlpha[i];
      if (h0 >= 1.0f / 255.0f || h1 >= 1.0f / 255.0f) {
        ++fh;
        fs += fc.flip.error[i];
      }
      fi += h0 >= 0.5f && h1 >= 0.5f;
      fu += h0 >= 0.5f || h1 >= 0.5f;
    }
    writeImage(ff.color, a.out + "/floor.png");
    const std::string floorStrands = a.out + "/floor_strands.hair";
    exportStrands(fr, *original, floorStrands);
    const StrandGroom alt = loadStrandGroom(floorStrands, dev.info().maxAlloc);
    const std::vector<float> d = fitDistances(*strands, alt, a.fit.errorSample, a.fit.threads);
    double mean = 0.0;
    for (float v : d) mean += v;
    mean /= std::max<std::size_t>(d.size(), 1);
    floor = {{"hair_flip", fh > 0 ? fs / static_cast<double>(fh) : 0.0},
             {"mask_iou", fu > 0 ? static_cast<double>(fi) / static_cast<double>(fu) : 1.0},
             {"distance_mean_fibre_widths", mean / strands->appearance.strandWidth}};
  }
  const FitReport& r = fit.report;
  json j = {{"input", roundTrip ? a.groom : a.strands},
            {"resolution", {a.width, a.height}},
            {"camera", a.camera},
            {"hair_flip", hairFlip},
            {"hair_pixels", hair},
            {"mask_iou", iou},
            {"image_flip", cmp.flip.mean},
            {"fit_seconds", r.seconds},
            {"threads", a.fit.threads},
            {"bundles", r.bundles},
            {"layers", r.layers},
            {"vertices", r.vertices},
            {"strand_file_bytes", r.strandFileBytes},
            {"mesh_file_bytes", r.meshFileBytes},
            {"mesh_over_strand_file_percent",
             100.0 * static_cast<double>(r.meshFileBytes) / static_cast<double>(r.strandFileBytes)},
            {"distance_mean_fibre_widths", r.error.meanWidths},
            {"distance_p95_fibre_widths", r.error.p95Widths},
            {"distance_mean_m", r.error.meanM},
            {"distance_p95_m", r.error.p95M}};
  if (!floor.is_null()) j["floor"] = floor;
  writeTextAtomically(a.out + "/summary.json", j.dump(2) + "\n");
  std::printf("%s\n", j.dump(2).c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"clhair_fit_bench: a hair mesh fitted to strands, measured by its renders"};
  Args a;
  app.add_option("--groom", a.groom, "round trip of this hair mesh");
  app.add_option("--strands", a.strands, "fit this strand file (compared with itself drawn)");
  app.add_option("--scene", a.scene, "scene whose camera direction, lights and head are used");
  app.add_option("--appearance", a.appearance, "--strands: appearance from this hair mesh");
  app.add_option("--out", a.out, "output folder");
  app.add_option("--camera", a.camera, "close, mid or far");
  app.add_option("--ao", a.ao, "baked ambient occlusion in both renders: on (default) or off");
  app.add_option("--width", a.width);
  app.add_option("--height", a.height);
  app.add_option("--panel-height", a.panelHeight, "height of side_by_side.png's panels");
  app.add_option("--bundles", a.fit.bundles);
  app.add_option("--layers", a.fit.layers);
  app.add_option("--shape-weight", a.fit.shapeWeight);
  app.add_option("--shape-scale", a.fit.shapeScale);
  app.add_option("--threads", a.fit.threads, "fitting threads (0: all cores)");
  app.add_option("--error-sample", a.fit.errorSample);
  app.add_option("--drop", a.drop,
                 "styling terms to switch off after the fit, to see what each adds: any of "
                 "curl,clump,frizz,flyaway,length");
  app.add_option("--floor-kernels", a.floorKernels,
                 "--groom: also render the original with the kernels of this source tree (the "
                 "per-strand random key changed there) and report it as the floor");
  app.add_flag("--reuse", a.reuse, "reuse the strand file and the original's render in --out");
  CLI11_PARSE(app, argc, argv);
  try {
    return run(a);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "clhair_fit_bench: error: %s\n", e.what());
    return 1;
  }
}
