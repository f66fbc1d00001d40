// test_flag_rules.cpp — the rules every value on the command line meets before any work
// (host/cli/flag_rules.cpp): an empty value is refused with the flag named (`--quality ""`
// used to render as if the flag were absent, `--png-compression ""` as level 0), a number that
// sizes work is within its documented range (`fit-mesh --fibre-width 1e30` used to run for
// minutes, `--error-sample -5` was taken), and a walk over every flag of every subcommand's
// --help with "" and -1: each ends with exit 1 and one line, nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_util.h"

namespace clhair::test {
namespace {

namespace fs = std::filesystem;

std::size_t lineCount(const std::string& text) {
  std::size_t n = 0;
  for (char c : text) n += c == '\n';
  return n + (!text.empty() && text.back() != '\n');
}

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> w;
  for (std::string s; in >> s;) w.push_back(s);
  return w;
}

// One option of a --help listing: its longest name, and whether it takes a value and of which
// CLI11 type (INT, UINT, FLOAT, TEXT; "" for a flag).
struct HelpOption {
  std::string name, type;
};

std::vector<HelpOption> optionsOf(const std::string& help) {
  std::vector<HelpOption> out;
  std::istringstream in(help);
  for (std::string line; std::getline(in, line);) {
    const std::vector<std::string> w = words(line);
    if (w.empty() || w[0].size() < 2 || w[0][0] != '-' || line.rfind("  ", 0) != 0) continue;
    HelpOption o;
    std::stringstream names(w[0]);
    for (std::string n; std::getline(names, n, ',');)
      if (n.size() > o.name.size()) o.name = n;
    if (o.name == "--help" || o.name == "--version") continue;
    if (w.size() > 1) {
      std::string t = w[1];
      t.erase(std::remove_if(t.begin(), t.end(), [](char c) { return c == '[' || c == ']'; }),
              t.end());
      t = t.substr(0, t.find(':'));
      if (t == "INT" || t == "UINT" || t == "FLOAT" || t == "TEXT" || t == "INT64") o.type = t;
    }
    out.push_back(o);
  }
  return out;
}

void writeBytes(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

bool numeric(const std::string& type) {
  return type == "INT" || type == "UINT" || type == "FLOAT" || type == "INT64";
}

// Each subcommand with arguments that reach the end of parsing but no work: inputs that do
// not exist, outputs in the scratch folder.
struct Command {
  std::string name, args;
};

std::vector<Command> commands(const std::string& dir) {
  const std::string in = quote(dir + "/missing");
  return {{"devices", ""},
          {"render", in + ".json -o " + quote(dir + "/out.png")},
          {"groom", "--preset tiny -o " + quote(dir + "/g.json")},
          {"bake-ao", in + ".json -o " + quote(dir + "/ao.json")},
          {"bake-visibility", in + ".json -o " + quote(dir + "/v.clhvis")},
          {"export-strands", in + ".json -o " + quote(dir + "/s.hair")},
          {"compare", in + "a.png " + in + "b.png"},
          {"fit-mesh", in + ".hair -o " + quote(dir + "/m.json")}};
}

TEST(FlagRules, EmptyValuesAreRefusedWithTheFlagNamed) {
  const std::string dir = scratchDir();
  writeBytes(dir + "/scene.json", "{}");
  for (const std::string flag : {"--quality", "--shading", "--shadow-lod", "--encode-threads",
                                 "--png-compression", "--frames", "--temporal"}) {
    SCOPED_TRACE(flag);
    const CommandResult r = runCli("render " + quote(dir + "/scene.json") + " -o " +
                                   quote(dir + "/o.png") + " " + flag + " ''");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(lineCount(r.output), 1u) << r.output;
    const std::string line = onlyErrorLine(r.output);
    EXPECT_NE(line.find(flag), std::string::npos) << line;
    EXPECT_NE(line.find("empty"), std::string::npos) << line;
  }
  EXPECT_FALSE(fs::exists(dir + "/o.png"));
}

// The numbers that size work, refused at parse time: the input does not exist, and the line
// names the flag, not the file (the check came first).
TEST(FlagRules, BoundsOfWorkAtParseTime) {
  const std::string dir = scratchDir();
  const std::string fit =
      "fit-mesh " + quote(dir + "/missing.hair") + " -o " + quote(dir + "/m.json") + " ";
  const struct {
    std::string args, says;
  } cases[] = {
      {fit + "--fibre-width 1e30", "--fibre-width must be 0..1, not 1e30"},
      {fit + "--error-sample -5", "--error-sample must be 0..2147483648, not -5"},
      {fit + "--bundles 16385", "--bundles must be 0..16384"},
      {fit + "--shape-weight -1", "--shape-weight"},
      {"render " + quote(dir + "/s.json") + " -o " + quote(dir + "/o.png") + " --encode-threads -1",
       "--encode-threads must be 0..64, not -1"},
      {"render " + quote(dir + "/s.json") + " -o " + quote(dir + "/o.png") +
           " --png-compression 10",
       "--png-compression must be 0..9"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args);
    const CommandResult r = runCli(c.args);
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(lineCount(r.output), 1u) << r.output;
    EXPECT_NE(onlyErrorLine(r.output).find(c.says), std::string::npos) << r.output;
  }
}

// Every flag of every subcommand (and the global ones) given "" and -1. "" is refused naming
// the flag (but for a flag whose value is optional, where "" is the flag alone); -1 is refused
// naming the flag for every number flag but the two whose check needs the scene (--width, --height:
// the resolution with the scene's other side), and any run ends with exit 1 and one line, writing
// nothing.
TEST(FlagRules, EveryFlagOfEverySubcommandWithEmptyAndMinusOne) {
  const std::string dir = scratchDir();
  const std::set<std::string> checkedWithTheScene = {"render --width", "render --height"};
  std::size_t walked = 0;
  std::vector<HelpOption> global = optionsOf(runCli("--help").output);
  ASSERT_FALSE(global.empty());
  for (const Command& c : commands(dir)) {
    const CommandResult help = runCli(c.name + " --help");
    ASSERT_EQ(help.exitCode, 0) << c.name;
    std::vector<HelpOption> opts = optionsOf(help.output);
    for (const HelpOption& g : global)
      if (c.name == "devices") opts.push_back(g);  // the global options, once
    for (const HelpOption& o : opts) {
      if (o.type.empty() || o.name == "--output" || o.name == "--preset") continue;
      for (const std::string value : {"''", "-1"}) {
        const bool isGlobal = c.name == "devices" &&
                              std::any_of(global.begin(), global.end(),
                                          [&](const HelpOption& g) { return g.name == o.name; });
        const std::string cmd = isGlobal ? o.name + " " + value + " devices"
                                         : c.name + " " + c.args + " " + o.name + " " + value;
        SCOPED_TRACE(cmd);
        const CommandResult r = runCli(cmd);
        ++walked;
        const bool valid = r.exitCode == 0 && r.output.find("clhair: error") == std::string::npos;
        // a flag whose value is optional (render --reference) takes "" as the flag alone: the
        // same outcome as the flag given without a value
        bool optionalValue = false;
        if (value == "''" && r.output.find(o.name) == std::string::npos) {
          const CommandResult alone = runCli(cmd.substr(0, cmd.size() - value.size()));
          optionalValue = alone.exitCode == r.exitCode && alone.output == r.output;
        }
        if ((value == "''" && !optionalValue) || !valid) {
          EXPECT_EQ(r.exitCode, 1) << r.output;
          EXPECT_EQ(lineCount(r.output), 1u) << r.output;
        }
        const std::string line = valid ? std::string() : onlyErrorLine(r.output);
        if (value == "''" && optionalValue) {
          // an empty optional value is the flag alone (--reference: its default method)
        } else if (value == "''") {
          EXPECT_NE(line.find(o.name), std::string::npos) << r.output;
          EXPECT_NE(line.find("empty"), std::string::npos) << r.output;
        } else if (numeric(o.type) && !checkedWithTheScene.count(c.name + " " + o.name)) {
          EXPECT_NE(line.find(o.name), std::string::npos) << r.output;
        }
        for (const auto& e : fs::directory_iterator(dir))
          ADD_FAILURE() << e.path() << " was written";
      }
    }
  }
  EXPECT_GT(walked, 80u) << "the walk found fewer flags than the commands have";
}

}  // namespace
}  // namespace clhair::test
