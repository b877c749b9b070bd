#version 450
// Pixel x of an N x 1 target (N <= 64) samples `tex` at lookups.coords[x] with the level of
// detail lookups.lods[x / 4][x % 4]: 2D (u, v), ARRAY (u, v, layer), CUBE (direction),
// CUBE_ARRAY (direction, cube). The tests choose texel centres, so every lookup has one answer.
layout(set = 0, binding = 0) uniform Lookups {
    vec4 coords[64];
    vec4 lods[16];
} lookups;
#if defined(ARRAY)
layout(set = 0, binding = 1) uniform sampler2DArray tex;
#elif defined(CUBE)
layout(set = 0, binding = 1) uniform samplerCube tex;
#elif defined(CUBE_ARRAY)
layout(set = 0, binding = 1) uniform samplerCubeArray tex;
#else
layout(set = 0, binding = 1) uniform sampler2D tex;
#endif
layout(location = 0) out vec4 outColor;

void main() {
    int i = int(gl_FragCoord.x);
    vec4 c = lookups.coords[i];
    float lod = lookups.lods[i / 4][i % 4];
#if defined(CUBE_ARRAY)
    outColor = textureLod(tex, c, lod);
#elif defined(ARRAY) || defined(CUBE)
    outColor = textureLod(tex, c.xyz, lod);
#else
    outColor = textureLod(tex, c.xy, lod);
#endif
}
