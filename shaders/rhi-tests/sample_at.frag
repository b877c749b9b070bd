#version 450
// Pixel x of an N x 1 target samples `tex` at coords[x]: (u, v[, w]) and, for the mip-mapped
// kinds, the level of detail in .w; for SHADOW, (u, v, reference). The test chooses exact texel
// centres, so every lookup has one right answer. UINT samples an unsigned-integer texture into
// an unsigned-integer target.
layout(set = 0, binding = 0) uniform Coords { vec4 coords[32]; } lookups;
#if defined(CUBE)
layout(set = 0, binding = 1) uniform samplerCube tex;
#elif defined(VOLUME)
layout(set = 0, binding = 1) uniform sampler3D tex;
#elif defined(SHADOW)
layout(set = 0, binding = 1) uniform sampler2DShadow tex;
#elif defined(UINT)
layout(set = 0, binding = 1) uniform usampler2D tex;
#else
layout(set = 0, binding = 1) uniform sampler2D tex;
#endif
#if defined(UINT)
layout(location = 0) out uvec4 outColor;
#else
layout(location = 0) out vec4 outColor;
#endif

void main() {
    vec4 c = lookups.coords[int(gl_FragCoord.x)];
#if defined(SHADOW)
    outColor = vec4(texture(tex, c.xyz));
#elif defined(UINT)
    outColor = textureLod(tex, c.xy, c.w);
#elif defined(CUBE) || defined(VOLUME)
    outColor = textureLod(tex, c.xyz, c.w);
#else
    outColor = textureLod(tex, c.xy, c.w);
#endif
}
