// kernel_sources.h — where kernel source text comes from.
//
// Kernels and their headers are embedded at build time (cmake/embed_files.cmake). A
// developer override (CLHAIR_KERNEL_DIR, or --kernel-dir) reads the same files from a
// source tree instead, so a kernel edit needs no rebuild. `#include "x.h"` lines are
// resolved here against the same file set and wrapped in #line directives, so a build log
// names the true file and line whichever way the text arrived.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace clhair {

struct EmbeddedFile {
  const char*
      name;  // logical name used by #include: "strands.cl", "subgroup.h", "clhair/gpu_types.h"
  const char* path;  // path relative to the source tree
  const char* data;
  std::size_t size;
  std::uint64_t hash;  // first 64 bits of the file's SHA-256
};

const std::vector<EmbeddedFile>& embeddedKernelFiles();

class KernelSources {
 public:
  // overrideDir empty: embedded files; otherwise the source tree root holding kernels/.
  explicit KernelSources(std::string overrideDir = {});

  // The full text of a top-level kernel file with its includes expanded.
  std::string program(const std::string& name) const;

  // A 64-bit hash of the expanded text (part of the program cache key).
  static std::uint64_t hashText(const std::string& text);

  const std::string& overrideDir() const { return overrideDir_; }

 private:
  std::string read(const std::string& name) const;
  void expand(const std::string& name, std::vector<std::string>& stack, std::string& out,
              std::vector<std::string>& included) const;

  std::string overrideDir_;
};

}  // namespace clhair
