#!/usr/bin/env bash
# back_edge_test.sh COMPILER SOURCE_DIR LAYERS_DIR — the build refuses a back-edge between
# layers (CTest Layers.ABackEdgeDoesNotCompile): back_edge_probe.cpp, which includes a frame
# header, compiles with the frame layer's include path (LAYERS_DIR/frame, made by
# CMakeLists.txt) and fails with the groom layer's, which has no frame folder.
set -euo pipefail
cxx=$1 src=$2 layers=$3
probe=$src/tests/layers/back_edge_probe.cpp
flags=(-std=c++17 -fsyntax-only -DCL_HPP_ENABLE_EXCEPTIONS -DCL_HPP_MINIMUM_OPENCL_VERSION=120
       -DCL_HPP_TARGET_OPENCL_VERSION=120 -I"$src/include" -I"$src/kernels/include")
if ! "$cxx" "${flags[@]}" -I"$layers/frame" "$probe"; then
  echo "back_edge_test.sh: the probe does not compile in its own layer (frame)"
  exit 1
fi
if out=$("$cxx" "${flags[@]}" -I"$layers/groom" "$probe" 2>&1); then
  echo "back_edge_test.sh: a groom-layer file including frame/frame_plan.h compiled"
  exit 1
fi
if [[ "$out" != *"frame/frame_plan.h"* ]]; then
  echo "back_edge_test.sh: the groom-layer compile failed for another reason:"
  echo "$out"
  exit 1
fi
echo "back_edge_test.sh: the groom layer cannot include frame/frame_plan.h"
