#include <janus/rhi/rhi.h>

#include "bad_shader_shaders.h"

int main() { return sizeof(bad_shader_shaders::reads_storage_frag) > 0 ? 0 : 1; }
