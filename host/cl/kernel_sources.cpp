// kernel_sources.cpp — embedded or on-disk kernel text with includes expanded (see header).
#include "cl/kernel_sources.h"

#include <algorithm>
#include <regex>
#include <sstream>

#include "clhair/error.h"
#include "io/regular_file.h"

namespace clhair {

namespace {
constexpr std::uint64_t kMaxSourceBytes = 16u << 20;  // a kernel file of the override tree
}  // namespace

KernelSources::KernelSources(std::string overrideDir) : overrideDir_(std::move(overrideDir)) {}

std::string KernelSources::read(const std::string& name) const {
  for (const EmbeddedFile& f : embeddedKernelFiles()) {
    if (name != f.name) continue;
    if (overrideDir_.empty()) return std::string(f.data, f.size);
    std::string path = overrideDir_ + "/" + f.path;
    try {
      return RegularFile(path, "kernel source").readAll(kMaxSourceBytes);
    } catch (const Error& e) {
      throw Error(std::string("kernel override (CLHAIR_KERNEL_DIR=") + overrideDir_ +
                  "): " + e.what());
    }
  }
  throw Error("kernel source \"" + name + "\" is not part of the build");
}

void KernelSources::expand(const std::string& name, std::vector<std::string>& stack,
                           std::string& out, std::vector<std::string>& included) const {
  if (std::find(stack.begin(), stack.end(), name) != stack.end())
    throw Error("kernel source: include cycle through \"" + name + "\"");
  if (std::find(included.begin(), included.end(), name) != included.end()) return;
  included.push_back(name);
  stack.push_back(name);
  static const std::regex includeLine(R"(^\s*#\s*include\s*"([^"]+)\"\s*$)");
  std::istringstream text(read(name));
  std::string line;
  int lineNo = 0;
  out += "#line 1 \"" + name + "\"\n";
  while (std::getline(text, line)) {
    ++lineNo;
    std::smatch m;
    if (std::regex_match(line, m, includeLine)) {
      expand(m[1].str(), stack, out, included);
      out += "#line " + std::to_string(lineNo + 1) + " \"" + name + "\"\n";
    } else {
      out += line;
      out += '\n';
    }
  }
  stack.pop_back();
}

std::string KernelSources::program(const std::string& name) const {
  std::vector<std::string> stack, included;
  std::string out;
  expand(name, stack, out, included);
  return out;
}

std::uint64_t KernelSources::hashText(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace clhair
