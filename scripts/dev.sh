#!/usr/bin/env bash
# dev.sh — one command from a fresh Debian 12 machine to a result.
#
#   scripts/dev.sh demo   install what is missing, build, render the default scene to clhair-default.png
#   scripts/dev.sh test   install what is missing, build, run the whole test suite, then a
#                         brief libFuzzer run of the file readers (clang build in ./build-fuzz)
#
# Packages come from scripts/debian-packages.txt. The build goes to ./build (Release,
# warnings as errors); PoCL's compiled-kernel cache goes to ./build/pocl-cache.
set -euo pipefail
cd "$(dirname "$0")/.."
mode="${1:-}"
case "$mode" in
  demo | test) ;;
  *)
    echo "usage: scripts/dev.sh demo|test" >&2
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

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DCLHAIR_WERROR=ON > build-configure.log 2>&1 ||
  { cat build-configure.log; exit 1; }
rm -f build-configure.log
if [[ "$mode" == demo ]]; then
  cmake --build build -j"$jobs" --target clhair   # the renderer only: tests and benchmark are not needed
else
  cmake --build build -j"$jobs"
fi
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-$PWD/build/pocl-cache}"

if [[ "$mode" == demo ]]; then
  ./build/clhair render assets/scenes/default.json -o clhair-default.png
  echo "wrote $PWD/clhair-default.png"
else
  (cd build && ctest --output-on-failure -j2 --timeout 600)
  # a brief libFuzzer run of every file reader on its seed corpus (clang build, 10 s each)
  if command -v clang++-15 >/dev/null; then
    CC=clang-15 CXX=clang++-15 cmake -S . -B build-fuzz -DCLHAIR_FUZZ=ON -DCLHAIR_BUILD_BENCH=OFF \
      > build-fuzz-configure.log 2>&1 || { cat build-fuzz-configure.log; exit 1; }
    rm -f build-fuzz-configure.log
    cmake --build build-fuzz --target clhair_fuzzers -j"$jobs"
    (cd build-fuzz && ctest -L fuzz --output-on-failure --timeout 300)
  else
    echo "clang++-15 not found: skipping the fuzz run" >&2
  fi
fi
