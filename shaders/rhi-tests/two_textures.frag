#version 450
// Each output channel comes from a different resource, so a texture bound to the wrong unit
// (or a UBO at the wrong binding point) changes a channel. SEPARATE_SETS moves texB to set 1;
// HIGH_BINDINGS uses sparse, high binding numbers (9, 14, 15) instead of 0, 1, 2.
#ifdef HIGH_BINDINGS
#define BINDING_PARAMS 9
#define BINDING_A 14
#define BINDING_B 15
#else
#define BINDING_PARAMS 0
#define BINDING_A 1
#define BINDING_B 2
#endif
layout(set = 0, binding = BINDING_PARAMS) uniform Params { vec4 value; } params;
layout(set = 0, binding = BINDING_A) uniform sampler2D texA;
#ifdef SEPARATE_SETS
layout(set = 1, binding = BINDING_B) uniform sampler2D texB;
#else
layout(set = 0, binding = BINDING_B) uniform sampler2D texB;
#endif
layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outColor;

void main() { outColor = vec4(texture(texA, vUv).r, texture(texB, vUv).g, params.value.b, 1.0); }
