// error_line.cpp — the one error line of the `clhair` command (error_line.h): a message folded
// onto one line, its details after it (--verbose) or in a log file in $TMPDIR, and the line
// for an unknown subcommand, which lists the known ones.
#include "error_line.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include "clhair/error.h"
#include "io/safe_write.h"

namespace clhair::cli {

std::string oneLine(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  for (std::size_t p = text.find('\n'); p != std::string::npos; p = text.find('\n', p))
    text.replace(p, 1, "; ");
  return text;
}

void reportError(const std::string& message, std::string details, bool verbose) {
  const std::size_t nl = message.find('\n');
  std::string line = message.substr(0, nl);
  if (nl != std::string::npos)
    details = message.substr(nl + 1) + (details.empty() ? "" : "\n") + details;
  while (!details.empty() && (details.back() == '\n' || details.back() == ' ')) details.pop_back();
  if (details.empty()) {
    std::fprintf(stderr, "clhair: error: %s\n", oneLine(line).c_str());
    return;
  }
  if (verbose) {
    std::fprintf(stderr, "clhair: error: %s\n%s\n", oneLine(line).c_str(), details.c_str());
    return;
  }
  const char* tmp = std::getenv("TMPDIR");
  const std::string log = std::string(tmp && *tmp ? tmp : "/tmp") + "/clhair-error-" +
                          std::to_string(::getpid()) + ".log";
  std::string where;
  try {
    writeFileAtomically(log, "clhair: error: " + line + "\n" + details + "\n");
    where = "details in " + log;
  } catch (const Error&) {
    where = "details with --verbose";
  }
  std::fprintf(stderr, "clhair: error: %s (%s)\n", oneLine(line).c_str(), where.c_str());
}

std::string unknownSubcommand(const CLI::App& app, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--device" || a == "--subgroup" || a == "--kernel-dir") {
      ++i;  // the option's value
      continue;
    }
    if (!a.empty() && a[0] == '-') continue;
    std::string known;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
      if (sub->get_name() == a) return {};
      known += (known.empty() ? "" : ", ") + sub->get_name();
    }
    return "unknown subcommand \"" + a + "\"; expected one of: " + known;
  }
  return {};
}

}  // namespace clhair::cli
