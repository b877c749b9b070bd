// tinygltf compiled with the fuzz build's instrumentation (fuzz/CMakeLists.txt).
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
