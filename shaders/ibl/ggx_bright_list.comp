#version 450
#extension GL_GOOGLE_include_directive : require
// GGX prefilter, bright-texel list, compute path: one dispatch writes the 2(K + 1) x 1 list
// (renderer/src/ibl/ggx_prefilter.cpp).
#define JANUS_IBL_BRIGHT_LIST 1
#include "ibl/ggx_bright.glsl"

layout(local_size_x = 64) in;
layout(set = 0, binding = JANUS_BINDING_BRIGHT_TARGET, rgba16f) uniform writeonly image2D listTarget;

void main() {
    int column = int(gl_GlobalInvocationID.x);
    if (column >= 2 * (brightParams.w + 1)) return;
    imageStore(listTarget, ivec2(column, 0), listTexel(column));
}
