#!/usr/bin/env bash
# gpu-check.sh — clhair on an NVIDIA GPU machine that has NVIDIA's OpenCL driver but none of
# clhair's libraries, through ../shared/gpu/bundle.sh (binaries that write images as PPM).
#
#   scripts/gpu-check.sh bundle [OUT]   build Release into ./build-gpu and pack the bundle into
#                                       ./gpu-bundle (both ignored by git); carry gpu-bundle
#   scripts/gpu-check.sh run OUT        on the GPU machine, in the checkout: `clhair devices`, the
#                                       benchmark's table1, throughput and sequences sections and
#                                       the fixed renders below, all into OUT (results.md, logs,
#                                       bench.json, images as .ppm)
#   scripts/gpu-check.sh compare OUT    here: the same renders on this machine's default device
#                                       (PoCL) and `clhair compare` (FLIP, PSNR) against OUT's
#                                       images; appends the table to OUT/compare.md
#
# The fixed renders: the default scene at 1920x1080 (SWR1 + Huang's filter, and MSAA 4), the
# three-light scene, frame 30 of the wind shot and the crowd, each one frame.
# The bundle writes PPM whatever the extension, so its throughput rows time PPM writing, not
# PNG or EXR encoding.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
mode="${1:-}"

renders=(
  "default assets/scenes/default.json --width 1920 --height 1080"
  "default_msaa4 assets/scenes/default.json --width 1920 --height 1080 --msaa 4"
  "three_lights assets/scenes/three_lights.json --width 1920 --height 1080"
  "wind30 assets/scenes/wind.json --width 1920 --height 1080 --frames 30"
  "crowd assets/scenes/crowd.json --width 1920 --height 1080"
)

case "$mode" in
  bundle)
    out="${2:-gpu-bundle}"
    cmake -S . -B build-gpu -DCMAKE_BUILD_TYPE=Release -DCLHAIR_BUILD_TESTS=OFF >/dev/null
    cmake --build build-gpu -j"$(nproc)" --target clhair clhair_bench
    rm -rf "$out"
    bash ../shared/gpu/bundle.sh build-gpu "$out"
    ;;
  run)
    out="${2:?usage: gpu-check.sh run OUT}"
    mkdir -p "$out"
    b="$root/gpu-bundle/run-on-gpu.sh"
    [[ -x "$b" ]] || { echo "gpu-check.sh: no gpu-bundle/run-on-gpu.sh (carry gpu-bundle)" >&2; exit 1; }
    {
      echo "# clhair GPU check, $(date -u +%Y-%m-%d), revision $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
      echo
      "$b" clhair devices
      nvidia-smi --query-gpu=name,driver_version --format=csv 2>/dev/null || true
    } >"$out/results.md" 2>&1
    for r in "${renders[@]}"; do
      read -r name args <<<"$r"
      # shellcheck disable=SC2086
      "$b" clhair render $args -o "$out/$name.####.png" >"$out/$name.log" 2>&1 ||
        echo "render $name failed: $(tail -n1 "$out/$name.log")" >>"$out/results.md"
    done
    "$b" clhair_bench --only table1 --out "$out/table1" >"$out/table1.log" 2>&1 || true
    "$b" clhair_bench --only throughput --out "$out/throughput" >"$out/throughput.log" 2>&1 || true
    "$b" clhair_bench --only sequences --out "$out/sequences" >"$out/sequences.log" 2>&1 || true
    for s in table1 throughput sequences; do
      [[ -f "$out/$s/bench.md" ]] && cat "$out/$s/bench.md" >>"$out/results.md"
    done
    echo "wrote $out/results.md"
    ;;
  compare)
    out="${2:?usage: gpu-check.sh compare OUT}"
    bin="$root/build/clhair"
    [[ -x "$bin" ]] || { echo "gpu-check.sh: build clhair first (scripts/dev.sh demo)" >&2; exit 1; }
    tmp=$(mktemp -d)
    {
      echo "| render | FLIP (mean) | PSNR dB |"
      echo "|---|---|---|"
    } >"$out/compare.md"
    for r in "${renders[@]}"; do
      read -r name args <<<"$r"
      gpu=$(ls "$out/$name".*.ppm 2>/dev/null | head -n1)
      [[ -n "$gpu" ]] || { echo "| $name | (no GPU image) | |" >>"$out/compare.md"; continue; }
      # shellcheck disable=SC2086
      "$bin" render $args -q -o "$tmp/$name.####.png"
      cpu=$(ls "$tmp/$name".*.png | head -n1)
      report=$("$bin" compare "$cpu" "$gpu" 2>&1)
      flip=$(awk '$1 == "FLIP" {print $2}' <<<"$report")
      psnr=$(awk '$1 == "PSNR" {print $2}' <<<"$report")
      echo "| $name | ${flip:-?} | ${psnr:-?} |" >>"$out/compare.md"
    done
    rm -rf "$tmp"
    cat "$out/compare.md"
    ;;
  *)
    echo "usage: scripts/gpu-check.sh bundle [OUT] | run OUT | compare OUT" >&2
    exit 2
    ;;
esac
