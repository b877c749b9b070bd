#version 450
#extension GL_GOOGLE_include_directive : require
#include "janus/shaders/bindings.h"
// Forward PBR (glTF metallic-roughness): GGX distribution, height-correlated Smith visibility,
// Schlick Fresnel, Lambert diffuse. Writes linear radiance to the RGBA16F HDR target.
// Directional lights come from the frame uniforms; point and spot lights from the light array,
// either all of them (naive) or the current tile's list (Forward+). One loop serves both, so a
// tile list that holds every light that reaches the pixel gives the naive image bit for bit.
#include "renderer/forward_common.glsl"
#include "renderer/light_access.glsl"
#include "renderer/shadow_sampling.glsl"
#include "renderer/sky_access.glsl"
#include "renderer/probe_access.glsl"
#include "gi/gi_access.glsl"
#include "renderer/face_normal.glsl"

layout(set = JANUS_SET_VIEW, binding = JANUS_BINDING_SHADOW_MAP) uniform sampler2DShadow shadowMap;

layout(set = JANUS_SET_MATERIAL, binding = JANUS_BINDING_BASE_COLOR) uniform sampler2D baseColorTexture;          // sRGB texture: decoded by the sampler
layout(set = JANUS_SET_MATERIAL, binding = JANUS_BINDING_METALLIC_ROUGHNESS) uniform sampler2D metallicRoughnessTexture;  // G roughness, B metallic
layout(set = JANUS_SET_MATERIAL, binding = JANUS_BINDING_NORMAL) uniform sampler2D normalTexture;
layout(set = JANUS_SET_MATERIAL, binding = JANUS_BINDING_OCCLUSION) uniform sampler2D occlusionTexture;          // R occlusion
layout(set = JANUS_SET_MATERIAL, binding = JANUS_BINDING_EMISSIVE) uniform sampler2D emissiveTexture;

layout(location = 0) in vec3 vWorldPosition;
layout(location = 1) in vec3 vNormal;
layout(location = 2) in vec2 vUv;
layout(location = 3) in vec4 vTangent;
layout(location = 4) in vec2 vUv1;
layout(location = 5) in vec4 vColor;

layout(location = 0) out vec4 outRadiance;

const float PI = 3.14159265358979;

// 1 - NoH^2 as |n x h|^2: for a near-mirror (alpha^2 ~ 4e-6) at the highlight's peak, 1 - NoH^2
// computed from NoH loses most of its bits in fp32, and two drivers' roundings then give peaks
// percent apart (Filament computes D the same way for the same reason).
float distributionGGX(float NoH, vec3 n, vec3 h, float alpha) {
    float a2 = alpha * alpha;
    vec3 nxh = cross(n, h);
    float f = NoH * NoH * a2 + dot(nxh, nxh);
    return a2 / (PI * f * f);
}

// Height-correlated Smith G divided by 4 NoL NoV (Heitz 2014).
float visibilitySmithGGXCorrelated(float NoV, float NoL, float alpha) {
    float a2 = alpha * alpha;
    float ggxV = NoL * sqrt(NoV * NoV * (1.0 - a2) + a2);
    float ggxL = NoV * sqrt(NoL * NoL * (1.0 - a2) + a2);
    return 0.5 / max(ggxV + ggxL, 1e-6);
}

vec3 fresnelSchlick(vec3 f0, float f90, float VoH) {
    float f = pow(1.0 - VoH, 5.0);
    return f0 + (vec3(f90) - f0) * f;
}

struct Surface {
    vec3 normal;
    vec3 view;
    vec3 diffuseColor;
    vec3 f0;
    float f90;             // 1 but for dielectrics with KHR_materials_specular
    float alpha;
};

// normalize() of a zero vector is NaN, and NaN would slip through later min/max clamps (drivers
// differ on which operand they return): a zero vector takes a defined fallback instead.
vec3 safeNormalize(vec3 v, vec3 fallback) {
    float lengthSq = dot(v, v);
    return lengthSq > 1e-24 ? normalize(v) : fallback;
}

// Outgoing radiance for light arriving along -lightDirection with irradiance `irradiance`
// at normal incidence.
vec3 shade(Surface s, vec3 toLight, vec3 irradiance) {
    float NoL = clamp(dot(s.normal, toLight), 0.0, 1.0);
    if (NoL <= 0.0) return vec3(0.0);
    vec3 h = safeNormalize(toLight + s.view, s.normal);   // zero only for light exactly against the view
    float NoV = clamp(abs(dot(s.normal, s.view)), 1e-4, 1.0);
    float NoH = clamp(dot(s.normal, h), 0.0, 1.0);
    float VoH = clamp(dot(s.view, h), 0.0, 1.0);
    vec3 F = fresnelSchlick(s.f0, s.f90, VoH);
    vec3 specular = F * (distributionGGX(NoH, s.normal, h, s.alpha) * visibilitySmithGGXCorrelated(NoV, NoL, s.alpha));
    vec3 diffuse = (vec3(1.0) - F) * s.diffuseColor / PI;
    return (diffuse + specular) * irradiance * NoL;
}

// Radiance can reach fp16's maximum (65504) and turn into Inf there; the HDR target holds less.
const float kMaxRadiance = 65000.0;

// One point or spot light (light_access.glsl), if it lights the mesh's rendering layers.
vec3 shadeLocalLight(Surface s, vec3 worldPosition, int index, uint meshLayers) {
    LocalLightSample light = localLightIrradiance(index, worldPosition);
    if ((light.layers & meshLayers) == 0u) return vec3(0.0);
    return shade(s, light.toLight, light.irradiance);
}

// Writes the fragment's radiance with `alpha`: the base colour's alpha for alphaMode BLEND (the
// transparent pass, docs/LIGHTING.md "Transparent surfaces": coverage, the output premultiplied
// and blended as One, OneMinusSrcAlpha); for MASK with alpha to coverage, the share of the
// pixel's samples the (unblended) radiance goes to; else 1, opaque.
void writeRadiance(vec3 radiance, float alpha) {
    // Whatever went wrong upstream, no NaN reaches the target (min() would not stop it).
    radiance = mix(radiance, vec3(0.0), isnan(radiance));
    bool blended = draw.flags.z == kAlphaModeBlend;
    alpha = clamp(alpha, 0.0, 1.0);
    outRadiance = vec4(min(radiance, vec3(kMaxRadiance)) * (blended ? alpha : 1.0), alpha);
}

void main() {
    // Every material lookup happens here, before the alpha test's discard and outside any branch:
    // implicit-LOD lookups take their level from the 2x2 quad's derivatives, which a discarded or
    // diverged neighbour leaves undefined (SPIR-V OpKill). NVIDIA's GL driver then sampled mip 0
    // at alpha-mask edges (issue 10); tests/rhi/shader_lint_test.cpp keeps every shader to this.
    vec4 baseColorSample = texture(baseColorTexture, materialUv(kTextureBaseColor, vUv, vUv1));
    vec4 metallicRoughness = texture(metallicRoughnessTexture, materialUv(kTextureMetallicRoughness, vUv, vUv1));
    vec3 normalSample = texture(normalTexture, materialUv(kTextureNormal, vUv, vUv1)).xyz;
    float occlusionSample = texture(occlusionTexture, materialUv(kTextureOcclusion, vUv, vUv1)).r;
    vec3 emissiveSample = texture(emissiveTexture, materialUv(kTextureEmissive, vUv, vUv1)).rgb;
    // The triangle's own plane, for the irradiance volume (faceNormal), here for the same reason.
    vec3 positionDx = dFdx(vWorldPosition), positionDy = dFdy(vWorldPosition);

    vec4 baseColor = draw.baseColorFactor * vColor * baseColorSample;
    // Before any discard, as the lookups: the quad's four lanes must all be alive.
    float alphaWidth = fwidth(baseColor.a);
    // What writeRadiance writes as alpha (see there).
    float outputAlpha = draw.flags.z == kAlphaModeBlend ? baseColor.a : 1.0;
    if (draw.flags.z == kAlphaModeMask) {
        if (frame.lightCounts.w != 0) {
            // Alpha to coverage (docs/LIGHTING.md, "Anti-aliasing"): the cut-off as a ramp one
            // pixel wide (alpha's change across the pixel), so the cut-out's edge covers samples
            // as a triangle's edge would and its inside stays opaque however soft the alpha is.
            outputAlpha = clamp((baseColor.a - draw.emissiveFactor.w) / max(alphaWidth, 1e-4) + 0.5, 0.0, 1.0);
            if (outputAlpha <= 0.0) discard;
        } else if (baseColor.a < draw.emissiveFactor.w) {
            discard;
        }
    }
    if (draw.shading.x != 0) {
        // Unlit (KHR_materials_unlit; points and lines without normals): the base colour is the radiance.
        writeRadiance(baseColor.rgb, outputAlpha);
        return;
    }
    float metallic = clamp(draw.materialParams.x * metallicRoughness.b, 0.0, 1.0);
    float perceptualRoughness = clamp(draw.materialParams.y * metallicRoughness.g, 0.045, 1.0);

    // A double-sided face seen from behind shades (and offsets its shadow lookup) with the
    // normal of the side that is seen.
    bool flipped = draw.flags.x != 0 && !gl_FrontFacing;
    vec3 geometricNormal = flipped ? -vNormal : vNormal;
    vec3 toCamera = safeNormalize(frame.cameraPosition.xyz - vWorldPosition * frame.cameraPosition.w, vec3(0.0, 0.0, 1.0));
    // A zero normal (file data, a degenerate transform) faces the camera rather than going NaN.
    vec3 normal = safeNormalize(vNormal, toCamera);
    if (flipped) normal = -normal;
    if (draw.flags.y != 0) {
        // Normal map in tangent space; the bitangent's sign comes from the tangent's w.
        // A tangent that is zero or parallel to the normal leaves no frame: keep the normal.
        vec3 tangentDirection = vTangent.xyz - normal * dot(normal, vTangent.xyz);
        if (dot(tangentDirection, tangentDirection) > 1e-24) {
            vec3 tangent = normalize(tangentDirection);
            vec3 bitangent = cross(normal, tangent) * vTangent.w;
            vec3 mapped = normalSample * 2.0 - 1.0;
            mapped.xy *= draw.materialParams.z;
            normal = safeNormalize(mat3(tangent, bitangent, normal) * mapped, normal);
        }
    }

    Surface s;
    s.normal = normal;
    s.view = toCamera;
    s.diffuseColor = baseColor.rgb * (1.0 - metallic);
    s.f0 = mix(draw.dielectricSpecular.rgb, baseColor.rgb, metallic);
    s.f90 = mix(draw.dielectricSpecular.w, 1.0, metallic);
    s.alpha = perceptualRoughness * perceptualRoughness;

    vec3 radiance = vec3(0.0);
    uint meshLayers = uint(draw.flags.w);
    float mainLightVisibility = 1.0;   // --debug shadow shows it
    for (int i = 0; i < frame.lightCounts.x; ++i) {
        DirectionalLight light = frame.directionalLights[i];
        if ((floatBitsToUint(light.colorIntensity.w) & meshLayers) == 0u) continue;
        vec3 irradiance = light.colorIntensity.rgb;
        if (i == 0 && frame.shadowParams.x > 0.0) {
            vec3 shadowCoord = shadowCoordFor(frame.worldToShadow, vWorldPosition, geometricNormal, frame.shadowParams.z);
            mainLightVisibility = sampleShadowPCF(shadowMap, shadowCoord, frame.shadowParams.y);
            irradiance *= mainLightVisibility;
        }
        radiance += shade(s, -light.direction.xyz, irradiance);
    }

    bool tiled = frame.lightCounts.z != 0;
    int tile = 0;
    int localCount = frame.lightCounts.y;
    if (tiled) {
        ivec2 tileXY = ivec2(gl_FragCoord.xy) / frame.tileGrid.x;
        tile = tileXY.y * frame.tileGrid.y + tileXY.x;
        localCount = int(tileDataAt(tile));
    }
    int listBase = frame.tileGrid.w + tile * frame.tileGrid.z;
    for (int k = 0; k < localCount; ++k) {
        int index = tiled ? int(tileDataAt(listBase + k)) : k;
        radiance += shadeLocalLight(s, vWorldPosition, index, meshLayers);
    }

    float occlusion = mix(1.0, occlusionSample, draw.materialParams.w);
    float NoV = clamp(abs(dot(s.normal, s.view)), 1e-4, 1.0);
    vec3 reflected = reflect(-s.view, s.normal);
    // Reflection probes first (docs/PROBES.md); the sky or the ambient colour fills what they leave.
    vec4 probes = vec4(0.0, 0.0, 0.0, 1.0);
    if (reflectionProbes.probeCount.x > 0) probes = reflectionProbeRadiance(vWorldPosition, reflected, perceptualRoughness);
    vec3 probeSpecular = probes.rgb;
    // Smoothed vertex normals and normal maps lean the shading normal away from the triangle's
    // plane: the volume's and the sky's light from below that plane is hidden by the surface
    // (docs/GI.md, "Bent normals"). Without either no plane is needed.
    vec3 surfaceNormal = giVolume.origin.w > 0.0 || frame.skyParams.x > 0.0 ? faceNormal(positionDx, positionDy, toCamera, s.normal) : s.normal;
    vec4 gi = giIrradianceOverPi(vWorldPosition, s.normal, surfaceNormal);   // coverage 0 without a volume
    if (frame.skyParams.w > 1.5) {
        // --debug shadow: what the shadow map lets through of the main light (1 without a map).
        outRadiance = vec4(vec3(mainLightVisibility), 1.0);
        return;
    }
    if (frame.skyParams.w > 0.5) {
        // --debug gi: the volume's irradiance / pi where it reaches, times its coverage.
        outRadiance = vec4(min(gi.rgb * gi.a, vec3(kMaxRadiance)), 1.0);
        return;
    }
    float remaining = probes.a;
    if (frame.skyParams.x > 0.0) {
        // The sky: SH9 diffuse and split-sum specular (docs/IBL.md).
        vec3 specularLight = skyPrefilteredRadiance(reflected, perceptualRoughness, frame.skyParams.y) * frame.skyParams.z;
        specularLight = probeSpecular + remaining * specularLight;
        // Diffuse: the irradiance volume where it reaches (docs/GI.md), the sky's SH elsewhere.
        vec3 diffuseIrradiance = skyIrradianceOverPi(s.normal, surfaceNormal);
        float diffuseScale = occlusion * frame.skyParams.z;
        if (gi.a > 0.0) {
            diffuseIrradiance = mix(diffuseIrradiance * frame.skyParams.z, gi.rgb, gi.a);
            diffuseScale = occlusion;
        }
        radiance += s.diffuseColor * diffuseIrradiance * diffuseScale +
                    specularLight * splitSumScale(NoV, perceptualRoughness, s.f0, s.f90) * specularOcclusion(NoV, occlusion, perceptualRoughness);
    } else if (gi.a > 0.0) {
        // The irradiance volume's diffuse light, the ambient colour's rough specular term.
        radiance += (mix(frame.ambientColor.rgb, gi.rgb, gi.a) * s.diffuseColor + frame.ambientColor.rgb * s.f0 * remaining) * occlusion;
        if (remaining < 1.0)
            radiance += probeSpecular * splitSumScale(NoV, perceptualRoughness, s.f0, s.f90) * specularOcclusion(NoV, occlusion, perceptualRoughness);
    } else {
        // Uniform ambient: diffuse plus a rough specular term (where no probe reflects).
        radiance += frame.ambientColor.rgb * (s.diffuseColor + s.f0 * remaining) * occlusion;
        if (remaining < 1.0)
            radiance += probeSpecular * splitSumScale(NoV, perceptualRoughness, s.f0, s.f90) * specularOcclusion(NoV, occlusion, perceptualRoughness);
    }
    radiance += draw.emissiveFactor.rgb * emissiveSample;
    writeRadiance(radiance, outputAlpha);
}
