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
    vec4 cameraPosition;   // homogeneous: w 1 the eye; w 0 the direction towards an orthographic camera (toCamera = xyz - position * w)
    vec4 ambientColor;
    vec4 shadowParams;     // x 1 when directional light 0 casts shadows, y shadow texel size, z normal offset (world)
    ivec4 lightCounts;     // x directional, y local, z 1 = read tile lists (tiled culling), 0 = loop every local light,
                           // w 1 = alpha-masked surfaces give their coverage by alpha (alpha to coverage, multisampled views)
    ivec4 tileGrid;        // x tileSize, y tilesX, z maxLightsPerTile, w tileCount
    DirectionalLight directionalLights[kMaxDirectionalLights];
    vec4 skyParams;        // x 1 = the sky lights the scene (else the ambient colour), y prefiltered cube's last mip, z intensity, w 1 = --debug gi, 2 = --debug shadow
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
    vec4 dielectricSpecular;   // rgb F0, w F90 of the non-metal part (KHR_materials_ior / _specular; glTF's default 0.04, 1)
    ivec4 shading;         // x 1 = unlit (KHR_materials_unlit, or points and lines without normals), y the instance's index
    // Texture t (kTexture*): rows 2t and 2t+1 of its KHR_texture_transform matrix; row 2t's w is
    // the UV set it reads (0: TEXCOORD_0, 1: TEXCOORD_1).
    vec4 textureTransforms[10];
} draw;

const int kTextureBaseColor = 0;
const int kTextureMetallicRoughness = 1;
const int kTextureNormal = 2;
const int kTextureOcclusion = 3;
const int kTextureEmissive = 4;

// Where material texture `slot` (kTexture*) is sampled, from the fragment's two interpolated UV sets. The
// transform is affine, so applying it per fragment equals interpolating transformed vertex UVs.
vec2 materialUv(int slot, vec2 uv0, vec2 uv1) {
    vec4 row0 = draw.textureTransforms[2 * slot];
    vec4 row1 = draw.textureTransforms[2 * slot + 1];
    vec3 uv = vec3(row0.w > 0.5 ? uv1 : uv0, 1.0);
    return vec2(dot(row0.xyz, uv), dot(row1.xyz, uv));
}
#endif

// draw.flags.z: glTF alphaMode.
const int kAlphaModeOpaque = 0;
const int kAlphaModeMask = 1;    // discard below the cutoff (emissiveFactor.w)
const int kAlphaModeBlend = 2;   // the transparent pass: premultiplied alpha out
