// scene_io.cpp — the JSON scene format (docs/scene-format.md) and camera presets.
//
// A groom entry names a hair mesh ("file") or a strand file ("strands_file": cyHair .hair
// or USC-HairSalon .data, read with a byte limit before anything is allocated); each file
// is read once per scene however many entries use it. A mesh entry names an OBJ file (a
// head), read and checked the same way: once per file, against the device's largest
// allocation, every error one line naming the scene and the file as the entry wrote it.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vector_relational.hpp>

#include "clhair/animation.h"
#include "clhair/error.h"
#include "clhair/gpu_types.h"
#include "clhair/scene.h"
#include "io/appearance_io.h"
#include "io/json_util.h"

namespace clhair {

namespace {

using nlohmann::json;

constexpr double kBig = 1e6;

// The scene's "quality": a level name, or {"level": name, "spp": passes of final}.
QualityParams readQuality(const JsonReader& r) {
  QualityParams q;
  const json& v = r.require("quality");
  auto level = [&](const std::string& name, const JsonReader& at, const char* key) {
    if (name == "draft") return Quality::Draft;
    if (name == "good") return Quality::Good;
    if (name == "final") return Quality::Final;
    at.fail(key, "must be \"draft\", \"good\" or \"final\", not \"" + name + "\"");
  };
  if (v.is_string()) {
    q.level = level(v.get<std::string>(), r, "quality");
    return q;
  }
  JsonReader o = r.object(v, "quality");
  q.level = level(o.string("level", "draft"), o, "level");
  q.spp = o.integer("spp", 0, 1, kMaxFinalPasses);
  o.rejectUnknown({"level", "spp"});
  return q;
}

std::string showNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", v);
  return buf;
}

// One keyed property: `width` numbers (1 or 3) within lo..hi.
struct KeyField {
  const char* name;
  int width;
  double lo, hi;
};

// The "keys" array and "interpolation" of the object `o`: every key holds "frame" (strictly
// increasing) and any of `fields`; a field a key leaves out takes its value from `defaults`
// (the object's still values, field by field in order).
KeyTrack readKeys(const JsonReader& o, const std::vector<KeyField>& fields,
                  const std::vector<double>& defaults) {
  KeyTrack t;
  for (const KeyField& f : fields) t.width += f.width;
  const std::string interp = o.string("interpolation", "linear");
  if (interp == "linear")
    t.interpolation = Interpolation::Linear;
  else if (interp == "smooth")
    t.interpolation = Interpolation::Smooth;
  else
    o.fail("interpolation", "is \"" + interp + "\", expected \"linear\" or \"smooth\"");
  const json& a = o.require("keys");
  if (!a.is_array() || a.empty())
    o.fail("keys", "must be a non-empty array of key objects ({\"frame\": 1, ...})");
  if (a.size() > 100000)
    o.fail("keys", "holds " + std::to_string(a.size()) + " keys, at most 100000 are supported");
  std::vector<std::string> known{"frame"};
  for (const KeyField& f : fields) known.push_back(f.name);
  for (std::size_t i = 0; i < a.size(); ++i) {
    JsonReader k = o.object(a[i], "keys[" + std::to_string(i) + "]");
    k.require("frame");
    const double frame = k.number("frame", 0.0, -1e7, 1e7);
    if (!t.frames.empty() && !(frame > t.frames.back()))
      k.fail("frame", "is " + showNumber(frame) + ", not after the previous key's " +
                          showNumber(t.frames.back()) + ": keys must be in increasing frame order");
    t.frames.push_back(frame);
    std::size_t at = 0;
    for (const KeyField& f : fields) {
      if (f.width == 3) {
        const glm::vec3 def(static_cast<float>(defaults[at]), static_cast<float>(defaults[at + 1]),
                            static_cast<float>(defaults[at + 2]));
        const glm::vec3 v = k.vec3(f.name, def, f.lo, f.hi);
        t.values.insert(t.values.end(), {v.x, v.y, v.z});
      } else {
        t.values.push_back(k.number(f.name, defaults[at], f.lo, f.hi));
      }
      at += static_cast<std::size_t>(f.width);
    }
    k.rejectUnknown(known);
  }
  return t;
}

// A "transform" object: translate / rotate_y / scale or a row-major matrix. With `keys`
// (grooms), "keys" and "interpolation" animate translate, rotate_y and scale.
glm::mat4 readTransform(const JsonReader& parent, const json& j, KeyTrack* keys = nullptr) {
  JsonReader t = parent.object(j, "transform");
  glm::mat4 m(1.0f);
  if (t.has("matrix")) {
    if (keys && t.has("keys"))
      t.fail("keys", "animate translate, rotate_y and scale: give those instead of \"matrix\"");
    const json& a = t.require("matrix");
    if (!a.is_array() || a.size() != 16) t.fail("matrix", "must be 16 numbers, row-major");
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) {
        if (!a[r * 4 + c].is_number()) t.fail("matrix", "must be 16 numbers, row-major");
        double d = a[r * 4 + c].get<double>();
        if (!std::isfinite(d) || std::fabs(d) > 3.0e38)
          t.fail("matrix", "holds a non-finite number or one beyond float range");
        m[c][r] = static_cast<float>(d);
      }
    // a singular matrix flattens what it places to a plane, a line or a point, which then
    // draws nothing (the smallest "scale" allowed, 1e-6 on every axis, has a determinant of 1e-18)
    const double det = glm::determinant(glm::dmat3(glm::mat3(m)));
    if (!(std::fabs(det) >= 1e-18))
      t.fail("matrix", "is degenerate: its 3x3 part has determinant " + showNumber(det) +
                           ", so it flattens everything it places (expected at least 1e-18 in "
                           "magnitude)");
    t.rejectUnknown({"matrix"});
    return m;
  }
  glm::vec3 translate = t.vec3("translate", glm::vec3(0.0f), -kBig, kBig);
  float rotateY = static_cast<float>(t.number("rotate_y", 0.0, -360.0, 360.0));
  float scale = static_cast<float>(t.number("scale", 1.0, 1e-6, 1e6));
  if (keys && (t.has("keys") || t.has("interpolation"))) {
    *keys = readKeys(t,
                     {{"translate", 3, -kBig, kBig},
                      {"rotate_y", 1, -36000.0, 36000.0},
                      {"scale", 1, 1e-6, 1e6}},
                     {translate.x, translate.y, translate.z, rotateY, scale});
    t.rejectUnknown({"translate", "rotate_y", "scale", "keys", "interpolation"});
  } else {
    t.rejectUnknown({"translate", "rotate_y", "scale"});
  }
  m = glm::translate(m, translate);
  m = glm::rotate(m, glm::radians(rotateY), glm::vec3(0, 1, 0));
  m = glm::scale(m, glm::vec3(scale));
  return m;
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
  if (o.has("method")) {
    const std::string m = o.string("method", "auto");
    if (m == "auto")
      f.method = FilterParams::Method::Auto;
    else if (m == "lipp")
      f.method = FilterParams::Method::Lipp;
    else if (m == "huang")
      f.method = FilterParams::Method::Huang;
    else
      o.fail("method", "must be \"auto\", \"lipp\" or \"huang\", not \"" + m + "\"");
  }
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

// The frames of a per-frame strand-file pattern ("dir/bob.####.hair", absolute): every file
// in its folder whose name is the pattern with a frame number for the '#' run; fails when
// there is none.
std::shared_ptr<StrandFrames> findStrandFrames(const JsonReader& o, const std::string& pattern,
                                               std::uint64_t maxBytes) {
  const std::filesystem::path folder = std::filesystem::path(pattern).parent_path();
  const std::string name = std::filesystem::path(pattern).filename().string();
  const std::size_t end = name.find_last_of('#');
  std::size_t begin = end;
  while (begin > 0 && name[begin - 1] == '#') --begin;
  const std::string prefix = name.substr(0, begin), suffix = name.substr(end + 1);
  auto frames = std::make_shared<StrandFrames>();
  frames->pattern = pattern;
  frames->maxBytes = maxBytes;
  std::size_t found = 0;
  std::error_code ec;
  for (std::filesystem::directory_iterator it(folder.empty() ? "." : folder, ec), last;
       !ec && it != last; it.increment(ec)) {
    const std::string n = it->path().filename().string();
    if (n.size() <= prefix.size() + suffix.size() || n.compare(0, prefix.size(), prefix) != 0 ||
        n.compare(n.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    const std::string digits = n.substr(prefix.size(), n.size() - prefix.size() - suffix.size());
    if (digits.size() > 9 ||
        !std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); }))
      continue;
    const long long number = std::stoll(digits);
    if (framePath(name, number) != n) continue;  // other padding: not this pattern's name
    frames->first = found == 0 ? number : std::min(frames->first, number);
    frames->last = found == 0 ? number : std::max(frames->last, number);
    ++found;
  }
  if (ec) o.fail("strands_file", "cannot list \"" + folder.string() + "\" (" + ec.message() + ")");
  if (found == 0)
    o.fail("strands_file", "no file matches \"" + pattern +
                               "\" (the '#' run stands for a frame number, zero-padded)");
  return frames;
}

// A groom entry's "visibility": {"file": a baked visibility file, "absorption"}, read once
// per file and checked against the groom it was baked for (`strands` at full detail).
void readVisibilityEntry(const JsonReader& o, const std::filesystem::path& base,
                         std::uint64_t strands, bool fileColor,
                         std::map<std::string, std::shared_ptr<const VisibilityBake>>& loaded,
                         GroomInstance& g) {
  if (!o.has("visibility")) return;
  JsonReader v = o.object(o.require("visibility"), "visibility");
  const std::string file = v.string("file", "");
  if (file.empty()) v.fail("file", "is missing: name a baked visibility file (.clhvis)");
  if (fileColor)
    v.fail("file",
           "a groom drawn with its file colours keeps no styling uv in the G-buffer, so it "
           "cannot look up baked visibility");
  std::filesystem::path p =
      std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : base / file;
  const std::string key = p.lexically_normal().string();
  auto it = loaded.find(key);
  if (it == loaded.end()) {
    try {
      it = loaded.emplace(key, std::make_shared<const VisibilityBake>(readVisibility(key))).first;
    } catch (const Error& e) {
      v.fail("file", e.what());
    }
  }
  if (it->second->strands != strands)
    v.fail("file", key + " was baked for a groom of " + std::to_string(it->second->strands) +
                       " strands, this groom has " + std::to_string(strands) +
                       " (bake it again with clhair bake-visibility)");
  g.visibility = it->second;
  g.visibilityAbsorption = static_cast<float>(v.number("absorption", 0.5, 0.0, 100.0));
  v.rejectUnknown({"file", "absorption"});
}

// "scale": "auto": the factor that makes the roots' largest extent (file units) a human
// head's hair line, kAutoRootExtent metres; 1 when the roots have no extent.
constexpr float kAutoRootExtent = 0.18f;

float autoScaleFactor(const StrandGroom& g, float* extent) {
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  std::size_t at = 0;
  for (std::uint32_t n : g.pointCounts) {
    lo = glm::min(lo, g.points[at]);
    hi = glm::max(hi, g.points[at]);
    at += n;
  }
  const glm::vec3 e = hi - lo;
  *extent = std::max(e.x, std::max(e.y, e.z));
  return *extent > 0.0f ? kAutoRootExtent / *extent : 1.0f;
}

// A groom entry's "children" (docs/scene-format.md, "Children"): lengths in scene units, at
// the file's `scale`. TressFX files grow the runtime's follow hairs unless told otherwise;
// other files draw their strands alone.
ChildrenParams readChildren(const JsonReader& o, float scale, bool tressfx) {
  ChildrenParams c;
  if (tressfx) {
    c.count = kTressFxFollowHairs;
    c.tipSpread = kTressFxTipSeparation;
    c.radius = kTressFxFollowRadiusMetres / scale;
  }
  if (!o.has("children")) return c;
  JsonReader k = o.object(o.require("children"), "children");
  const std::string mode = k.string("mode", "follow");
  if (mode != "follow" && mode != "interpolated")
    k.fail("mode", "is \"" + mode + "\", expected \"follow\" or \"interpolated\"");
  const bool follow = mode == "follow";
  c.mode = follow ? ChildrenParams::Mode::Follow : ChildrenParams::Mode::Interpolated;
  // follow: TressFX's defaults; interpolated: Blender's display amount of 10 per guide,
  // roots spread over half the guide spacing, no tip spread
  c.count = static_cast<std::uint32_t>(
      k.integer("count", follow ? static_cast<int>(kTressFxFollowHairs) : 10, 0,
                static_cast<int>(kMaxChildren)));
  c.tipSpread =
      static_cast<float>(k.number("tip_spread", follow ? kTressFxTipSeparation : 0.0, 0.0, 1000.0));
  c.radius = follow ? kTressFxFollowRadiusMetres / scale : 0.0f;  // 0: the guide spacing's
  if (k.has("radius")) c.radius = static_cast<float>(k.number("radius", 0.0, 0.0, 1e6)) / scale;
  c.clump = static_cast<float>(k.number("clump", 0.0, -1.0, 1.0));
  c.seed = static_cast<std::uint32_t>(k.integer64("seed", 1, 0, 0xFFFFFFFFll));
  k.rejectUnknown({"count", "mode", "radius", "tip_spread", "clump", "seed"});
  return c;
}

// A groom entry with "strands_file": the file (read once per scene), its placement (scale,
// up axis, then the entry's transform), appearance, LOD and filter.
GroomInstance readStrandGroom(
    const JsonReader& o, const std::filesystem::path& base, const FilterParams& sceneFilter,
    std::uint64_t maxBytes, std::map<std::string, std::shared_ptr<const StrandGroom>>& loaded,
    std::map<std::string, std::shared_ptr<const StrandGroom>>& variants,
    std::map<std::string, std::shared_ptr<const VisibilityBake>>& loadedVisibility,
    std::uint64_t sceneCap, std::vector<std::string>& warnings, std::vector<std::string>& notes,
    float& autoScale) {
  const std::string file = o.string("strands_file", "");
  if (file.empty()) o.fail("strands_file", "is empty: name a .hair, .data or .tfx strand file");
  std::filesystem::path p =
      std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : base / file;
  std::string key = p.lexically_normal().string();
  // "bob.####.hair": one file per frame; the first one found stands for the still groom
  std::shared_ptr<StrandFrames> frames;
  if (framePath(key, 0) != key) {
    frames = findStrandFrames(o, key, maxBytes);
    key = framePath(key, frames->first);
    p = key;
  }
  std::error_code ec;
  const bool found = std::filesystem::exists(p, ec);
  if (ec) o.fail("strands_file", "\"" + key + "\" cannot be checked (" + ec.message() + ")");
  if (!found) o.fail("strands_file", "\"" + key + "\" does not exist");
  // the entry's look, from the defaults: entries naming the same file may differ
  AppearanceParams look;
  LodParams lod;
  if (o.has("appearance")) readAppearance(o, o.require("appearance"), look, true);
  if (o.has("lod")) {
    JsonReader l = o.object(o.require("lod"), "lod");
    lod.enabled = l.boolean("enabled", lod.enabled);
    lod.lambda = static_cast<float>(l.number("lambda", lod.lambda, 1e-3, 1e3));
    lod.morphWindow = static_cast<float>(l.number("morph_window", lod.morphWindow, 0.0, 1.0));
    l.rejectUnknown({"enabled", "lambda", "morph_window"});
  }
  const auto cap =
      static_cast<std::uint64_t>(o.integer64("max_strands", static_cast<long long>(sceneCap), 0,
                                             static_cast<long long>(kMaxStrandPoints)));
  // "scale": a number, or "auto" (chosen from the file's roots below)
  const bool scaleAuto = o.has("scale") && o.require("scale").is_string();
  if (scaleAuto && o.string("scale", "") != "auto")
    o.fail("scale", "is \"" + o.string("scale", "") + "\", expected a number or \"auto\"");
  float scale = scaleAuto ? 1.0f : static_cast<float>(o.number("scale", 1.0, 1e-6, 1e6));
  float rootExtent = 0.0f;
  const std::string up = o.string("up", "y");
  if (up != "x" && up != "y" && up != "z")
    o.fail("up", "is \"" + up + "\", expected \"x\", \"y\" or \"z\"");
  // entries that name one file with the same look, LOD, cap, children and scale share one
  // groom (and so one device form); the first entry of a file takes it as read, other
  // variants copy it
  const auto dumpOf = [&](const char* k) { return o.has(k) ? o.require(k).dump() : ""; };
  const std::string variant = key + "\n" + dumpOf("appearance") + "\n" + dumpOf("lod") + "\n" +
                              std::to_string(cap) + "\n" + dumpOf("children") + "\n" +
                              dumpOf("scale");
  std::shared_ptr<const StrandGroom> shared;
  if (const auto same = variants.find(variant); same != variants.end()) {
    shared = same->second;
    if (scaleAuto) scale = autoScaleFactor(*shared, &rootExtent);
  } else {
    StrandGroom groom;
    const auto it = loaded.find(key);
    const bool firstRead = it == loaded.end();
    if (!firstRead) {
      groom = *it->second;
    } else {
      try {
        std::vector<std::string> notes;
        groom = loadStrandGroom(key, maxBytes, nullptr, &notes);
        for (const std::string& n : notes)
          warnings.push_back(o.file() + ": " + o.path("strands_file") + ": " + n);
      } catch (const Error& e) {
        o.fail("strands_file", e.what());
      }
    }
    // the file's own colours, thicknesses and transparencies are drawn unless the entry's
    // appearance gives its own (per key); asking for them by name on a file without any
    // says so
    const bool fileLook =
        !groom.colors.empty() || !groom.thickness.empty() || !groom.transparency.empty();
    if (!fileLook && o.has("appearance") && o.require("appearance").is_object() &&
        o.require("appearance").value("use_file_color", false))
      warnings.push_back(
          o.file() + ": " + o.path("appearance.use_file_color") + ": " + key +
          " has no per-point colours, thicknesses or transparencies, the groom's appearance " +
          "is used");
    groom.appearance = look;
    groom.lod = lod;
    if (scaleAuto) scale = autoScaleFactor(groom, &rootExtent);
    groom.children = readChildren(o, scale, lowerExtension(key) == ".tfx");
    const bool capped = cap > 0 && groom.pointCounts.size() > cap;
    if (firstRead && capped) loaded[key] = std::make_shared<const StrandGroom>(groom);
    capStrands(groom, cap);
    shared = std::make_shared<const StrandGroom>(std::move(groom));
    if (firstRead && !capped) loaded[key] = shared;
    variants[variant] = shared;
  }
  if (scaleAuto) {
    char buf[200];
    std::snprintf(buf, sizeof(buf),
                  "\"scale\": \"auto\" scales %s by %g: its roots span %g file units, "
                  "%g m after scaling",
                  key.c_str(), static_cast<double>(scale), static_cast<double>(rootExtent),
                  static_cast<double>(rootExtent * scale));
    notes.push_back(o.file() + ": " + o.path("scale") + ": " + buf);
    if (!(autoScale > 0.0f)) autoScale = scale;
  }
  GroomInstance g;
  g.name = o.string("name", shared->name);
  g.strands = shared;
  g.strandFrames = frames;
  glm::mat4 placement = o.has("transform")
                            ? readTransform(o, o.require("transform"), &g.transformKeys)
                            : glm::mat4(1.0f);
  g.fileTransform = strandFileTransform(scale, up == "x"   ? UpAxis::X
                                               : up == "z" ? UpAxis::Z
                                                           : UpAxis::Y);
  g.transform = placement * g.fileTransform;
  if (o.has("filter")) {
    g.hasFilter = true;
    g.filter = readFilter(o, o.require("filter"), sceneFilter);
  }
  readVisibilityEntry(o, base, shared->pointCounts.size(),
                      look.useFileColor && !shared->colors.empty(), loadedVisibility, g);
  o.rejectUnknown({"strands_file", "name", "transform", "scale", "up", "appearance", "lod",
                   "filter", "max_strands", "visibility", "children"});
  return g;
}

// A hair-mesh groom entry's "cage_animation" (a cage-animation file whose vertex count must
// be the mesh's layer vertices, read once per entry) and "wind".
void readCageMotion(const JsonReader& o, const std::filesystem::path& base, std::uint64_t maxBytes,
                    GroomInstance& g) {
  if (o.has("cage_animation")) {
    JsonReader c = o.object(o.require("cage_animation"), "cage_animation");
    const std::string file = c.string("file", "");
    if (file.empty()) c.fail("file", "is missing: name a cage-animation file (.cage)");
    std::filesystem::path p =
        std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : base / file;
    const std::string key = p.lexically_normal().string();
    std::error_code ec;
    if (!std::filesystem::exists(p, ec)) c.fail("file", "\"" + key + "\" does not exist");
    auto cage = std::make_shared<CageAnimation>();
    try {
      *cage = loadCageAnimation(key, maxBytes);
    } catch (const Error& e) {
      c.fail("file", e.what());
    }
    const HairMesh& m = *g.mesh;
    const std::uint64_t expected = static_cast<std::uint64_t>(m.layerCount) * m.vertexCount;
    if (cage->vertices != expected)
      c.fail("file", key + " holds " + std::to_string(cage->vertices) +
                         " vertices per frame, but the groom's cage has " +
                         std::to_string(expected) + " (" + std::to_string(m.layerCount) +
                         " layers of " + std::to_string(m.vertexCount) + " vertices)");
    g.cageStartFrame = c.number("start_frame", 1.0, -1e7, 1e7);
    c.rejectUnknown({"file", "start_frame"});
    g.cage = std::move(cage);
  }
  if (o.has("wind")) {
    JsonReader w = o.object(o.require("wind"), "wind");
    WindParams& wind = g.wind;
    wind.strength = static_cast<float>(w.number("strength", wind.strength, 0.0, kBig));
    const glm::vec3 d = w.vec3("direction", wind.direction, -kBig, kBig);
    if (glm::length(d) < 1e-6f) w.fail("direction", "must not be zero");
    wind.direction = glm::normalize(d);
    wind.frequency = static_cast<float>(w.number("frequency", wind.frequency, 0.0, 1000.0));
    wind.wavelength = static_cast<float>(w.number("wavelength", wind.wavelength, 1e-6, kBig));
    w.rejectUnknown({"strength", "direction", "frequency", "wavelength"});
  }
}

// A "meshes" entry: the OBJ file (read once per scene), its placement (scale, up axis, then
// transform, as for strand files) and its colour.
MeshInstance readMesh(const JsonReader& o, const std::filesystem::path& base,
                      std::uint64_t maxBytes,
                      std::map<std::string, std::shared_ptr<const TriangleMesh>>& loaded,
                      float autoScale) {
  const std::string file = o.string("file", "");
  if (file.empty()) o.fail("file", "is missing: name the mesh's .obj file");
  const std::string label = o.file() + ": mesh \"" + file + "\"";
  std::filesystem::path p =
      std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : base / file;
  const std::string key = p.lexically_normal().string();
  std::error_code ec;
  const bool found = std::filesystem::exists(p, ec);
  if (ec) throw Error(label + ": \"" + key + "\" cannot be checked (" + ec.message() + ")");
  if (!found) throw Error(label + ": \"" + key + "\" does not exist");
  MeshInstance m;
  auto it = loaded.find(key);
  if (it != loaded.end()) {
    m.mesh = it->second;
  } else {
    MeshLimits limits;
    limits.maxBufferBytes = maxBytes;
    m.mesh = std::make_shared<const TriangleMesh>(loadTriangleMesh(key, limits, label));
    loaded[key] = m.mesh;
  }
  m.name = o.string("name", m.mesh->name);
  // "auto": the factor the grooms' "scale": "auto" chose (a head and its groom share units)
  float scale = 1.0f;
  if (o.has("scale") && o.require("scale").is_string()) {
    if (o.string("scale", "") != "auto")
      o.fail("scale", "is \"" + o.string("scale", "") + "\", expected a number or \"auto\"");
    if (!(autoScale > 0.0f))
      o.fail("scale",
             "is \"auto\", which takes the factor of a strand-file groom's \"scale\": "
             "\"auto\", and no groom has one");
    scale = autoScale;
  } else {
    scale = static_cast<float>(o.number("scale", 1.0, 1e-6, 1e6));
  }
  const std::string up = o.string("up", "y");
  if (up != "x" && up != "y" && up != "z")
    o.fail("up", "is \"" + up + "\", expected \"x\", \"y\" or \"z\"");
  glm::mat4 placement =
      o.has("transform") ? readTransform(o, o.require("transform")) : glm::mat4(1.0f);
  m.transform = placement * strandFileTransform(scale, up == "x"   ? UpAxis::X
                                                       : up == "z" ? UpAxis::Z
                                                                   : UpAxis::Y);
  m.color = o.vec3("color", m.color, 0.0, 1.0);
  o.rejectUnknown({"file", "name", "transform", "scale", "up", "color"});
  return m;
}

const std::vector<glm::vec3>& groomPoints(const GroomInstance& g) {
  return g.strands ? g.strands->points : g.mesh->positions;
}

std::string showVec(const glm::vec3& v) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), "(%g, %g, %g)", v.x, v.y, v.z);
  return buf;
}

// The box that camera presets frame: the bounds of the grooms' world points that are not
// outliers. The 0.5 % and 99.5 % percentiles per axis (over at most about a million
// points, evenly strided) give a core box; a point counts when it lies within one core
// size (the largest axis extent) of that box. For an ordinary groom every point does, so
// the framing is its exact bounds; a stray vertex (a broken file's 1e30) is left out, and
// described in *warnings (one line per groom, naming its first such strand) when given.
void framingBounds(const Scene& s, glm::vec3& lo, glm::vec3& hi, std::vector<std::string>* warnings,
                   const std::string& where) {
  lo = glm::vec3(-0.5f);
  hi = glm::vec3(0.5f);
  std::size_t total = 0;
  for (const GroomInstance& g : s.grooms) total += groomPoints(g).size();
  if (total == 0) return;
  const std::size_t stride = std::max<std::size_t>(1, total / 1'000'000);
  std::vector<float> axis[3];
  for (auto& a : axis) a.reserve(total / stride + s.grooms.size());
  for (const GroomInstance& g : s.grooms)
    for (std::size_t i = 0; i < groomPoints(g).size(); i += stride) {
      const glm::vec3 w = glm::vec3(g.transform * glm::vec4(groomPoints(g)[i], 1.0f));
      for (int c = 0; c < 3; ++c) axis[c].push_back(w[c]);
    }
  glm::vec3 coreLo, coreHi;
  for (int c = 0; c < 3; ++c) {
    std::vector<float>& a = axis[c];
    const std::size_t n = a.size();
    const std::size_t k0 = static_cast<std::size_t>(0.005 * static_cast<double>(n - 1));
    const std::size_t k1 = static_cast<std::size_t>(std::ceil(0.995 * static_cast<double>(n - 1)));
    std::nth_element(a.begin(), a.begin() + k0, a.end());
    coreLo[c] = a[k0];
    std::nth_element(a.begin(), a.begin() + k1, a.end());
    coreHi[c] = a[k1];
  }
  const glm::vec3 coreExtent = coreHi - coreLo;
  float margin = std::max(coreExtent.x, std::max(coreExtent.y, coreExtent.z));
  // a core of one point (or of points in one place) still admits nearby ones
  margin =
      std::max(margin, 1e-6f * std::max(1.0f, std::max(glm::length(coreLo), glm::length(coreHi))));
  const glm::vec3 acceptLo = coreLo - margin, acceptHi = coreHi + margin;

  glm::vec3 blo(std::numeric_limits<float>::max()), bhi(-std::numeric_limits<float>::max());
  for (std::size_t gi = 0; gi < s.grooms.size(); ++gi) {
    const GroomInstance& g = s.grooms[gi];
    const std::vector<glm::vec3>& points = groomPoints(g);
    std::size_t strand = 0, strandEnd = g.strands && !g.strands->pointCounts.empty()
                                            ? g.strands->pointCounts[0]
                                            : 0;
    std::size_t outlierStrands = 0, firstOutlier = 0, lastCounted = ~std::size_t(0);
    glm::vec3 firstPoint(0.0f);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (g.strands)
        while (i >= strandEnd && strand + 1 < g.strands->pointCounts.size())
          strandEnd += g.strands->pointCounts[++strand];
      const glm::vec3 w = glm::vec3(g.transform * glm::vec4(points[i], 1.0f));
      const bool inside =
          glm::all(glm::greaterThanEqual(w, acceptLo)) && glm::all(glm::lessThanEqual(w, acceptHi));
      if (inside) {
        blo = glm::min(blo, w);
        bhi = glm::max(bhi, w);
        continue;
      }
      const std::size_t id = g.strands ? strand : i;
      if (id == lastCounted) continue;
      if (outlierStrands == 0) {
        firstOutlier = id;
        firstPoint = w;
      }
      ++outlierStrands;
      lastCounted = id;
    }
    if (outlierStrands > 0 && warnings) {
      const std::string what = g.strands ? "strand" : "hair-mesh layer vertex";
      std::string msg = where + ": grooms[" + std::to_string(gi) + "] (\"" + g.name +
                        "\"): " + what + " " + std::to_string(firstOutlier) + " has a point at " +
                        showVec(firstPoint) + ", far outside the rest of the hair (" +
                        showVec(coreLo) + " to " + showVec(coreHi) +
                        "); camera presets frame the hair without it";
      if (outlierStrands > 1)
        msg += " (and " + std::to_string(outlierStrands - 1) + " more " + what +
               (outlierStrands > 2 ? "s" : "") + " like it)";
      warnings->push_back(msg);
    }
  }
  if (blo.x <= bhi.x) {
    lo = blo;
    hi = bhi;
    // follow hairs reach up to their offset's growth beyond their guides
    for (const GroomInstance& g : s.grooms) {
      if (!g.strands || g.strands->children.count == 0) continue;
      const ChildrenParams& c = g.strands->children;
      const float scale = std::cbrt(std::fabs(glm::determinant(glm::mat3(g.transform))));
      const float reach = 1.4143f * std::max(c.radius, 0.0f) * (1.0f + c.tipSpread) * scale;
      lo -= glm::vec3(reach);
      hi += glm::vec3(reach);
    }
  }
}

}  // namespace

std::vector<std::string> viewWarnings(const Scene& scene, const std::string& where) {
  // Human hair is 20..180 um thick on grooms 0.05..1.5 m across, so width / size is 5e-5 or
  // more (3e-5 would be 70 um fibres on a groom 2.3 m across), while the same file in
  // centimetres is 100 times lower; 50 units is 50 m in clhair's metres.
  constexpr float kMinWidthRatio = 3e-5f, kMaxSize = 50.0f, kMinPixels = 1.0f;
  std::vector<std::string> out;
  const Camera& c = scene.camera;
  const glm::vec3 forward = glm::normalize(c.target - c.position);
  const float fy =
      0.5f * static_cast<float>(scene.height) / std::tan(glm::radians(c.fovYDegrees) * 0.5f);
  for (std::size_t i = 0; i < scene.grooms.size(); ++i) {
    const GroomInstance& g = scene.grooms[i];
    Scene one;
    one.grooms.push_back(g);
    glm::vec3 lo, hi;
    framingBounds(one, lo, hi, nullptr, "");
    const glm::vec3 ext = hi - lo;
    const float size = std::max(ext.x, std::max(ext.y, ext.z));
    const float width =
        g.strands ? g.strands->appearance.strandWidth : g.mesh->appearance.strandWidth;
    const float depth = glm::dot(0.5f * (lo + hi) - c.position, forward);
    const std::string hint =
        g.strands ? "\"scale\" (0.01 for a file in centimetres, or \"auto\" to scale its roots "
                    "to a head's 0.18 m)"
                  : "\"transform\": {\"scale\": ...} (0.01 for centimetres)";
    std::string msg;
    char buf[256];
    if (size > 0.0f && (width < kMinWidthRatio * size || size > kMaxSize)) {
      std::snprintf(
          buf, sizeof(buf),
          "is %g units across with fibres %g wide (%.2g of its size; human hair is about 1e-4)",
          static_cast<double>(size), static_cast<double>(width), static_cast<double>(width / size));
      msg = buf;
      if (depth > 0.0f) {
        std::snprintf(buf, sizeof(buf), ", so its fibres are %.2g pixels wide here",
                      static_cast<double>(width * fy / depth));
        msg += buf;
      }
      msg += ": are its units right? set " + hint;
    } else if (depth > 0.0f && size * fy / depth < kMinPixels) {
      std::snprintf(buf, sizeof(buf),
                    "covers only %.2g pixels of the %dx%d image (%g units across, %g away)",
                    static_cast<double>(size * fy / depth), scene.width, scene.height,
                    static_cast<double>(size), static_cast<double>(depth));
      msg = std::string(buf) + ": is it in the units you expect? check " + hint + " or the camera";
    }
    if (!msg.empty())
      out.push_back(where + ": grooms[" + std::to_string(i) + "] (\"" + g.name + "\") " + msg);
  }
  return out;
}

CameraPreset parseCameraPreset(const std::string& name) {
  if (name == "close") return CameraPreset::Close;
  if (name == "mid") return CameraPreset::Mid;
  if (name == "far") return CameraPreset::Far;
  throw Error("unknown camera preset \"" + name + "\"; expected close, mid or far");
}

namespace {

// Frames the grooms' bounds from unit direction `dir` (target -> eye).
Camera frameAlong(const Scene& scene, CameraPreset preset, glm::vec3 dir, float fovYDeg,
                  glm::vec3 up) {
  glm::vec3 lo, hi;
  framingBounds(scene, lo, hi, nullptr, "");
  // the meshes too (a head under its groom), so that none is cut off
  if (scene.grooms.empty() && !scene.meshes.empty()) {
    lo = glm::vec3(std::numeric_limits<float>::max());
    hi = -lo;
  }
  for (const MeshInstance& m : scene.meshes)
    for (const glm::vec3& p : m.mesh->positions) {
      const glm::vec3 w = glm::vec3(m.transform * glm::vec4(p, 1.0f));
      lo = glm::min(lo, w);
      hi = glm::max(hi, w);
    }
  if (!(lo.x <= hi.x)) {
    lo = glm::vec3(-0.5f);
    hi = glm::vec3(0.5f);
  }
  const float fraction = preset == CameraPreset::Close ? 0.6f
                         : preset == CameraPreset::Mid ? 0.2f
                                                       : 0.05f;
  glm::vec3 center = 0.5f * (lo + hi);
  glm::vec3 extent = hi - lo;
  // The groom's size across the view: its vertical extent, or its horizontal one when the
  // image is the smaller side of it (a wide groom must still fit).
  float aspect = static_cast<float>(scene.width) / static_cast<float>(scene.height);
  float horizontal = std::max(extent.x, extent.z) / aspect;
  float size = std::max(extent.y, horizontal);
  float tanHalf = std::tan(glm::radians(fovYDeg) * 0.5f);
  float distance = std::max(size / (2.0f * fraction * tanHalf), glm::length(extent));
  Camera cam;
  cam.fovYDegrees = fovYDeg;
  cam.target = center;
  cam.position = center + dir * distance;
  cam.up = up;
  return cam;
}

}  // namespace

Camera framePreset(const Scene& scene, CameraPreset preset, float azimuthDeg, float elevationDeg,
                   float fovYDeg) {
  float az = glm::radians(azimuthDeg), el = glm::radians(elevationDeg);
  glm::vec3 dir(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
  return frameAlong(scene, preset, dir, fovYDeg, glm::vec3(0, 1, 0));
}

Camera reframeCamera(const Scene& scene, CameraPreset preset) {
  const Camera& c = scene.camera;
  glm::vec3 dir = c.position - c.target;
  const float len = glm::length(dir);
  // loadScene refuses a camera whose target is its position; a Scene built in code may
  // still hold one, and then the default preset direction is used
  const float el = glm::radians(10.0f);
  dir = len > 0.0f && std::isfinite(len) ? dir / len : glm::vec3(0.0f, std::sin(el), std::cos(el));
  return frameAlong(scene, preset, dir, c.fovYDegrees, c.up);
}

Scene loadScene(const std::string& path, std::uint64_t maxStrandBytes) {
  json root = readJsonFile(path, "scene");
  JsonReader r(path, root);
  Scene s;
  const std::filesystem::path base = std::filesystem::path(path).parent_path();

  if (r.has("resolution")) {
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
  s.background = r.vec3("background", s.background, 0.0, kBig);
  if (r.has("background_image")) {
    std::filesystem::path f = r.string("background_image", "");
    if (f.empty()) r.fail("background_image", "is empty");
    if (!f.is_absolute()) f = base / f;
    s.backgroundImage = f.lexically_normal().string();
    std::error_code ec;
    if (!std::filesystem::exists(s.backgroundImage, ec))
      r.fail("background_image", "\"" + s.backgroundImage + "\" does not exist");
  }
  s.ambient = r.vec3("ambient", s.ambient, 0.0, kBig);

  if (r.has("lights")) {
    const json& lights = r.require("lights");
    if (!lights.is_array()) r.fail("lights", "must be an array");
    for (std::size_t i = 0; i < lights.size(); ++i) {
      JsonReader l = r.object(lights[i], "lights[" + std::to_string(i) + "]");
      Light light;
      std::string type = l.string("type", "directional");
      if (type == "point") {
        light.type = Light::Type::Point;
        light.position = l.vec3("position", light.position, -kBig, kBig);
      } else if (type == "directional") {
        light.type = Light::Type::Directional;
        glm::vec3 d = l.vec3("direction", light.direction, -kBig, kBig);
        if (glm::length(d) < 1e-6f) l.fail("direction", "must not be zero");
        light.direction = glm::normalize(d);
      } else {
        l.fail("type", "is \"" + type + "\", expected \"point\" or \"directional\"");
      }
      light.color = l.vec3("color", light.color, 0.0, kBig);
      light.intensity = static_cast<float>(l.number("intensity", light.intensity, 0.0, kBig));
      light.shadows = l.boolean("shadows", false);
      l.rejectUnknown({"type", "position", "direction", "color", "intensity", "shadows"});
      s.lights.push_back(light);
    }
    if (s.lights.size() > 16)
      r.fail("lights",
             "holds " + std::to_string(s.lights.size()) + " lights, at most 16 are supported");
    int shadowed = 0;
    for (const Light& l : s.lights) shadowed += l.shadows;
    if (shadowed > 4)
      r.fail("lights", std::to_string(shadowed) + " lights cast shadows, at most 4 can");
  }
  if (r.has("spheres")) {
    const json& a = r.require("spheres");
    if (!a.is_array()) r.fail("spheres", "must be an array");
    for (std::size_t i = 0; i < a.size(); ++i) {
      JsonReader o = r.object(a[i], "spheres[" + std::to_string(i) + "]");
      Sphere sp;
      sp.center = o.vec3("center", sp.center, -kBig, kBig);
      sp.radius = static_cast<float>(o.number("radius", sp.radius, 1e-6, kBig));
      sp.color = o.vec3("color", sp.color, 0.0, 1.0);
      o.rejectUnknown({"center", "radius", "color"});
      s.spheres.push_back(sp);
    }
  }
  if (r.has("planes")) {
    const json& a = r.require("planes");
    if (!a.is_array()) r.fail("planes", "must be an array");
    for (std::size_t i = 0; i < a.size(); ++i) {
      JsonReader o = r.object(a[i], "planes[" + std::to_string(i) + "]");
      Plane pl;
      glm::vec3 n = o.vec3("normal", pl.normal, -kBig, kBig);
      if (glm::length(n) < 1e-6f) o.fail("normal", "must not be zero");
      pl.normal = glm::normalize(n);
      pl.offset = static_cast<float>(o.number("offset", pl.offset, -kBig, kBig));
      pl.color = o.vec3("color", pl.color, 0.0, 1.0);
      o.rejectUnknown({"normal", "offset", "color"});
      s.planes.push_back(pl);
    }
  }

  if (r.has("shadows")) {
    JsonReader o = r.object(r.require("shadows"), "shadows");
    s.shadows.resolution = o.integer("resolution", s.shadows.resolution, 16, 4096);
    if (o.has("layers")) {
      glm::vec3 l =
          o.vec3("layers", glm::vec3(s.shadows.layers[0], s.shadows.layers[1], s.shadows.layers[2]),
                 1e-7, kBig);
      if (!(l.x < l.y && l.y < l.z))
        o.fail("layers", "must increase: three layer ends past the first hair");
      for (int i = 0; i < 3; ++i) s.shadows.layers[i] = l[i];
    }
    s.shadows.density = static_cast<float>(o.number("density", s.shadows.density, 0.0, 1e6));
    s.shadows.lodCorrection = o.boolean("lod_correction", s.shadows.lodCorrection);
    s.shadows.bias = static_cast<float>(o.number("bias", s.shadows.bias, 0.0, 1000.0));
    s.shadows.pcf = o.boolean("pcf", s.shadows.pcf);
    s.shadows.lodScale = static_cast<float>(o.number("lod_scale", s.shadows.lodScale, 1e-3, 1e3));
    o.rejectUnknown(
        {"resolution", "layers", "density", "lod_correction", "bias", "pcf", "lod_scale"});
  }
  if (r.has("filter")) s.filter = readFilter(r, r.require("filter"), s.filter);
  if (r.has("environment")) {
    JsonReader o = r.object(r.require("environment"), "environment");
    EnvironmentDesc& e = s.environment;
    e.enabled = true;
    if (o.has("file") == o.has("sky"))
      o.fail("file", "give exactly one of \"file\" (an equirectangular map) and \"sky\"");
    if (o.has("file")) {
      std::filesystem::path f = o.string("file", "");
      if (!f.is_absolute()) f = base / f;
      e.file = f.lexically_normal().string();
      std::error_code ec;
      if (!std::filesystem::exists(e.file, ec)) o.fail("file", "\"" + e.file + "\" does not exist");
    } else {
      JsonReader k = o.object(o.require("sky"), "sky");
      SkyParams& sky = e.sky;
      sky.sunElevationDeg =
          static_cast<float>(k.number("sun_elevation", sky.sunElevationDeg, -90.0, 90.0));
      sky.sunAzimuthDeg =
          static_cast<float>(k.number("sun_azimuth", sky.sunAzimuthDeg, -360.0, 360.0));
      sky.sunAngularDiameterDeg = static_cast<float>(
          k.number("sun_angular_diameter", sky.sunAngularDiameterDeg, 0.01, 45.0));
      sky.sunColor = k.vec3("sun_color", sky.sunColor, 0.0, kBig);
      sky.sunIrradiance =
          static_cast<float>(k.number("sun_irradiance", sky.sunIrradiance, 0.0, 1e6));
      sky.zenith = k.vec3("zenith", sky.zenith, 0.0, kBig);
      sky.horizon = k.vec3("horizon", sky.horizon, 0.0, kBig);
      sky.ground = k.vec3("ground", sky.ground, 0.0, kBig);
      sky.gradientExponent =
          static_cast<float>(k.number("gradient_exponent", sky.gradientExponent, 0.01, 100.0));
      sky.groundBlend = static_cast<float>(k.number("ground_blend", sky.groundBlend, 0.0, 1.0));
      sky.width = k.integer("resolution", sky.width, 16, 4096);
      k.rejectUnknown({"sun_elevation", "sun_azimuth", "sun_angular_diameter", "sun_color",
                       "sun_irradiance", "zenith", "horizon", "ground", "gradient_exponent",
                       "ground_blend", "resolution"});
    }
    e.intensity = static_cast<float>(o.number("intensity", e.intensity, 0.0, 1e6));
    e.rotateYDegrees = static_cast<float>(o.number("rotate_y", e.rotateYDegrees, -360.0, 360.0));
    e.visible = o.boolean("visible", e.visible);
    o.rejectUnknown({"file", "sky", "intensity", "rotate_y", "visible"});
  }

  std::map<std::string, std::shared_ptr<const HairMesh>> loaded, loadedVariants;
  std::map<std::string, std::shared_ptr<const StrandGroom>> loadedStrands, strandVariants;
  s.segmentBudget = static_cast<std::uint64_t>(
      r.integer64("segment_budget", static_cast<long long>(s.segmentBudget), 0,
                  static_cast<long long>(kMaxSegmentBudget)));
  const auto sceneCap = static_cast<std::uint64_t>(r.integer64("max_strands", 0, 0, 50'000'000));
  std::map<std::string, std::shared_ptr<const VisibilityBake>> loadedVisibility;
  float autoScale = 0.0f;  // the first "scale": "auto" groom's factor (meshes may take it)
  if (r.has("grooms")) {
    const json& a = r.require("grooms");
    if (!a.is_array()) r.fail("grooms", "must be an array");
    for (std::size_t i = 0; i < a.size(); ++i) {
      JsonReader o = r.object(a[i], "grooms[" + std::to_string(i) + "]");
      if (o.has("file") == o.has("strands_file"))
        o.fail("file",
               "give exactly one of \"file\" (a hair mesh) and \"strands_file\" (a .hair, .data or "
               ".tfx strand file)");
      if (o.has("strands_file")) {
        s.grooms.push_back(readStrandGroom(o, base, s.filter, maxStrandBytes, loadedStrands,
                                           strandVariants, loadedVisibility, sceneCap, s.warnings,
                                           s.notes, autoScale));
        continue;
      }
      std::string file = o.string("file", "");
      if (file.empty()) o.fail("file", "is missing: name the groom's hair-mesh file");
      std::filesystem::path p =
          std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : base / file;
      std::string key = p.lexically_normal().string();
      std::error_code ec;
      const bool found = std::filesystem::exists(p, ec);
      if (ec) o.fail("file", "\"" + key + "\" cannot be checked (" + ec.message() + ")");
      if (!found) o.fail("file", "\"" + key + "\" does not exist");
      std::shared_ptr<const HairMesh> mesh;
      if (loaded.count(key)) {
        mesh = loaded[key];
      } else {
        mesh = std::make_shared<const HairMesh>(loadHairMesh(key));
        loaded[key] = mesh;
      }
      GroomInstance g;
      g.name = o.string("name", mesh->name);
      if (o.has("transform"))
        g.transform = readTransform(o, o.require("transform"), &g.transformKeys);
      if (o.has("filter")) {
        g.hasFilter = true;
        g.filter = readFilter(o, o.require("filter"), s.filter);
      }
      const auto cap = static_cast<std::uint64_t>(
          o.integer64("max_strands", static_cast<long long>(sceneCap), 0, 50'000'000));
      const auto dumpOf = [&](const char* k) { return o.has(k) ? o.require(k).dump() : ""; };
      const std::string variant = key + "\n" + dumpOf("strands") + "\n" + dumpOf("lod") + "\n" +
                                  dumpOf("control_points") + "\n" + std::to_string(cap);
      if (const auto same = loadedVariants.find(variant); same != loadedVariants.end()) {
        mesh = same->second;  // the same overrides and cap: one device form for all entries
      } else if (o.has("strands") || o.has("lod") || o.has("control_points") ||
                 (cap > 0 && static_cast<std::uint64_t>(mesh->strandCount) > cap)) {
        HairMesh copy = *mesh;
        copy.strandCount = o.integer64("strands", copy.strandCount, 0, 50'000'000);
        copy.controlPoints =
            o.integer("control_points", copy.controlPoints, 2, CLH_MAX_CONTROL_POINTS);
        if (o.has("lod")) {
          JsonReader l = o.object(o.require("lod"), "lod");
          copy.lod.enabled = l.boolean("enabled", copy.lod.enabled);
          copy.lod.lambda = static_cast<float>(l.number("lambda", copy.lod.lambda, 1e-3, 1e3));
          copy.lod.morphWindow =
              static_cast<float>(l.number("morph_window", copy.lod.morphWindow, 0.0, 1.0));
          l.rejectUnknown({"enabled", "lambda", "morph_window"});
        }
        capStrands(copy, cap);
        validateHairMesh(copy, path + ": grooms[" + std::to_string(i) + "]");
        mesh = std::make_shared<const HairMesh>(std::move(copy));
      }
      loadedVariants[variant] = mesh;
      g.mesh = mesh;
      readCageMotion(o, base, maxStrandBytes, g);
      // an animated entry deforms its own copy: entries naming one file share a device form
      if (g.cage || g.wind.strength > 0.0f) g.mesh = std::make_shared<const HairMesh>(*g.mesh);
      readVisibilityEntry(o, base, static_cast<std::uint64_t>(g.mesh->strandCount), false,
                          loadedVisibility, g);
      o.rejectUnknown({"file", "name", "transform", "strands", "lod", "control_points", "filter",
                       "cage_animation", "wind", "max_strands", "visibility"});
      s.grooms.push_back(g);
    }
  }

  // meshes after the grooms: a mesh's "scale": "auto" takes the grooms' factor
  if (r.has("meshes")) {
    const json& a = r.require("meshes");
    if (!a.is_array()) r.fail("meshes", "must be an array");
    std::map<std::string, std::shared_ptr<const TriangleMesh>> loadedMeshes;
    for (std::size_t i = 0; i < a.size(); ++i)
      s.meshes.push_back(readMesh(r.object(a[i], "meshes[" + std::to_string(i) + "]"), base,
                                  maxStrandBytes, loadedMeshes, autoScale));
  }

  if (!s.grooms.empty()) {
    glm::vec3 lo, hi;
    framingBounds(s, lo, hi, &s.warnings, path);
  }
  if (r.has("camera")) {
    JsonReader c = r.object(r.require("camera"), "camera");
    float fov = static_cast<float>(c.number("fov", 35.0, 1.0, 170.0));
    const bool keyed = c.has("keys") || c.has("interpolation");
    CameraAnimation& anim = s.cameraAnimation;
    if (c.has("preset")) {
      std::string name = c.string("preset", "mid");
      CameraPreset preset;
      try {
        preset = parseCameraPreset(name);
      } catch (const Error& e) {
        c.fail("preset", e.what());
      }
      const double azimuth = c.number("azimuth", 0.0, -360.0, 360.0);
      const double elevation = c.number("elevation", 10.0, -89.0, 89.0);
      s.camera =
          framePreset(s, preset, static_cast<float>(azimuth), static_cast<float>(elevation), fov);
      if (keyed) {
        anim.preset = true;
        anim.framing = preset;
        anim.keys = readKeys(c,
                             {{"azimuth", 1, -36000.0, 36000.0},
                              {"elevation", 1, -89.0, 89.0},
                              {"fov", 1, 1.0, 170.0}},
                             {azimuth, elevation, fov});
      }
      c.rejectUnknown({"preset", "azimuth", "elevation", "fov", "keys", "interpolation"});
    } else {
      s.camera.position = c.vec3("position", s.camera.position, -kBig, kBig);
      s.camera.target = c.vec3("target", s.camera.target, -kBig, kBig);
      s.camera.up = c.vec3("up", s.camera.up, -kBig, kBig);
      s.camera.fovYDegrees = fov;
      if (glm::length(s.camera.target - s.camera.position) < 1e-9f)
        c.fail("target", "must differ from position");
      if (glm::length(glm::cross(s.camera.target - s.camera.position, s.camera.up)) < 1e-9f)
        c.fail("up", "must not be parallel to the viewing direction");
      if (keyed) {
        const Camera& k = s.camera;
        anim.keys = readKeys(c,
                             {{"position", 3, -kBig, kBig},
                              {"target", 3, -kBig, kBig},
                              {"up", 3, -kBig, kBig},
                              {"fov", 1, 1.0, 170.0}},
                             {k.position.x, k.position.y, k.position.z, k.target.x, k.target.y,
                              k.target.z, k.up.x, k.up.y, k.up.z, k.fovYDegrees});
        // every key must be a camera on its own (between keys sceneAtFrame checks again)
        for (std::size_t i = 0; i < anim.keys.frames.size(); ++i) {
          const double* v = &anim.keys.values[i * 10];
          const glm::vec3 pos(v[0], v[1], v[2]), target(v[3], v[4], v[5]), up(v[6], v[7], v[8]);
          const std::string where = "keys[" + std::to_string(i) + "]";
          if (glm::length(target - pos) < 1e-9f) c.fail(where, "target must differ from position");
          if (glm::length(glm::cross(target - pos, up)) < 1e-9f)
            c.fail(where, "up must not be parallel to the viewing direction");
        }
      }
      c.rejectUnknown({"position", "target", "up", "fov", "keys", "interpolation"});
    }
  } else {
    s.camera = framePreset(s, CameraPreset::Mid);
  }
  if (r.has("cameras")) {
    const json& cams = r.require("cameras");
    if (!cams.is_array() || cams.empty() || cams.size() > static_cast<std::size_t>(kMaxViews))
      r.fail("cameras", "must be an array of 1 to " + std::to_string(kMaxViews) + " views");
    for (std::size_t i = 0; i < cams.size(); ++i) {
      JsonReader c = r.object(cams[i], "cameras[" + std::to_string(i) + "]");
      View v;
      v.name = c.string("name", "");
      if (v.name.empty() || v.name.find_first_of("/\\%#") != std::string::npos)
        c.fail("name", "a view needs a name without / \\ % or #");
      for (const View& o : s.views)
        if (o.name == v.name) c.fail("name", "\"" + v.name + "\" names two views");
      if (c.has("offset")) {
        v.relative = true;
        v.offset = c.vec3("offset", v.offset, -kBig, kBig);
        c.rejectUnknown({"name", "offset"});
      } else {
        Camera& k = v.camera;
        k.position = c.vec3("position", k.position, -kBig, kBig);
        k.target = c.vec3("target", k.target, -kBig, kBig);
        k.up = c.vec3("up", k.up, -kBig, kBig);
        k.fovYDegrees = static_cast<float>(c.number("fov", 35.0, 1.0, 170.0));
        if (glm::length(k.target - k.position) < 1e-9f)
          c.fail("target", "must differ from position");
        if (glm::length(glm::cross(k.target - k.position, k.up)) < 1e-9f)
          c.fail("up", "must not be parallel to the viewing direction");
        c.rejectUnknown({"name", "position", "target", "up", "fov"});
      }
      s.views.push_back(v);
    }
  }
  s.frameRate = r.number("frame_rate", s.frameRate, 1e-3, 1e6);
  if (r.has("raster")) {
    const std::string m = r.string("raster", "lines");
    if (m == "lines")
      s.raster = RasterMode::Lines;
    else if (m == "coverage")
      s.raster = RasterMode::Coverage;
    else
      r.fail("raster", "must be \"lines\" or \"coverage\", not \"" + m + "\"");
  }
  if (r.has("quality")) s.quality = readQuality(r);
  if (r.has("temporal")) {  // temporal reprojection (clhair/temporal.h), off by default
    JsonReader o = r.object(r.require("temporal"), "temporal");
    TemporalParams& tp = s.temporal;
    tp.history = o.integer("history", tp.history, 0, kMaxTemporalHistory);
    tp.blend = static_cast<float>(o.number("blend", tp.blend, 1e-3, 1.0));
    tp.depthTolerance =
        static_cast<float>(o.number("depth_tolerance", tp.depthTolerance, 1e-4, 10.0));
    o.rejectUnknown({"history", "blend", "depth_tolerance"});
  }
  r.rejectUnknown({"resolution",     "camera",      "cameras",     "background",       "ambient",
                   "lights",         "spheres",     "planes",      "meshes",           "grooms",
                   "shadows",        "filter",      "environment", "background_image", "frame_rate",
                   "segment_budget", "max_strands", "raster",      "temporal",         "quality"});
  return s;
}

}  // namespace clhair
