#version 450
// Renders mip N of one cube face from mip N - 1: pixel (x, y) = parent texel (2x, 2y) plus
// 1/255 in red. CUBE: `src` is a samplerCube view of mip N - 1 (a mip range, which every
// backend has), looked up at the parent texel's centre direction with nearest filtering.
// Otherwise `src` is a sampler2D view of that face at mip N - 1 (needs texture views).
layout(set = 0, binding = 0) uniform Params { ivec4 face; } params;   // x: the face 0..5
#if defined(CUBE)
layout(set = 0, binding = 1) uniform samplerCube src;
#else
layout(set = 0, binding = 1) uniform sampler2D src;
#endif
layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outColor;

void main() {
    ivec2 parent = 2 * ivec2(gl_FragCoord.xy);
#if defined(CUBE)
    // Inverse of the face table of the Vulkan/GL specs (sc, tc, ma per major axis), |ma| = 1.
    vec2 st = 2.0 * (vec2(parent) + 0.5) / vec2(textureSize(src, 0)) - 1.0;
    float s = st.x, t = st.y;
    vec3 dir;
    switch (params.face.x) {
        case 0: dir = vec3(1.0, -t, -s); break;
        case 1: dir = vec3(-1.0, -t, s); break;
        case 2: dir = vec3(s, 1.0, t); break;
        case 3: dir = vec3(s, -1.0, -t); break;
        case 4: dir = vec3(s, -t, 1.0); break;
        default: dir = vec3(-s, -t, -1.0); break;
    }
    vec4 value = textureLod(src, dir, 0.0);
#else
    vec4 value = texelFetch(src, parent, 0);
#endif
    outColor = value + vec4(1.0 / 255.0, 0.0, 0.0, 0.0);
}
