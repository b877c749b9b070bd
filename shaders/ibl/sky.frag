#version 450
#extension GL_GOOGLE_include_directive : require
#include "janus/shaders/bindings.h"
// The sky background: the sky's radiance along each pixel's view ray, from the background cube
// (as sharp as the sky file, with a box-filtered chain): the implicit level of detail follows the
// pixel's footprint, so a small image averages the sky rather than aliasing it.
layout(set = 0, binding = JANUS_BINDING_SKY_UNIFORMS, std140) uniform SkyUniforms {
    mat4 inverseViewProjection;   // of the view without its translation: clip -> world direction
    vec4 params;                  // x intensity
} sky;
layout(set = 0, binding = JANUS_BINDING_SKY_RADIANCE) uniform samplerCube skyRadiance;

layout(location = 0) in vec2 vNdc;
layout(location = 0) out vec4 outRadiance;

void main() {
    // From the near plane's point to the far plane's: the pixel's ray for either projection (an
    // orthographic view sees the sky along its axis at every pixel, as its rays are parallel).
    vec4 near = sky.inverseViewProjection * vec4(vNdc, 0.0, 1.0);
    vec4 far = sky.inverseViewProjection * vec4(vNdc, 1.0, 1.0);
    vec3 direction = normalize(far.xyz / far.w - near.xyz / near.w);
    vec3 radiance = texture(skyRadiance, direction).rgb * sky.params.x;
    outRadiance = vec4(min(radiance, vec3(65000.0)), 1.0);
}
