// test_cross_compile.cpp — every kernel, with each GPU sub-group backend selected, compiles
// with Debian's clang-15 for the devices CI does not have (NVIDIA PTX, AMD GCN/RDNA, SPIR
// for Intel and other KHR-subgroup drivers).
//
// Inputs: every kernels/*.cl file of the source tree, found at run time so a new kernel is
// covered without touching this file, crossed with one row per target/backend. Outputs:
// the compiled objects under the test's scratch folder. Each case asserts clang's exit code
// 0 with -Wall -Werror; for the nvptx rows, a kernel that uses the sub-group layer must
// also keep its inline-asm shuffles in the PTX (proof that `__asm__ volatile` survived
// optimisation). Skipped, with the reason, when clang-15 is not on PATH.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "test_util.h"

namespace clhair::test {
namespace {

namespace fs = std::filesystem;

// One target/backend combination; `output` is the clang output-mode flags.
struct CrossRow {
  const char* name;      // short identifier, part of the test name
  const char* flags;     // target, -cl-std and -D options
  const char* extraExt;  // appended to the always-on 64-bit atomics extensions, or ""
  const char* output;    // "-S" (PTX text), "-c" (object) or "-c -emit-llvm"
  const char* suffix;    // output file extension
  // For PTX: the shuffle instruction the sub-group layer must leave in the output, and one
  // it must not (the other PTX flavour), or nullptr.
  const char* ptxMust;
  const char* ptxMustNot;
  // Whether the row needs clang's full opencl-c.h: only for cl_intel_subgroups, which clang
  // 15's builtin tables (the default, -fdeclare-opencl-builtins) lack. Parsing the header
  // cost every compile 0.15-0.2 s, a quarter of the suite's 130 s of cross-compiles.
  bool fullHeader = false;
};

const CrossRow kRows[] = {
    {"nvptx_sm70",
     "-target nvptx64-nvidia-nvcl -march=sm_70 -cl-std=CL1.2 -DSG_BACKEND=3 -DSG_SIZE=32", "", "-S",
     "ptx", "shfl.sync.", nullptr},
    {"nvptx_sm60_legacy",
     "-target nvptx64-nvidia-nvcl -march=sm_60 -cl-std=CL1.2 -DSG_BACKEND=3 -DSG_PTX_LEGACY_SHFL=1 "
     "-DSG_SIZE=32",
     "", "-S", "ptx", "shfl.", "shfl.sync"},
    {"amd_gfx1030",
     "-target amdgcn-amd-amdhsa -mcpu=gfx1030 -nogpulib -cl-std=CL1.2 -DSG_BACKEND=4 -DSG_SIZE=32",
     "", "-c", "o", nullptr, nullptr},
    {"amd_gfx906_wave64",
     "-target amdgcn-amd-amdhsa -mcpu=gfx906 -nogpulib -cl-std=CL1.2 -DSG_BACKEND=4 -DSG_SIZE=32",
     "", "-c", "o", nullptr, nullptr},
    {"spir64_khr", "-target spir64 -cl-std=CL3.0 -DSG_BACKEND=1 -DSG_SIZE=32",
     "+cl_khr_subgroups,+__opencl_c_subgroups,+cl_khr_subgroup_shuffle_relative", "-c -emit-llvm",
     "bc", nullptr, nullptr},
    {"spir64_intel",
     "-target spir64 -cl-std=CL1.2 -DSG_BACKEND=2 -DSG_INTEL_REQD_SIZE=1 -DSG_SIZE=32",
     "+cl_intel_subgroups", "-c -emit-llvm", "bc", nullptr, nullptr, true},
    {"spir64_local", "-target spir64 -cl-std=CL1.2 -DSG_BACKEND=0 -DSG_SIZE=32", "",
     "-c -emit-llvm", "bc", nullptr, nullptr},
    // the CPU mapping: one lane per strand, several strands per work-group
    {"spir64_single", "-target spir64 -cl-std=CL1.2 -DSG_BACKEND=5 -DSG_SIZE=1 -DSG_STRANDS=32", "",
     "-c -emit-llvm", "bc", nullptr, nullptr},
    {"nvptx_single",
     "-target nvptx64-nvidia-nvcl -march=sm_70 -cl-std=CL1.2 -DSG_BACKEND=5 -DSG_SIZE=1 "
     "-DSG_STRANDS=32",
     "", "-S", "ptx", nullptr, nullptr},
};

// kernels/*.cl of the source tree, sorted so test names are stable.
std::vector<std::string> kernelFiles() {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(fs::path(sourceDir()) / "kernels", ec))
    if (e.is_regular_file() && e.path().extension() == ".cl")
      out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

bool haveClang15() { return runCommand("command -v clang-15 >/dev/null").exitCode == 0; }

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

using CrossParam = std::tuple<std::string, int>;  // kernel file name, row index

class CrossCompile : public ::testing::TestWithParam<CrossParam> {};

// Compiles kernels/<file> for `row` with `defines` added; returns the output path.
fs::path compileKernel(const std::string& file, const CrossRow& row, const std::string& defines) {
  const fs::path src = fs::path(sourceDir()) / "kernels" / file;
  const fs::path out = fs::path(scratchDir()) / (fs::path(file).stem().string() + "." + row.suffix);

  std::string ext = "+cl_khr_int64_base_atomics,+cl_khr_int64_extended_atomics";
  if (*row.extraExt) ext += std::string(",") + row.extraExt;
  // clang 15 declares OpenCL builtins from its TableGen tables, which lack
  // cl_intel_subgroups; for that row, -cl-no-stdinc -finclude-default-header pulls in the full
  // opencl-c.h, which declares every extension's builtins behind its -cl-ext macro.
  const std::string header =
      row.fullHeader ? "-cl-no-stdinc -Xclang -finclude-default-header " : "";
  std::string cmd = "clang-15 -x cl " + header + std::string("-I") +
                    quote(sourceDir() + "/kernels/common") + " -I" +
                    quote(sourceDir() + "/kernels/include") +
                    " -Wall -Werror -O2 -Xclang -cl-ext=" + ext + " " + row.flags + " " + defines +
                    " " + row.output + " -o " + quote(out.string()) + " " + quote(src.string());
  CommandResult r = runCommand(cmd);
  EXPECT_EQ(r.exitCode, 0) << "command: " << cmd << "\n--- clang output ---\n" << r.output;
  EXPECT_TRUE(fs::exists(out)) << out << " was not written";
  return out;
}

TEST_P(CrossCompile, BuildsWithClang15) {
  if (!haveClang15()) GTEST_SKIP() << "clang-15 is not on PATH (Debian: apt install clang-15)";
  const std::string& file = std::get<0>(GetParam());
  const CrossRow& row = kRows[std::get<1>(GetParam())];
  const fs::path src = fs::path(sourceDir()) / "kernels" / file;
  const fs::path out = compileKernel(file, row, "");
  if (::testing::Test::HasFailure()) return;

  if (row.ptxMust && readFile(src).find("SG_DECLARE") != std::string::npos) {
    std::string ptx = readFile(out);
    EXPECT_NE(ptx.find(row.ptxMust), std::string::npos)
        << file << " uses the sub-group layer but its PTX (" << out << ") holds no \""
        << row.ptxMust << "\": the inline-asm shuffles were lost";
    if (row.ptxMustNot) {
      EXPECT_EQ(ptx.find(row.ptxMustNot), std::string::npos)
          << out << " holds \"" << row.ptxMustNot
          << "\" although this row selects the other PTX shuffle";
    }
  }
}

std::string paramName(const ::testing::TestParamInfo<CrossParam>& info) {
  std::string name =
      fs::path(std::get<0>(info.param)).stem().string() + "_" + kRows[std::get<1>(info.param)].name;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(Kernels, CrossCompile,
                         ::testing::Combine(::testing::ValuesIn(kernelFiles()),
                                            ::testing::Range(0,
                                                             static_cast<int>(std::size(kRows)))),
                         paramName);

// The compile-time variants the host builds besides the default one: the strand kernels'
// deep-opacity pass, raster counters and every MSAA count; the shading and compositing
// resolve of MSAA 8; the coverage raster and its shading.
struct Variant {
  const char* file;
  const char* defines;
  const char* name;
};
const Variant kVariants[] = {
    {"strands.cl", "-DCLH_RASTER_OPACITY=1", "opacity"},
    {"strands.cl", "-DCLH_MSAA=2 -DCLH_RASTER_STATS=1", "msaa2_stats"},
    {"strands.cl", "-DCLH_MSAA=8", "msaa8"},
    {"strands_explicit.cl", "-DCLH_RASTER_OPACITY=1", "opacity"},
    {"strands_explicit.cl", "-DCLH_MSAA=4", "msaa4"},
    {"shade.cl", "-DCLH_MSAA=8", "msaa8"},
    {"composite.cl", "-DCLH_MSAA=8", "msaa8"},
    {"strands.cl", "-DCLH_RASTER_COVER=1", "coverage"},
    {"strands_explicit.cl", "-DCLH_RASTER_COVER=1", "coverage"},
    {"shade.cl", "-DCLH_RASTER_COVER=1", "coverage"},
};

class CrossCompileVariant : public ::testing::TestWithParam<std::tuple<int, int>> {};

TEST_P(CrossCompileVariant, BuildsWithClang15) {
  if (!haveClang15()) GTEST_SKIP() << "clang-15 is not on PATH (Debian: apt install clang-15)";
  const Variant& v = kVariants[std::get<0>(GetParam())];
  compileKernel(v.file, kRows[std::get<1>(GetParam())], v.defines);
}

INSTANTIATE_TEST_SUITE_P(
    Variants, CrossCompileVariant,
    ::testing::Combine(::testing::Range(0, static_cast<int>(std::size(kVariants))),
                       ::testing::Values(0, 2, 4)),  // nvptx, amd, spir64 khr
    [](const ::testing::TestParamInfo<std::tuple<int, int>>& info) {
      const Variant& v = kVariants[std::get<0>(info.param)];
      std::string name = fs::path(v.file).stem().string() + "_" + v.name + "_" +
                         kRows[std::get<1>(info.param)].name;
      for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return name;
    });

}  // namespace
}  // namespace clhair::test
