#version 450
// Each output channel comes from a different resource, so a texture bound to the wrong unit
// (or a UBO at the wrong binding point) changes a channel. SEPARATE_SETS moves texB to set 1.
layout(set = 0, binding = 0) uniform Params { vec4 value; } params;
layout(set = 0, binding = 1) uniform sampler2D texA;
#ifdef SEPARATE_SETS
layout(set = 1, binding = 2) uniform sampler2D texB;
#else
layout(set = 0, binding = 2) uniform sampler2D texB;
#endif
layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outColor;

void main() { outColor = vec4(texture(texA, vUv).r, texture(texB, vUv).g, params.value.b, 1.0); }
