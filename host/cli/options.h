// options.h — the option groups more than one place of the `clhair` command line shares,
// each defined once: the device (global: --device, --subgroup, --kernel-dir), the output
// (-o,--output, required, with the subcommand's own help), the camera (--width, --height,
// --camera) and the quality (--spp, --shadow-lod, --quality) with the check of its level.
// Each adds its options in the order `clhair ... --help` lists them.
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "clhair/device.h"
#include "clhair/scene.h"

namespace clhair::cli {

// --device, --subgroup and --kernel-dir on the whole command (the environment fills the rest:
// DeviceOptions::fromEnvironment).
void addDeviceOptions(CLI::App& app, DeviceOptions& opts);

// The required -o,--output of a subcommand that writes one file.
CLI::Option* addOutputOption(CLI::App* cmd, std::string& path, const std::string& help);

// --width and --height (0: the scene's) and --camera (a framing preset: close, mid, far).
void addCameraOptions(CLI::App* cmd, int& width, int& height, std::string& camera);

// --spp (samples of --reference, passes of --quality final), --shadow-lod and --quality.
void addQualityOptions(CLI::App* cmd, int& spp, std::string& shadowLod, std::string& quality,
                       std::string& shading);

// The table of rules every given value meets before any work (flag_rules.cpp): none empty,
// the numbers that size work within their documented range; throws the first failure.
void checkFlagRules(const CLI::App& app);

// --quality's value as RenderOptions::quality; nullopt when not given.
std::optional<Quality> parseQualityFlag(const std::string& v);

}  // namespace clhair::cli
