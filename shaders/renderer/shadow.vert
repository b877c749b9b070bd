#version 450
// Shadow pass: positions only, into the directional light's clip space (see docs/SHADOWS.md).
layout(set = 0, binding = 0) uniform ShadowPass { mat4 lightViewProjection; } pass;
layout(set = 1, binding = 1) uniform ShadowCaster { mat4 world; } caster;

layout(location = 0) in vec3 inPosition;

void main() {
    gl_Position = pass.lightViewProjection * (caster.world * vec4(inPosition, 1.0));
}
