#version 450
#extension GL_GOOGLE_include_directive : require
// Forward PBR (glTF metallic-roughness): GGX distribution, height-correlated Smith visibility,
// Schlick Fresnel, Lambert diffuse. Writes linear radiance to the RGBA16F HDR target.
#include "renderer/forward_common.glsl"

layout(set = 1, binding = 2) uniform sampler2D baseColorTexture;          // sRGB texture: decoded by the sampler
layout(set = 1, binding = 3) uniform sampler2D metallicRoughnessTexture;  // G roughness, B metallic
layout(set = 1, binding = 4) uniform sampler2D normalTexture;
layout(set = 1, binding = 5) uniform sampler2D occlusionTexture;          // R occlusion
layout(set = 1, binding = 6) uniform sampler2D emissiveTexture;

layout(location = 0) in vec3 vWorldPosition;
layout(location = 1) in vec3 vNormal;
layout(location = 2) in vec2 vUv;
layout(location = 3) in vec4 vTangent;

layout(location = 0) out vec4 outRadiance;

const float PI = 3.14159265358979;

float distributionGGX(float NoH, float alpha) {
    float a2 = alpha * alpha;
    float f = (NoH * a2 - NoH) * NoH + 1.0;
    return a2 / (PI * f * f);
}

// Height-correlated Smith G divided by 4 NoL NoV (Heitz 2014).
float visibilitySmithGGXCorrelated(float NoV, float NoL, float alpha) {
    float a2 = alpha * alpha;
    float ggxV = NoL * sqrt(NoV * NoV * (1.0 - a2) + a2);
    float ggxL = NoV * sqrt(NoL * NoL * (1.0 - a2) + a2);
    return 0.5 / max(ggxV + ggxL, 1e-6);
}

vec3 fresnelSchlick(vec3 f0, float VoH) {
    float f = pow(1.0 - VoH, 5.0);
    return f0 + (vec3(1.0) - f0) * f;
}

struct Surface {
    vec3 normal;
    vec3 view;
    vec3 diffuseColor;
    vec3 f0;
    float alpha;
};

// Outgoing radiance for light arriving along -lightDirection with irradiance `irradiance`
// at normal incidence.
vec3 shade(Surface s, vec3 toLight, vec3 irradiance) {
    float NoL = clamp(dot(s.normal, toLight), 0.0, 1.0);
    if (NoL <= 0.0) return vec3(0.0);
    vec3 h = normalize(toLight + s.view);
    float NoV = clamp(abs(dot(s.normal, s.view)), 1e-4, 1.0);
    float NoH = clamp(dot(s.normal, h), 0.0, 1.0);
    float VoH = clamp(dot(s.view, h), 0.0, 1.0);
    vec3 F = fresnelSchlick(s.f0, VoH);
    vec3 specular = F * (distributionGGX(NoH, s.alpha) * visibilitySmithGGXCorrelated(NoV, NoL, s.alpha));
    vec3 diffuse = (vec3(1.0) - F) * s.diffuseColor / PI;
    return (diffuse + specular) * irradiance * NoL;
}

// KHR_lights_punctual's recommended range window: smooth fall-off to zero at `range`.
float rangeAttenuation(float distance, float range) {
    if (range <= 0.0) return 1.0 / max(distance * distance, 1e-4);
    float ratio = distance / range;
    float window = clamp(1.0 - ratio * ratio * ratio * ratio, 0.0, 1.0);
    return window * window / max(distance * distance, 1e-4);
}

void main() {
    vec4 baseColor = draw.baseColorFactor * texture(baseColorTexture, vUv);
    if (draw.flags.z != 0 && baseColor.a < draw.emissiveFactor.w) discard;
    vec4 metallicRoughness = texture(metallicRoughnessTexture, vUv);
    float metallic = clamp(draw.materialParams.x * metallicRoughness.b, 0.0, 1.0);
    float perceptualRoughness = clamp(draw.materialParams.y * metallicRoughness.g, 0.045, 1.0);

    vec3 normal = normalize(vNormal);
    if (draw.flags.x != 0 && !gl_FrontFacing) normal = -normal;
    if (draw.flags.y != 0) {
        // Normal map in tangent space; the bitangent's sign comes from the tangent's w.
        vec3 tangent = normalize(vTangent.xyz - normal * dot(normal, vTangent.xyz));
        vec3 bitangent = cross(normal, tangent) * vTangent.w;
        vec3 mapped = texture(normalTexture, vUv).xyz * 2.0 - 1.0;
        mapped.xy *= draw.materialParams.z;
        normal = normalize(mat3(tangent, bitangent, normal) * mapped);
    }

    Surface s;
    s.normal = normal;
    s.view = normalize(frame.cameraPosition.xyz - vWorldPosition);
    s.diffuseColor = baseColor.rgb * (1.0 - metallic);
    s.f0 = mix(vec3(0.04), baseColor.rgb, metallic);
    s.alpha = perceptualRoughness * perceptualRoughness;

    vec3 radiance = vec3(0.0);
    for (int i = 0; i < frame.lightCounts.x; ++i) {
        LightData light = frame.directionalLights[i];
        radiance += shade(s, -light.directionType.xyz, light.colorIntensity.rgb);
    }
    for (int i = 0; i < frame.lightCounts.y; ++i) {
        LightData light = frame.localLights[i];
        vec3 toLight = light.positionRange.xyz - vWorldPosition;
        float distance = length(toLight);
        toLight /= max(distance, 1e-6);
        float attenuation = rangeAttenuation(distance, light.positionRange.w);
        if (light.directionType.w > 1.5) {
            float cd = dot(light.directionType.xyz, -toLight);
            float cone = clamp(cd * light.spotScaleOffset.x + light.spotScaleOffset.y, 0.0, 1.0);
            attenuation *= cone * cone;
        }
        radiance += shade(s, toLight, light.colorIntensity.rgb * attenuation);
    }

    // Uniform ambient until probes / IBL land: diffuse plus a rough specular term.
    float occlusion = mix(1.0, texture(occlusionTexture, vUv).r, draw.materialParams.w);
    radiance += frame.ambientColor.rgb * (s.diffuseColor + s.f0) * occlusion;
    radiance += draw.emissiveFactor.rgb * texture(emissiveTexture, vUv).rgb;

    outRadiance = vec4(radiance, 1.0);
}
