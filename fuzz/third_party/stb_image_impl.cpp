// stb_image / stb_image_write compiled with the fuzz build's instrumentation (fuzz/CMakeLists.txt).
// One translation unit per library: stb's implementation section has no include guard.
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image.h>
#include <stb_image_write.h>
