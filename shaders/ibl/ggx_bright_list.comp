#version 450
#extension GL_GOOGLE_include_directive : require
// GGX prefilter, bright-texel list, compute path: one dispatch writes the (K + 1) x 2 list
// (renderer/src/ibl/ggx_prefilter.cpp).
#define JANUS_IBL_BRIGHT_LIST 1
#include "ibl/ggx_bright.glsl"

layout(local_size_x = 8, local_size_y = 2) in;
layout(set = 0, binding = JANUS_BINDING_BRIGHT_TARGET, rgba16f) uniform writeonly image2D listTarget;

void main() {
    ivec2 id = ivec2(gl_GlobalInvocationID.xy);
    if (id.x > brightParams.w || id.y >= 2) return;
    imageStore(listTarget, id, listTexel(id.x, id.y));
}
