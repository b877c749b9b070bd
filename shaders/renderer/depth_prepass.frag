#version 450
#extension GL_GOOGLE_include_directive : require
#include "janus/shaders/bindings.h"
// Depth prepass for Forward+ (with forward.vert): writes depth only, but drops alpha-masked
// pixels exactly as forward.frag does, so the tile depth bounds and the forward pass's
// LessOrEqual test see the same surfaces.
#include "renderer/forward_common.glsl"

layout(set = JANUS_SET_MATERIAL, binding = JANUS_BINDING_BASE_COLOR) uniform sampler2D baseColorTexture;

layout(location = 2) in vec2 vUv;
layout(location = 4) in vec2 vUv1;
layout(location = 5) in vec4 vColor;

void main() {
    if (draw.flags.z == kAlphaModeMask) {
        vec4 baseColor = draw.baseColorFactor * vColor * texture(baseColorTexture, materialUv(kTextureBaseColor, vUv, vUv1));
        if (baseColor.a < draw.emissiveFactor.w) discard;
    }
}
