// fuzz_util.h — shared plumbing for the libFuzzer targets: the readers take paths, so each
// input is written to a file in a folder private to this fuzzer process (made with
// mkdtemp under $TMPDIR or /tmp, removed at exit), and a failed invariant traps so
// libFuzzer records the input as a crash.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace clhair::fuzz {

inline void removeWorkDir();

// The folder of this process, created on first use and removed at exit.
inline const std::string& workDir() {
  static const std::string dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/clhair-fuzz-" +
                          std::to_string(::getpid()) + "-XXXXXX";
    if (!::mkdtemp(pattern.data())) {
      std::perror("clhair fuzz: mkdtemp");
      std::abort();
    }
    return pattern;
  }();
  // Registered after `dir` is built, so it runs before `dir` is destroyed.
  static const bool cleanup = std::atexit(removeWorkDir) == 0;
  (void)cleanup;
  return dir;
}

inline void removeWorkDir() {
  std::error_code ec;
  std::filesystem::remove_all(workDir(), ec);
}

// Writes the input to workDir()/name and returns the path.
inline std::string writeInput(const std::uint8_t* data, std::size_t size, const std::string& name) {
  const std::string path = workDir() + "/" + name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out) {
    std::perror(("clhair fuzz: cannot write " + path).c_str());
    std::abort();
  }
  return path;
}

// A broken invariant: print it and trap, so the input is saved as a crash.
#define CLHAIR_FUZZ_CHECK(cond)                                                         \
  do {                                                                                  \
    if (!(cond)) {                                                                      \
      std::fprintf(stderr, "%s:%d: invariant failed: %s\n", __FILE__, __LINE__, #cond); \
      __builtin_trap();                                                                 \
    }                                                                                   \
  } while (0)

}  // namespace clhair::fuzz
