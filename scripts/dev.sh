#!/usr/bin/env bash
# dev.sh — one command from a fresh Debian 12 machine to a result.
#
#   scripts/dev.sh demo   install what is missing, build, render the default scene to clhair-default.png
#   scripts/dev.sh test   install what is missing, build, run the whole test suite; then the
#                         Python package: built into a virtual environment (./build-py/venv)
#                         against ./build's library, its pytest suite run; then, in
#                         a clang ASan + UBSan build (./build-san), a brief libFuzzer run of
#                         the file readers and the host-heavy tests (see below)
#   scripts/dev.sh intel  also install Intel's CPU OpenCL runtime from PyPI into
#                         ./build/intel-ocl (a virtual environment; no system file changes)
#                         and write ./build/intel-ocl/env.sh, which registers it next to
#                         PoCL; `test` then also runs the sub-group and raster tests on it
#
# Packages come from scripts/debian-packages.txt. The build goes to ./build (Release,
# warnings as errors); PoCL's compiled-kernel cache goes to ./build/pocl-cache. `test`
# prints each step's wall and CPU time.
set -euo pipefail
cd "$(dirname "$0")/.."
TIMEFORMAT="dev.sh: %0R s wall, %0U s user + %0S s sys"
mode="${1:-}"
case "$mode" in
  demo | test | intel) ;;
  *)
    echo "usage: scripts/dev.sh demo|test|intel" >&2
    exit 2
    ;;
esac

missing=()
while read -r pkg; do
  [[ -z "$pkg" || "$pkg" == \#* ]] && continue
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
done < scripts/debian-packages.txt
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  sudo_cmd=()
  if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
  "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -qq
  "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

if [[ "$mode" == intel ]]; then
  # Intel's CPU runtime (real sub-groups: the khr and intel backends) in a virtual
  # environment. The loader finds it through OCL_ICD_VENDORS, a folder holding its .icd
  # next to a copy of the system's ones. LD_LIBRARY_PATH must name its lib folder too:
  # clhair links Debian's libtbb.so.12 (through OpenImageIO), and once that soname is
  # loaded the runtime's newer TBB is never opened and the runtime drops its platform
  # silently (clinfo, which links no TBB, lists it either way).
  venv="$PWD/build/intel-ocl"
  mkdir -p build
  command -v python3 >/dev/null || { echo "python3 is needed for the Intel runtime" >&2; exit 1; }
  if [[ ! -x "$venv/bin/pip" ]]; then
    python3 -m venv "$venv" 2>/dev/null || {
      sudo_cmd=()
      if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
      "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends python3-venv
      python3 -m venv "$venv"
    }
  fi
  "$venv/bin/pip" install -q intel-opencl-rt intel-cmplr-lib-rt
  lib=$(ls "$venv"/lib/libintelocl.so* 2>/dev/null | grep -v gdb | head -n1)
  [[ -n "$lib" ]] || { echo "intel-opencl-rt installed no libintelocl.so" >&2; exit 1; }
  mkdir -p "$venv/vendors"
  cp /etc/OpenCL/vendors/*.icd "$venv/vendors/" 2>/dev/null || true
  echo "$lib" >"$venv/vendors/intel-cpu.icd"
  cat >"$venv/env.sh" <<ENV
# source this: Intel's CPU OpenCL runtime next to the system's drivers
export OCL_ICD_VENDORS="$venv/vendors"
export LD_LIBRARY_PATH="$venv/lib\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}"
ENV
  echo "Intel CPU runtime registered: source $venv/env.sh (then clhair devices lists it)"
  exit 0
fi

python_tests() {
  local venv="$PWD/build-py/venv" req=python/requirements-test.txt
  if [[ ! -x "$venv/bin/python" ]]; then
    python3 -m venv "$venv" || { echo "python3 -m venv failed (Debian: python3-venv)" >&2; return 1; }
  fi
  if ! cmp -s "$req" "$venv/requirements-installed.txt"; then
    "$venv/bin/python" -m pip install -q --disable-pip-version-check -r "$req"
    cp "$req" "$venv/requirements-installed.txt"
  fi
  "$venv/bin/python" -m pip install -q --disable-pip-version-check --no-build-isolation --no-deps \
    -C cmake.define.CLHAIR_CORE_BUILD="$PWD/build" .
  (cd python/tests && CLHAIR_CLI="$PWD/../../build/clhair" "$venv/bin/python" -m pytest -q -p no:cacheprovider)
}

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DCLHAIR_WERROR=ON > build-configure.log 2>&1 ||
  { cat build-configure.log; exit 1; }
rm -f build-configure.log
if [[ "$mode" == demo ]]; then
  cmake --build build -j"$jobs" --target clhair   # the renderer only: tests and benchmark are not needed
else
  echo "dev.sh: build (Release)"
  time cmake --build build -j"$jobs"
fi
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-$PWD/build/pocl-cache}"
export CLHAIR_CACHE_DIR="${CLHAIR_CACHE_DIR:-$PWD/build/clhair-cache}"

if [[ "$mode" == demo ]]; then
  ./build/clhair render assets/scenes/default.json -o clhair-default.png
  echo "wrote $PWD/clhair-default.png"
else
  # After the Release suite, a clang build with AddressSanitizer + UndefinedBehaviorSanitizer
  # (./build-san, CLHAIR_SANITIZE: any finding fails its test; leaks inside the OpenCL
  # driver only are suppressed, see cmake/sanitizers/) holds the libFuzzer targets of the
  # file readers (5 s each on their seed corpora) and a sanitized clhair_tests and CLI.
  # It runs the tests whose time goes into host code: the file, scene and OBJ readers, the
  # CLI's refusals, the CPU raster, references (the Embree tracer among them) and image
  # metrics, environment building, and the renderer API end to end on the device. The
  # kernels' own tests (raster, shadows, filter, LOD, sub-groups, cross-compiles, Oclgrind)
  # spend their time in PoCL and LLVM, which are not instrumented, so they run in the
  # Release build only. Every test runs once: the Release run leaves out the ones the
  # sanitized run has (all of them run there when clang-15 is missing), which keeps the
  # whole command's tests near 10 minutes.
  host_tests='^(StrandFile[A-Za-z]*|Mesh|MeshCli|ExplicitScene|Metrics[A-Za-z]*|CpuRaster'
  host_tests+='|Reference|TracedReference'
  host_tests+='|BsdfReference|LodMath|FastMath|Environment(Sh|Errors|Mapping|Sky|Build)|Render'
  host_tests+='|ExplicitMemory|ExplicitRender|Host|Keyframes|AnimatedScene|CageFile'
  host_tests+='|FitSanitized|DiffusionField)\.'
  # Cli.GeneratedPresetGroomRenders (a written preset renders pixel for pixel as the preset
  # in memory) runs in the Release build: in the clang build one pixel of the two differs
  # (with LOD from the screen, and before it with a light's map), which is not a sanitizer
  # finding and was not explained.
  host_tests+='|^Cli\.(Missing|Malformed|Absurd|Zero|HairMeshWith|Unknown|ParseErrors|Devices)'
  host_tests+='|^ExplicitCli\.(Malformed|TrailingBytes|WarnsAbout)|^Fuzz\.'
  sanitize=0
  if command -v clang++-15 >/dev/null; then sanitize=1; else
    echo "clang++-15 not found: no sanitizer and fuzz runs; the Release build runs every test" >&2
  fi
  release_filter=()
  if ((sanitize)); then release_filter=(-E "$host_tests"); fi

  echo "dev.sh: tests (Release)"
  time (cd build && ctest --output-on-failure -j2 --timeout 600 "${release_filter[@]}")
  # The Python package (python/, docs/python.md) in ./build-py/venv: its PyPI requirements
  # (installed again only when python/requirements-test.txt changes), then `pip install .`
  # linking ./build's libclhair_core.a (only the binding's files compile), then pytest; a
  # failing test fails the command.
  echo "dev.sh: Python package and its tests (pytest)"
  time python_tests
  # on Intel's CPU runtime too, when `scripts/dev.sh intel` registered it
  if [[ -f build/intel-ocl/env.sh ]]; then
    (
      # shellcheck disable=SC1091
      source build/intel-ocl/env.sh
      if ./build/clhair devices 2>/dev/null | grep -q "Intel(R) OpenCL"; then
        CLHAIR_DEVICE="Intel(R) OpenCL" ./build/tests/clhair_tests \
          --gtest_filter='*Subgroup*:CpuRaster*:Strands*:*StrandsVsReference*:FastMath*:BinaryCache*:GBuffer*'
      else
        echo "build/intel-ocl/env.sh exists but the Intel runtime does not load: skipped" >&2
      fi
    )
  fi
  if ((sanitize)); then
    CC=clang-15 CXX=clang++-15 cmake -S . -B build-san -DCMAKE_BUILD_TYPE=Release \
      -DCLHAIR_SANITIZE=ON -DCLHAIR_FUZZ=ON -DCLHAIR_FUZZ_SECONDS=5 -DCLHAIR_BUILD_BENCH=OFF \
      > build-san-configure.log 2>&1 || { cat build-san-configure.log; exit 1; }
    rm -f build-san-configure.log
    echo "dev.sh: build (clang, ASan + UBSan, fuzzers)"
    time cmake --build build-san --target clhair_fuzzers clhair clhair_tests -j"$jobs"
    echo "dev.sh: fuzzers and host tests (ASan + UBSan)"
    # not timed here: ctest's own summary stays the last thing printed. A failed test runs
    # once more: LeakSanitizer's stop-the-world tracer can itself crash at exit ("Tracer
    # caught signal 11 ... LeakSanitizer has encountered a fatal error") after every
    # assertion passed, seen once in ExplicitRender.*; a real finding fails both runs.
    (cd build-san && ctest --output-on-failure -j2 --timeout 600 --repeat until-pass:2 \
      -R "$host_tests")
  fi
fi
