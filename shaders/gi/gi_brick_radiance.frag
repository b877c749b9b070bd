#version 450
#extension GL_GOOGLE_include_directive : require
// Fallback path: one fragment per brick of the brick-radiance texture (gi_brick_radiance.glsl).
#include "gi/gi_brick_radiance.glsl"
layout(location = 0) out vec4 outRadiance;
void main() {
    ivec2 texel = ivec2(gl_FragCoord.xy);
    int brick = texel.y * kGiDataWidth + texel.x;
    if (brick >= relight.counts.x) {
        outRadiance = vec4(0.0);
        return;
    }
    outRadiance = vec4(brickRadiance(brick), 1.0);
}
