// scene_strand_groom.cpp — a scene's groom entry that names a strand file ("strands_file":
// cyHair .hair, USC-HairSalon .data, TressFX .tfx, PLY or a per-frame "bob.####.hair"
// pattern): the file read once per scene with a byte limit before anything is allocated,
// its placement (scale, "auto" included, up axis, then the entry's transform), appearance,
// LOD, strand cap, children, filter and baked visibility.
//
// Entries naming one file with the same look, LOD, cap, children and scale share one groom,
// and so one device form.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <system_error>

#include "clhair/error.h"
#include "io/appearance_io.h"
#include "io/auto_scale.h"
#include "io/enum_field.h"
#include "io/scene_sections.h"

namespace clhair::scene_io {

namespace {

constexpr EnumName<ChildrenParams::Mode> kChildModes[] = {
    {"follow", ChildrenParams::Mode::Follow}, {"interpolated", ChildrenParams::Mode::Interpolated}};

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

// The entry's strand file as a path key: "bob.####.hair" stands for its first frame, whose
// frames `frames` receives. Fails when the file does not exist.
std::string strandFileKey(const JsonReader& o, const std::filesystem::path& base,
                          std::uint64_t maxBytes, std::shared_ptr<StrandFrames>* frames) {
  const std::string file = o.string("strands_file", "");
  if (file.empty()) o.fail("strands_file", "is empty: name a .hair, .data or .tfx strand file");
  std::filesystem::path p =
      std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : base / file;
  std::string key = p.lexically_normal().string();
  if (framePath(key, 0) != key) {
    *frames = findStrandFrames(o, key, maxBytes);
    key = framePath(key, (*frames)->first);
    p = key;
  }
  std::error_code ec;
  const bool found = std::filesystem::exists(p, ec);
  if (ec) o.fail("strands_file", "\"" + key + "\" cannot be checked (" + ec.message() + ")");
  if (!found) o.fail("strands_file", "\"" + key + "\" does not exist");
  return key;
}

// The strand file `key` as read; its reader's notes become the scene's warnings.
StrandGroom readStrandFile(const JsonReader& o, const std::string& key, std::uint64_t maxBytes,
                           std::vector<std::string>& warnings) {
  try {
    std::vector<std::string> notes;
    StrandGroom g = loadStrandGroom(key, maxBytes, nullptr, &notes);
    for (const std::string& n : notes)
      warnings.push_back(o.file() + ": " + o.path("strands_file") + ": " + n);
    return g;
  } catch (const Error& e) {
    o.fail("strands_file", e.what());
  }
  return {};  // o.fail throws
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
  c.mode = readEnum(k, "mode", k.string("mode", "follow"), kChildModes, EnumWording::Expected);
  const bool follow = c.mode == ChildrenParams::Mode::Follow;
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

}  // namespace

// A groom entry with "strands_file": the file (read once per scene), its placement (scale:
// a number, or "auto": `autoScale`, sceneAutoScale's; up axis; then the entry's transform),
// appearance, LOD and filter.
GroomInstance readStrandGroom(
    const JsonReader& o, const std::filesystem::path& base, const FilterParams& sceneFilter,
    std::uint64_t maxBytes, std::map<std::string, std::shared_ptr<const StrandGroom>>& loaded,
    std::map<std::string, std::shared_ptr<const StrandGroom>>& variants,
    std::map<std::string, std::shared_ptr<const VisibilityBake>>& loadedVisibility,
    std::uint64_t sceneCap, std::vector<std::string>& warnings, float autoScale) {
  std::shared_ptr<StrandFrames> frames;
  // a groom held in memory under its name (clhair/scene_json.h), else a file
  const std::string named = o.string("strands_file", "");
  const std::string key = loaded.count(named) ? named : strandFileKey(o, base, maxBytes, &frames);
  // the entry's look, from the defaults: entries naming the same file may differ
  AppearanceParams look;
  LodParams lod;
  lod.enabled = true;  // a strand file draws with LOD unless the entry says otherwise
  if (o.has("appearance")) readAppearance(o, o.require("appearance"), look, true);
  if (o.has("lod")) {
    JsonReader l = o.object(o.require("lod"), "lod");
    lod.enabled = l.boolean("enabled", lod.enabled);
    lod.lambda = static_cast<float>(l.number("lambda", lod.lambda, 1e-3, 1e3));
    lod.morphWindow = static_cast<float>(l.number("morph_window", lod.morphWindow, 0.0, 1.0));
    lod.strandsPerPixel =
        static_cast<float>(l.number("strands_per_pixel", lod.strandsPerPixel, 0.0, 1e4));
    l.rejectUnknown({"enabled", "lambda", "morph_window", "strands_per_pixel"});
  }
  const auto cap =
      static_cast<std::uint64_t>(o.integer64("max_strands", static_cast<long long>(sceneCap), 0,
                                             static_cast<long long>(kMaxStrandPoints)));
  // "scale": a number, or "auto" (chosen from the file's roots below)
  const bool scaleAuto = o.has("scale") && o.require("scale").is_string();
  if (scaleAuto && o.string("scale", "") != "auto")
    o.fail("scale", "is \"" + o.string("scale", "") + "\", expected a number or \"auto\"");
  float scale = scaleAuto ? 1.0f : static_cast<float>(o.number("scale", 1.0, 1e-6, 1e6));
  const UpAxis up = readUpAxis(o);
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
    if (scaleAuto) scale = autoScale;
  } else {
    const auto it = loaded.find(key);
    const bool firstRead = it == loaded.end();
    StrandGroom groom = firstRead ? readStrandFile(o, key, maxBytes, warnings) : *it->second;
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
    if (scaleAuto) scale = autoScale;
    groom.children = readChildren(o, scale, lowerExtension(key) == ".tfx");
    const bool capped = cap > 0 && groom.pointCounts.size() > cap;
    if (firstRead && capped) loaded[key] = std::make_shared<const StrandGroom>(groom);
    capStrands(groom, cap);
    shared = std::make_shared<const StrandGroom>(std::move(groom));
    if (firstRead && !capped) loaded[key] = shared;
    variants[variant] = shared;
  }
  GroomInstance g;
  g.name = o.string("name", shared->name);
  g.strands = shared;
  g.strandFrames = frames;
  glm::mat4 placement = o.has("transform")
                            ? readTransform(o, o.require("transform"), &g.transformKeys)
                            : glm::mat4(1.0f);
  g.fileTransform = strandFileTransform(scale, up);
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

float sceneAutoScale(const JsonReader& r, const std::filesystem::path& base, std::uint64_t maxBytes,
                     std::map<std::string, std::shared_ptr<const StrandGroom>>& loaded,
                     std::vector<std::string>& warnings, std::vector<std::string>& notes) {
  if (!r.has("grooms") || !r.require("grooms").is_array()) return 0.0f;
  const nlohmann::json& a = r.require("grooms");
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  std::vector<std::string> files;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!a[i].is_object() || !a[i].contains("strands_file") || !a[i].contains("scale") ||
        a[i]["scale"] != "auto")
      continue;  // anything else is the entry's own reader's to check
    JsonReader o = r.object(a[i], "grooms[" + std::to_string(i) + "]");
    std::shared_ptr<StrandFrames> frames;
    const std::string named = o.string("strands_file", "");
    const std::string key = loaded.count(named) ? named : strandFileKey(o, base, maxBytes, &frames);
    if (std::find(files.begin(), files.end(), key) != files.end()) continue;
    files.push_back(key);
    auto it = loaded.find(key);
    if (it == loaded.end())
      it = loaded
               .emplace(key, std::make_shared<const StrandGroom>(
                                 readStrandFile(o, key, maxBytes, warnings)))
               .first;
    addRootBounds(*it->second, lo, hi);
  }
  if (files.empty()) return 0.0f;
  float extent = 0.0f;
  const float factor = autoScaleFactor(lo, hi, &extent);
  std::string names = std::filesystem::path(files[0]).filename().string();
  for (std::size_t k = 1; k < files.size() && k < 4; ++k)
    names += ", " + std::filesystem::path(files[k]).filename().string();
  if (files.size() > 4) names += ", ...";
  char buf[160];
  std::snprintf(buf, sizeof(buf),
                " by %g: their roots span %g file units together, %g m after scaling",
                static_cast<double>(factor), static_cast<double>(extent),
                static_cast<double>(extent * factor));
  notes.push_back(r.file() + ": grooms: \"scale\": \"auto\" scales " +
                  std::to_string(files.size()) + (files.size() == 1 ? " file (" : " files (") +
                  names + ")" + buf +
                  "; meshes with \"auto\" take the same factor, grooms with a number keep it");
  return factor;
}

}  // namespace clhair::scene_io
