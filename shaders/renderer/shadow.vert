#version 450
#extension GL_GOOGLE_include_directive : require
#include "janus/shaders/bindings.h"
// Shadow pass: positions only, into the directional light's clip space (see docs/SHADOWS.md).
layout(set = 0, binding = JANUS_BINDING_SHADOW_PASS) uniform ShadowPass { mat4 lightViewProjection; } pass;
layout(set = 1, binding = JANUS_BINDING_SHADOW_CASTER) uniform ShadowCaster { mat4 world; } caster;

layout(location = 0) in vec3 inPosition;

void main() {
    gl_Position = pass.lightViewProjection * (caster.world * vec4(inPosition, 1.0));
}
