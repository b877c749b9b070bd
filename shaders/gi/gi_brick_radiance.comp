#version 450
#extension GL_GOOGLE_include_directive : require
// Compute path: one invocation per brick (gi_brick_radiance.glsl).
#include "gi/gi_brick_radiance.glsl"
layout(local_size_x = 64) in;
layout(set = 0, binding = JANUS_BINDING_GI_TARGET, rgba32f) uniform writeonly highp image2D brickRadianceImage;
void main() {
    int brick = int(gl_GlobalInvocationID.x);
    if (brick >= relight.counts.x) return;
    imageStore(brickRadianceImage, ivec2(brick % kGiDataWidth, brick / kGiDataWidth), vec4(brickRadiance(brick), 1.0));
}
