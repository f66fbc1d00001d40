// defaults.cpp — the sanitizer settings every executable of a -DCLHAIR_SANITIZE=ON build
// starts with, so a test, the CLI it spawns and a run by hand all report the same way
// without ASAN_OPTIONS & co. (those still override these). Linked into the executables
// only in that build (CMakeLists.txt).
//
// Leaks are checked at exit with the suppressions in lsan.supp beside this file (memory
// the OpenCL driver keeps until the process ends, matched by the driver's modules only).
// UBSan findings already abort (-fno-sanitize-recover=undefined); here they also print
// the stack. Stacks are symbolized with CLHAIR_SYMBOLIZER, found when configuring
// (llvm-symbolizer, else binutils' addr2line): Debian's clang-15 runtime looks only for
// llvm-symbolizer-15, which its clang-15 package does not install, and prints bare
// addresses without it. Suppressions match module names, so they work either way.

#ifndef CLHAIR_LSAN_SUPPRESSIONS
#error "CLHAIR_LSAN_SUPPRESSIONS (the path of lsan.supp) must be defined"
#endif
#ifdef CLHAIR_SYMBOLIZER
#define CLHAIR_SYMBOLIZER_OPTION ":external_symbolizer_path=\"" CLHAIR_SYMBOLIZER "\""
#else
#define CLHAIR_SYMBOLIZER_OPTION ""
#endif

extern "C" {

// The runtimes call these before main(); they must not allocate or touch other globals.
const char* __asan_default_options() {
  return "check_initialization_order=1:strict_init_order=1:"
         "detect_stack_use_after_return=1" CLHAIR_SYMBOLIZER_OPTION;
}

const char* __lsan_default_options() {
  return "suppressions=\"" CLHAIR_LSAN_SUPPRESSIONS "\":print_suppressions=0";
}

const char* __ubsan_default_options() { return "print_stacktrace=1" CLHAIR_SYMBOLIZER_OPTION; }

}  // extern "C"
