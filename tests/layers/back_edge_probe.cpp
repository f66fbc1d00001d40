// back_edge_probe.cpp — a groom-layer file that includes a frame-layer header (a back-edge).
// CTest Layers.ABackEdgeDoesNotCompile compiles it with the groom layer's include path and
// expects the compiler to fail: the layers' include paths are what enforces DESIGN.md's
// "Layers" in the build. Never part of a library.
#include "frame/frame_plan.h"

int main() { return 0; }
