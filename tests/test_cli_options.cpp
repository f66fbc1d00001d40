// test_cli_options.cpp — the global options (--device, --subgroup, --kernel-dir, --verbose)
// before or after the subcommand: the same command either way, and a global option missing
// its value after the subcommand refused with one error line. No device is drawn on: the
// commands either compare two images or stop at the device's choice.
#include <gtest/gtest.h>

#include <string>

#include "test_util.h"

namespace clhair {
namespace {

using test::CommandResult;
using test::quote;
using test::runCli;

std::size_t lines(const std::string& s) {
  std::size_t n = 0;
  for (char c : s) n += c == '\n';
  return n + (!s.empty() && s.back() != '\n');
}

TEST(CliOptionPlacement, GlobalOptionsWorkAfterTheSubcommand) {
  const std::string png = quote(test::sourceDir() + "/tests/golden/strand_file_head.png");
  // a command that succeeds: --verbose after the subcommand is taken, not refused
  const CommandResult after = runCli("compare " + png + " " + png + " --verbose");
  EXPECT_EQ(after.exitCode, 0) << after.output;
  const CommandResult before = runCli("--verbose compare " + png + " " + png);
  EXPECT_EQ(before.exitCode, 0) << before.output;
  EXPECT_EQ(after.output, before.output);

  // commands refused by the global option's value: the same error line either way, the
  // option's own (naming the value and the choices), not a parse error
  const std::string dir = test::scratchDir();
  const std::string scene = quote(test::assetPath("scenes/default.json"));
  const std::string out = quote(dir + "/out.png");
  const struct {
    std::string option;
    std::string says;
  } cases[] = {{"--subgroup bogus", "local"}, {"--device 97:97", "97"}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.option);
    const CommandResult a = runCli("render " + scene + " -o " + out + " " + c.option);
    const CommandResult b = runCli(c.option + " render " + scene + " -o " + out);
    EXPECT_EQ(a.exitCode, 1) << a.output;
    // the same line either way, but for the log file it names (the process id)
    EXPECT_EQ(a.output.substr(0, a.output.find("(details in")),
              b.output.substr(0, b.output.find("(details in")));
    EXPECT_NE(a.output.find(c.says), std::string::npos) << a.output;
    EXPECT_EQ(a.output.find("not expected"), std::string::npos) << a.output;
  }
}

TEST(CliOptionPlacement, AGlobalOptionWithoutItsValueIsOneErrorLine) {
  const std::string png = quote(test::sourceDir() + "/tests/golden/strand_file_head.png");
  for (const char* option : {"--device", "--subgroup", "--kernel-dir"}) {
    SCOPED_TRACE(option);
    const CommandResult r = runCli("compare " + png + " " + png + " " + option);
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_EQ(r.output.rfind("clhair: error:", 0), 0u) << r.output;
    EXPECT_EQ(lines(r.output), 1u) << r.output;
    EXPECT_NE(r.output.find(option), std::string::npos) << r.output;
  }
}

}  // namespace
}  // namespace clhair
