#version 450
#extension GL_GOOGLE_include_directive : require
// The GI bake's G-buffer (docs/GI.md, "Bake"): one shader for every material, four RGBA16F
// targets of a probe's cube face, drawn with forward.vert and no face culling:
//   0: diffuse albedo (base colour x (1 - metallic)), distance from the probe (cleared to -1: sky)
//   1: the normal of the side seen, +1 when that side is a front face (or the material is
//      double-sided), -1 for a back face (the probe looks at the inside of something)
//   2: emission, the instance's index mod 2048
//   3: the normal of the triangle's plane on the side seen (the relight counts no light from
//      below that plane where the shading normal leans away from it, as forward shading), the
//      instance's index / 2048: the bake looks up its rendering layers (half floats hold these
//      integers exactly; a 32-bit layer mask they would not)
#include "renderer/forward_common.glsl"
#include "renderer/face_normal.glsl"

layout(set = JANUS_SET_MATERIAL, binding = JANUS_BINDING_BASE_COLOR) uniform sampler2D baseColorTexture;
layout(set = JANUS_SET_MATERIAL, binding = JANUS_BINDING_METALLIC_ROUGHNESS) uniform sampler2D metallicRoughnessTexture;
layout(set = JANUS_SET_MATERIAL, binding = JANUS_BINDING_EMISSIVE) uniform sampler2D emissiveTexture;

layout(location = 0) in vec3 vWorldPosition;
layout(location = 1) in vec3 vNormal;
layout(location = 2) in vec2 vUv;
layout(location = 3) in vec4 vTangent;
layout(location = 4) in vec2 vUv1;
layout(location = 5) in vec4 vColor;

layout(location = 0) out vec4 outAlbedoDistance;
layout(location = 1) out vec4 outNormalFacing;
layout(location = 2) out vec4 outEmission;
layout(location = 3) out vec4 outFaceNormal;

void main() {
    // Every lookup before the discard: a discarded neighbour leaves the quad's derivatives, and so
    // the implicit level of detail, undefined (forward.frag says more).
    vec4 baseColorSample = texture(baseColorTexture, materialUv(kTextureBaseColor, vUv, vUv1));
    float metallicSample = texture(metallicRoughnessTexture, materialUv(kTextureMetallicRoughness, vUv, vUv1)).b;
    vec3 emissiveSample = texture(emissiveTexture, materialUv(kTextureEmissive, vUv, vUv1)).rgb;
    vec3 positionDx = dFdx(vWorldPosition), positionDy = dFdy(vWorldPosition);
    vec4 baseColor = draw.baseColorFactor * vColor * baseColorSample;
    if (draw.flags.z == kAlphaModeMask && baseColor.a < draw.emissiveFactor.w) discard;
    float metallic = clamp(draw.materialParams.x * metallicSample, 0.0, 1.0);
    vec3 toSurface = vWorldPosition - frame.cameraPosition.xyz;
    float lengthSq = dot(vNormal, vNormal);
    vec3 normal = lengthSq > 1e-24 ? normalize(vNormal) : -normalize(toSurface);
    if (!gl_FrontFacing) normal = -normal;
    bool front = gl_FrontFacing || draw.flags.x != 0;
    outAlbedoDistance = vec4(clamp(baseColor.rgb, 0.0, 1.0) * (1.0 - metallic), length(toSurface));
    outNormalFacing = vec4(normal, front ? 1.0 : -1.0);
    int instance = draw.shading.y;
    outFaceNormal = vec4(faceNormal(positionDx, positionDy, -toSurface, normal), float(instance / 2048));
    vec3 emission = draw.emissiveFactor.rgb * emissiveSample;
    if (draw.shading.x != 0) {
        // Unlit: the surface shows its base colour whatever lights it, so to the volume it emits
        // that colour and reflects nothing.
        outAlbedoDistance.rgb = vec3(0.0);
        emission = baseColor.rgb;
    }
    outEmission = vec4(min(mix(emission, vec3(0.0), isnan(emission)), vec3(65000.0)), float(instance % 2048));
}
