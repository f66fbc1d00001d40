// flag_rules.cpp — the rules every value given on the `clhair` command line meets before any
// work, in one table: no flag or argument takes an empty value (`--quality "$LEVEL"` with the
// variable unset would otherwise read as the flag left out), and every flag that takes a
// count, a size or a number that sizes work is within its documented range (a negative count
// is refused, not wrapped; `fit-mesh --fibre-width 1e30` never starts). The commands check
// what needs more than a range (one of 1, 2, 4, 8; a scene's groom count; --width and
// --height, whose check names the resolution with the scene's other side) themselves.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "clhair/error.h"
#include "clhair/fit.h"
#include "clhair/progressive.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "groom/visibility_bake.h"
#include "metrics/flip.h"
#include "options.h"

namespace clhair::cli {

namespace {

// The range of one numeric flag of one subcommand.
struct FlagRule {
  const char* command;
  const char* flag;
  double lo, hi;
};

const FlagRule kFlagRules[] = {
    {"render", "--msaa", 1, 8},
    {"render", "--path-events", 1, 1024},
    {"render", "--spp", 1, 65536},
    {"render", "--final-subset", 1, kMaxFinalSubset},
    {"render", "--frames-in-flight", 1, kMaxFramesInFlight},
    {"render", "--encode-threads", 0, 64},
    {"render", "--png-compression", 0, 9},
    {"groom", "--strands", 0, 50000000},
    {"bake-visibility", "--groom", 0, 65535},
    {"bake-visibility", "--rays", 1, 4096},
    {"bake-visibility", "--points-per-cell", 1, 64},
    {"bake-visibility", "--max-events", 1, kMaxEventsLimit},
    {"bake-visibility", "--cell-stride", 1, 1 << 20},
    {"export-strands", "--groom", 0, 65535},
    {"compare", "--ppd", kFlipMinPpd, kFlipMaxPpd},
    {"fit-mesh", "--bundles", 0, kFitMaxBundles},
    {"fit-mesh", "--layers", 0, 64},
    {"fit-mesh", "--fibre-width", 0, 1},
    {"fit-mesh", "--shape-weight", 0, 1000},
    {"fit-mesh", "--seed", 0, 4294967295.0},
    {"fit-mesh", "--error-sample", 0, 2147483648.0},
};

std::string number(double v) {
  char buf[32];
  if (v == std::floor(v) && std::fabs(v) < 1e15)
    std::snprintf(buf, sizeof(buf), "%.0f", v);
  else
    std::snprintf(buf, sizeof(buf), "%g", v);
  return buf;
}

// What the user typed for `o`: its long name, else its short one, else the argument's name.
std::string flagName(const CLI::Option& o) {
  if (!o.get_lnames().empty()) return "--" + o.get_lnames().front();
  if (!o.get_snames().empty()) return "-" + o.get_snames().front();
  return o.get_name();
}

void checkApp(const CLI::App& app, const std::string& command) {
  for (const CLI::Option* o : app.get_options()) {
    // flags (no value) and --reference's optional method: nothing to check
    if (o->count() == 0 || o->get_expected_max() == 0 || o->get_expected_min() == 0) continue;
    const std::string name = flagName(*o);
    for (const std::string& v : o->results()) {
      if (v.empty())
        throw Error((command.empty() ? "" : command + " ") + name +
                    ": the value is empty (an unset variable?); see clhair " +
                    (command.empty() ? "" : command + " ") + "--help");
      for (const FlagRule& r : kFlagRules) {
        if (command != r.command || name != r.flag) continue;
        char* end = nullptr;
        const double x = std::strtod(v.c_str(), &end);
        if (end == v.c_str() || *end != '\0') continue;  // CLI11 refuses what is no number
        if (!(x >= r.lo && x <= r.hi))
          throw Error(name + " must be " + number(r.lo) + ".." + number(r.hi) + ", not " + v);
      }
    }
  }
}

}  // namespace

void checkFlagRules(const CLI::App& app) {
  checkApp(app, "");
  for (const CLI::App* sub : app.get_subcommands()) checkApp(*sub, sub->get_name());
}

}  // namespace clhair::cli
