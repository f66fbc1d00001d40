// fit_report_io.cpp — the fit report as JSON (docs/fitting.md, "The report"): the overall
// error, counts, lengths, sizes, times and fitted styling, then one entry per bundle.
// Numbers are rounded to 6 significant digits so reports stay readable and diffable.
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <nlohmann/json.hpp>

#include "clhair/fit.h"
#include "io/json_util.h"

namespace clhair {

namespace {

using nlohmann::json;

double tidy(double v) {
  if (!std::isfinite(v)) return 0.0;
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return std::strtod(buf, nullptr);
}

json distanceJson(const FitDistance& d) {
  return {{"strands", d.strands},
          {"mean_m", tidy(d.meanM)},
          {"p95_m", tidy(d.p95M)},
          {"mean_fibre_widths", tidy(d.meanWidths)},
          {"p95_fibre_widths", tidy(d.p95Widths)}};
}

json lengthJson(const LengthStats& l) {
  return {{"strands", l.strands}, {"mean_m", tidy(l.mean)},     {"min_m", tidy(l.min)},
          {"p05_m", tidy(l.p05)}, {"median_m", tidy(l.median)}, {"p95_m", tidy(l.p95)},
          {"max_m", tidy(l.max)}};
}

json styleJson(const FittedStyle& s) {
  return {{"curl_amplitude", tidy(s.curlAmplitude)},
          {"curl_frequency", tidy(s.curlFrequency)},
          {"curl_helix", tidy(s.curlHelix)},
          {"curl_phase_jitter", tidy(s.curlPhaseJitter)},
          {"clump_strength", tidy(s.clumpStrength)},
          {"clump_frequency", tidy(s.clumpFrequency)},
          {"clump_shape", tidy(s.clumpShape)},
          {"frizz_amplitude", tidy(s.frizzAmplitude)},
          {"frizz_frequency", tidy(s.frizzFrequency)},
          {"flyaway_fraction", tidy(s.flyawayFraction)},
          {"flyaway_amplitude", tidy(s.flyawayAmplitude)},
          {"length_variation", tidy(s.lengthVariation)}};
}

}  // namespace

std::string fitReportJson(const FitReport& r) {
  json j;
  j["input"] = r.input;
  j["fibre_width_m"] = tidy(r.fibreWidth);
  j["bundles"] = r.bundles;
  j["layers"] = r.layers;
  j["vertices"] = r.vertices;
  j["error"] = distanceJson(r.error);
  j["strands"] = {{"in", r.strandsIn}, {"out", r.strandsOut}};
  j["length"] = {{"in", lengthJson(r.lengthIn)}, {"out", lengthJson(r.lengthOut)}};
  json size = {{"strand_bytes_in_memory", r.strandBytes}};
  if (r.strandFileBytes > 0) size["strand_file_bytes"] = r.strandFileBytes;
  if (r.meshFileBytes > 0) {
    size["mesh_file_bytes"] = r.meshFileBytes;
    if (r.strandFileBytes > 0)
      size["mesh_over_strand_file_percent"] = tidy(100.0 * static_cast<double>(r.meshFileBytes) /
                                                   static_cast<double>(r.strandFileBytes));
  }
  j["size"] = size;
  json t = json::object();
  for (const auto& p : r.timings) t[p.first] = tidy(p.second);
  j["time_s"] = {{"total", tidy(r.seconds)}, {"phases", t}};
  j["style"] = styleJson(r.fitted);
  j["notes"] = r.notes;
  json bundles = json::array();
  for (const FitBundleReport& b : r.perBundle)
    bundles.push_back({{"strands_in", b.strandsIn},
                       {"strands_out", b.strandsOut},
                       {"width_m", tidy(b.width)},
                       {"root_density_in_per_m2", tidy(b.rootDensityIn)},
                       {"root_density_out_per_m2", tidy(b.rootDensityOut)},
                       {"error", distanceJson(b.error)},
                       {"style", styleJson(b.style)}});
  j["per_bundle"] = bundles;
  return j.dump(1) + "\n";
}

void writeFitReport(const FitReport& report, const std::string& path) {
  writeTextAtomically(path, fitReportJson(report));
}

}  // namespace clhair
