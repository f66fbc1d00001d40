// scene_render.cpp — a scene's render settings: "resolution", "filter" (also a groom's
// own), "quality", "raster" and "temporal" (docs/scene-format.md).
//
// Each reads over the defaults already in the Scene (or the FilterParams given), so a key
// left out keeps its default.
#include <string>

#include "clhair/error.h"
#include "clhair/temporal.h"
#include "io/enum_field.h"
#include "io/scene_sections.h"

namespace clhair::scene_io {

using nlohmann::json;

namespace {

constexpr EnumName<Quality> kQualities[] = {
    {"draft", Quality::Draft}, {"good", Quality::Good}, {"final", Quality::Final}};
constexpr EnumName<FilterParams::Method> kFilterMethods[] = {
    {"auto", FilterParams::Method::Auto},
    {"lipp", FilterParams::Method::Lipp},
    {"huang", FilterParams::Method::Huang}};
constexpr EnumName<RasterMode> kRasterModes[] = {{"lines", RasterMode::Lines},
                                                 {"coverage", RasterMode::Coverage}};

}  // namespace

QualityParams readQuality(const JsonReader& r) {
  QualityParams q;
  const json& v = r.require("quality");
  if (v.is_string()) {
    q.level = readEnum(r, "quality", v.get<std::string>(), kQualities, EnumWording::MustBe);
    return q;
  }
  JsonReader o = r.object(v, "quality");
  q.level = readEnum(o, "level", o.string("level", "draft"), kQualities, EnumWording::MustBe);
  q.spp = o.integer("spp", 0, 1, kMaxFinalPasses);
  o.rejectUnknown({"level", "spp"});
  return q;
}

FilterParams readFilter(const JsonReader& parent, const json& j, FilterParams f) {
  JsonReader o = parent.object(j, "filter");
  f.enabled = o.boolean("enabled", f.enabled);
  f.radius = o.integer("radius", f.radius, 0, 8);
  f.sPar = static_cast<float>(o.number("s_parallel", f.sPar, 1e-3, 10.0));
  f.sPerp = static_cast<float>(o.number("s_perp", f.sPerp, 1e-3, 10.0));
  f.sigmaC = static_cast<float>(o.number("sigma_c", f.sigmaC, 1e-3, 100.0));
  f.depthReject = static_cast<float>(o.number("depth_reject", f.depthReject, 0.0, 10.0));
  f.depthMismatch = static_cast<float>(o.number("depth_mismatch", f.depthMismatch, 0.0, 10.0));
  f.strip = static_cast<float>(o.number("strip", f.strip, 0.0, 8.0));
  f.promote = o.boolean("promote", f.promote);
  if (o.has("method"))
    f.method =
        readEnum(o, "method", o.string("method", "auto"), kFilterMethods, EnumWording::MustBe);
  f.link = o.boolean("link", f.link);
  f.linkThreshold = static_cast<float>(o.number("link_threshold", f.linkThreshold, 0.0, 1.0));
  f.linkSigma = static_cast<float>(o.number("link_sigma", f.linkSigma, 0.1, 10.0));
  f.linkMaxSteps = o.integer("link_max_steps", f.linkMaxSteps, 1, 4096);
  f.alphaFix = o.boolean("alpha_fix", f.alphaFix);
  f.linkTable = o.integer("link_table", f.linkTable, 0, 1 << 26);
  f.aniso = o.boolean("aniso", f.aniso);
  f.sigmaD = static_cast<float>(o.number("sigma_d", f.sigmaD, 1e-3, 10.0));
  f.sigmaTheta = static_cast<float>(o.number("sigma_theta", f.sigmaTheta, 1e-3, 10.0));
  f.sigmaCAniso = static_cast<float>(o.number("sigma_c_aniso", f.sigmaCAniso, 1e-3, 100.0));
  f.kernelK = static_cast<float>(o.number("kernel_k", f.kernelK, 0.0, 1.0));
  o.rejectUnknown(
      {"enabled",        "radius",         "s_parallel", "s_perp",     "sigma_c", "depth_reject",
       "depth_mismatch", "strip",          "promote",    "method",     "link",    "link_threshold",
       "link_sigma",     "link_max_steps", "alpha_fix",  "link_table", "aniso",   "sigma_d",
       "sigma_theta",    "sigma_c_aniso",  "kernel_k"});
  return f;
}

void readResolution(const JsonReader& r, Scene& s) {
  if (!r.has("resolution")) return;
  const json& res = r.require("resolution");
  if (!res.is_array() || res.size() != 2 || !res[0].is_number_integer() ||
      !res[1].is_number_integer())
    r.fail("resolution", "must be [width, height] in pixels");
  long long w = res[0].get<long long>(), h = res[1].get<long long>();
  if (w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide)
    r.fail("resolution", std::to_string(w) + "x" + std::to_string(h) + " is outside 1.." +
                             std::to_string(kMaxImageSide) + " per side");
  s.width = static_cast<int>(w);
  s.height = static_cast<int>(h);
}

void readRaster(const JsonReader& r, Scene& s) {
  if (!r.has("raster")) return;
  s.raster = readEnum(r, "raster", r.string("raster", "lines"), kRasterModes, EnumWording::MustBe);
}

void readTemporal(const JsonReader& r, Scene& s) {  // clhair/temporal.h, off by default
  if (!r.has("temporal")) return;
  JsonReader o = r.object(r.require("temporal"), "temporal");
  TemporalParams& tp = s.temporal;
  tp.history = o.integer("history", tp.history, 0, kMaxTemporalHistory);
  tp.blend = static_cast<float>(o.number("blend", tp.blend, 1e-3, 1.0));
  tp.depthTolerance =
      static_cast<float>(o.number("depth_tolerance", tp.depthTolerance, 1e-4, 10.0));
  o.rejectUnknown({"history", "blend", "depth_tolerance"});
}

}  // namespace clhair::scene_io
