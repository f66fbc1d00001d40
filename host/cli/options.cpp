// options.cpp — the shared option groups of the `clhair` command line (options.h): their
// names, help texts and defaults in one place, and the check of --quality's value.
#include "options.h"

#include "clhair/error.h"
#include "clhair/progressive.h"

namespace clhair::cli {

void addDeviceOptions(CLI::App& app, DeviceOptions& opts) {
  app.add_option("--device", opts.selector,
                 "device: P:D indices or a name substring (env CLHAIR_DEVICE)");
  app.add_option(
      "--subgroup", opts.subgroup,
      "force a sub-group backend: single, local, khr, intel, nvptx, amd (env CLHAIR_SUBGROUP)");
  app.add_option("--kernel-dir", opts.kernelDir,
                 "read kernels from this source tree (env CLHAIR_KERNEL_DIR)");
}

CLI::Option* addOutputOption(CLI::App* cmd, std::string& path, const std::string& help) {
  return cmd->add_option("-o,--output", path, help)->required();
}

void addCameraOptions(CLI::App* cmd, int& width, int& height, std::string& camera) {
  cmd->add_option("--width", width, "override the scene's width");
  cmd->add_option("--height", height, "override the scene's height");
  cmd->add_option("--camera", camera, "frame the grooms with a preset: close, mid, far");
}

void addQualityOptions(CLI::App* cmd, int& spp, std::string& shadowLod, std::string& quality,
                       std::string& shading) {
  cmd->add_option("--spp", spp,
                  "samples per pixel of --reference (default 256), or jittered passes of "
                  "--quality final (default " +
                      std::to_string(kDefaultFinalPasses) + ")");
  cmd->add_option("--shadow-lod", shadowLod,
                  "LOD of the lights' passes: camera (default: the light's view, no more "
                  "strands than the camera's LOD draws), light (the light's view alone) or "
                  "off (every strand)");
  cmd->add_option("--quality", quality,
                  "draft (one sample per pixel, the scene's filter), good (" +
                      std::to_string(kGoodMsaa) +
                      " samples per pixel, no filter) or final (--spp jittered passes of one "
                      "sample accumulated); default: the scene's \"quality\", draft");
  cmd->add_option("--shading", shading,
                  "with more than one sample per pixel: sample (shade every sample; good's "
                  "default) or point (shade once per visible strand point and interpolate "
                  "along the segment)");
}

std::optional<Quality> parseQualityFlag(const std::string& v) {
  if (v.empty()) return std::nullopt;
  if (v == "draft") return Quality::Draft;
  if (v == "good") return Quality::Good;
  if (v == "final") return Quality::Final;
  throw Error("--quality must be draft, good or final, not \"" + v + "\"");
}

}  // namespace clhair::cli
