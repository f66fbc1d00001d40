// compare.cpp — `clhair compare`: image B against reference A, PSNR and RMSE on sRGB display
// values, mean LDR-FLIP and the share within one 8-bit code, as text or JSON; optionally the
// FLIP error map.
#include <cmath>
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "clhair/error.h"
#include "commands.h"
#include "io/json_util.h"
#include "options.h"
#include "outputs.h"

namespace clhair::cli {

namespace {

std::string shortNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", v);
  return buf;
}

}  // namespace

CLI::App* addCompareCommand(CLI::App& app, CompareFlags& cf) {
  CLI::App* compare =
      app.add_subcommand("compare", "compare image B against reference A: PSNR, RMSE, mean FLIP");
  compare->add_option("reference", cf.reference, "reference image")->required();
  compare->add_option("test", cf.test, "test image (same size)")->required();
  compare->add_option("--error-map", cf.errorMap,
                      "write the FLIP error map (.png: magma colours, .exr: raw values)");
  compare->add_option("--ppd", cf.ppd, "FLIP pixels per degree of visual angle (default 67)");
  compare->add_flag("--json", cf.json, "print the results as JSON");
  return compare;
}

// PSNR and RMSE on sRGB display values, mean LDR-FLIP, and optionally the FLIP error map:
// magma colours for 8-bit formats, raw error values for float formats (.exr, .hdr).
int cmdCompare(const std::string& pathA, const std::string& pathB, const CompareFlags& f) {
  if (!(f.ppd >= kFlipMinPpd && f.ppd <= kFlipMaxPpd))
    throw Error("--ppd " + shortNumber(f.ppd) + " is outside " + shortNumber(kFlipMinPpd) + ".." +
                shortNumber(kFlipMaxPpd) + " (FLIP's default viewing setup is 67)");
  if (!f.errorMap.empty()) {  // before the work
    checkImageOutput(f.errorMap);
    checkNotAnInput("--error-map", f.errorMap,
                    {{"the reference image", pathA}, {"the test image", pathB}});
  }
  Image a = readImage(pathA);
  Image b = readImage(pathB);
  requireSameSize(a, b, pathA, pathB);
  ImageComparison c = compareImages(a, b, f.ppd);
  if (!f.errorMap.empty()) {
    const std::string ext = lowerExtension(f.errorMap);
    const bool raw = ext == ".exr" || ext == ".hdr";
    writeImage(flipErrorImage(c.flip, !raw), f.errorMap);
  }
  const bool identical = std::isinf(c.psnr.psnrDb);
  if (f.json) {
    // JSON has no infinity: identical images report "psnr_db": null.
    nlohmann::json j = {{"reference", pathA},
                        {"test", pathB},
                        {"width", a.width},
                        {"height", a.height},
                        {"psnr_db", nullptr},
                        {"rmse", c.psnr.rmse},
                        {"mse", c.psnr.mse},
                        {"flip_mean", c.flip.mean},
                        {"ppd", f.ppd},
                        {"error_map", nullptr},
                        {"within_one_code", c.withinOneCode}};
    if (!identical) j["psnr_db"] = c.psnr.psnrDb;
    if (!f.errorMap.empty()) j["error_map"] = f.errorMap;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::printf("%s vs %s: %dx%d\n", pathA.c_str(), pathB.c_str(), a.width, a.height);
  if (identical)
    std::printf("  PSNR  inf dB      (identical in sRGB)\n");
  else
    std::printf("  PSNR  %.4f dB   (sRGB R, G, B; peak 1)\n", c.psnr.psnrDb);
  std::printf("  RMSE  %.6f     (sRGB R, G, B in [0, 1])\n", c.psnr.rmse);
  std::printf("  FLIP  %.6f     (mean LDR-FLIP, %g pixels per degree)\n", c.flip.mean, f.ppd);
  std::printf("  within 1/255  %.4f %% of pixels (largest sRGB channel difference)\n",
              100.0 * c.withinOneCode);
  if (!f.errorMap.empty()) std::printf("  error map  %s\n", f.errorMap.c_str());
  return 0;
}

}  // namespace clhair::cli
