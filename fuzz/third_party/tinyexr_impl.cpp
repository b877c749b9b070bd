// tinyexr compiled with the fuzz build's instrumentation (fuzz/CMakeLists.txt).
#define TINYEXR_IMPLEMENTATION
#include <tinyexr.h>
