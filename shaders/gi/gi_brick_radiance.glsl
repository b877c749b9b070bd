// The first relight pass (docs/GI.md): each brick's outgoing radiance, the mean over its surfels
// of  albedo / pi * direct irradiance (directional lights, the main light's shadow, local
// lights) + emission + albedo * the last relight's irradiance / pi (further bounces), both from
// above the surfel's triangle only (its face normal), as forward shading's volume lookup.
// A sky sample's "brick" is the sky's radiance along its direction (the ambient colour without a sky).
#define FRAME_UNIFORMS_ONLY 1
#include "renderer/forward_common.glsl"
#include "renderer/light_access.glsl"
#include "renderer/shadow_sampling.glsl"
#include "renderer/sky_access.glsl"
#include "gi/gi_access.glsl"
#include "gi/gi_relight_common.glsl"

layout(set = 0, binding = JANUS_BINDING_SHADOW_MAP) uniform sampler2DShadow shadowMap;
layout(set = 0, binding = JANUS_BINDING_GI_SURFELS) uniform highp sampler2D giSurfels;
layout(set = 0, binding = JANUS_BINDING_GI_BRICKS) uniform highp sampler2D giBricks;

const float kGiPi = 3.14159265358979;

// Direct irradiance at a surfel with shading normal `normal` on a triangle whose plane has normal
// `faceNormal`: a light below that plane does not reach it, whatever the shading normal says (as
// the reference's), nor does a light whose rendering layers share no bit with the surfel's (as
// forward shading). The shadow lookup moves off the triangle's plane, not along the shading normal.
vec3 surfelIrradiance(vec3 position, vec3 normal, vec3 faceNormal, uint layers) {
    vec3 irradiance = vec3(0.0);
    for (int i = 0; i < frame.lightCounts.x; ++i) {
        DirectionalLight light = frame.directionalLights[i];
        if ((floatBitsToUint(light.colorIntensity.w) & layers) == 0u) continue;
        if (dot(faceNormal, -light.direction.xyz) <= 0.0) continue;
        vec3 e = light.colorIntensity.rgb * max(dot(normal, -light.direction.xyz), 0.0);
        if (i == 0 && frame.shadowParams.x > 0.0)
            e *= sampleShadowPCF(shadowMap, shadowCoordFor(frame.worldToShadow, position, faceNormal, frame.shadowParams.z),
                                 frame.shadowParams.y);
        irradiance += e;
    }
    for (int k = 0; k < frame.lightCounts.y; ++k) {
        LocalLightSample light = localLightIrradiance(k, position);
        if ((light.layers & layers) == 0u || dot(faceNormal, light.toLight) <= 0.0) continue;
        irradiance += light.irradiance * max(dot(normal, light.toLight), 0.0);
    }
    return irradiance;
}

vec3 brickRadiance(int brick) {
    vec4 header = giData(giBricks, brick * 2);
    if (header.z > 0.5) {
        vec3 direction = giData(giBricks, brick * 2 + 1).xyz;
        if (frame.skyParams.x > 0.0) return skyPrefilteredRadiance(direction, 0.0, frame.skyParams.y) * frame.skyParams.z;
        return frame.ambientColor.rgb;
    }
    int first = int(header.x), count = int(header.y);
    vec3 sum = vec3(0.0);
    for (int s = first; s < first + count; ++s) {
        // gi_relight_common.glsl's layout: position, normal, albedo, emission; in their w the face
        // normal (octahedral) and the rendering layers (two 16-bit halves).
        vec4 positionFace = giData(giSurfels, s * 4);
        vec4 normalFace = giData(giSurfels, s * 4 + 1);
        vec4 albedoLayers = giData(giSurfels, s * 4 + 2);
        vec4 emissionLayers = giData(giSurfels, s * 4 + 3);
        vec3 position = positionFace.xyz, normal = normalFace.xyz, albedo = albedoLayers.rgb, emission = emissionLayers.rgb;
        vec3 faceNormal = giOctahedralDecode(vec2(positionFace.w, normalFace.w));
        uint layers = uint(albedoLayers.w) | (uint(emissionLayers.w) << 16);
        vec3 radiance = albedo * (1.0 / kGiPi) * surfelIrradiance(position, normal, faceNormal, layers) + emission;
        if (relight.counts.z != 0) radiance += albedo * giIrradianceOverPi(position, normal, faceNormal).rgb;
        sum += radiance;
    }
    vec3 mean = count > 0 ? sum / float(count) : vec3(0.0);
    return min(mix(mean, vec3(0.0), isnan(mean)), vec3(65000.0));
}
