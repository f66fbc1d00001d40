// tinyobj_impl.cpp — tinyobjloader's implementation compiled into the OBJ fuzzer, so
// libFuzzer's coverage and the sanitizers see inside its parser (clhair_core links the
// packaged shared library instead).
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
