// error_line.h — how the `clhair` command reports a failure: one line "clhair: error: ...",
// its details (a device list, a build log) after it with --verbose or in a log file the line
// names, and the line for a command line that names no known subcommand.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace clhair::cli {

// A message on one line: line breaks become "; ".
std::string oneLine(std::string text);

// Prints the one error line. A message's lines after the first, and `details` (a device list,
// a build log), follow it with --verbose; otherwise they go to a log file in $TMPDIR (or /tmp)
// that the line names, or, when that cannot be written, the line says to use --verbose.
void reportError(const std::string& message, std::string details, bool verbose);

// The first word of the command line where a subcommand belongs, when it names none ("rendr"):
// "unknown subcommand ..." for the error line; "" otherwise.
std::string unknownSubcommand(const CLI::App& app, int argc, char** argv);

}  // namespace clhair::cli
