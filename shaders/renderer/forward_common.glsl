// Uniform blocks shared by forward.vert, forward.frag and depth_prepass.frag. Mirrors
// FrameUniforms in renderer/src/forward/forward_shading.h and DrawUniforms in renderer/src/core/gpu_scene.cpp (std140); binding numbers are unique
// across sets (see Conventions). Point and spot lights are not here: they live in the light
// array of renderer/light_access.glsl (docs/LIGHTING.md).
#include "janus/shaders/bindings.h"

const int kMaxDirectionalLights = 4;

struct DirectionalLight {
    vec4 direction;        // xyz the way the light travels (unit), w unused
    vec4 colorIntensity;   // rgb colour * intensity (lux), w renderingLayers as uint bits
};

layout(set = JANUS_SET_VIEW, binding = JANUS_BINDING_FRAME_UNIFORMS, std140) uniform FrameUniforms {
    mat4 viewProjection;
    mat4 worldToShadow;    // directional light 0 (the main one): world -> (u, v, depth) of its shadow map
    vec4 cameraPosition;
    vec4 ambientColor;
    vec4 shadowParams;     // x 1 when directional light 0 casts shadows, y shadow texel size, z normal offset (world)
    ivec4 lightCounts;     // x directional, y local, z 1 = read tile lists (tiled culling), 0 = loop every local light
    ivec4 tileGrid;        // x tileSize, y tilesX, z maxLightsPerTile, w tileCount
    DirectionalLight directionalLights[kMaxDirectionalLights];
    vec4 skyParams;        // x 1 = the sky lights the scene (else the ambient colour), y prefiltered cube's last mip, z intensity, w 1 = --debug gi
} frame;

// Passes that draw no meshes (the GI relight) define FRAME_UNIFORMS_ONLY: no per-draw set.
#ifndef FRAME_UNIFORMS_ONLY
layout(set = JANUS_SET_DRAW, binding = JANUS_BINDING_DRAW_UNIFORMS, std140) uniform DrawUniforms {
    mat4 world;
    mat4 normalMatrix;     // inverse transpose of world (upper 3x3 used)
    vec4 baseColorFactor;
    vec4 emissiveFactor;   // rgb emissive, w alpha cutoff
    vec4 materialParams;   // x metallic, y roughness, z normal scale, w occlusion strength
    ivec4 flags;           // x double-sided, y has tangents, z alpha mode (kAlphaMode*), w renderingLayers (uint bits)
} draw;
#endif

// draw.flags.z: glTF alphaMode.
const int kAlphaModeOpaque = 0;
const int kAlphaModeMask = 1;    // discard below the cutoff (emissiveFactor.w)
const int kAlphaModeBlend = 2;   // the transparent pass: premultiplied alpha out
