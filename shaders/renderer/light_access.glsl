// Point/spot light array and tile lists (layout: docs/LIGHTING.md, "GPU light layout" and "Tile
// lists"). Storage buffers on the compute path; on the fallback path (ES 3.0 has no SSBOs) the
// same words live in integer textures 1024 elements wide: element e at texel (e % 1024, e / 1024).
// Define TILE_DATA_ONLY to declare only the tile lists (binding 8).
#ifndef JANUS_LIGHT_ACCESS_GLSL
#define JANUS_LIGHT_ACCESS_GLSL
#include "janus/shaders/bindings.h"

const int kDataTextureWidth = 1024;

#ifdef LIGHTS_IN_TEXTURES
#ifndef TILE_DATA_ONLY
layout(set = JANUS_SET_VIEW, binding = JANUS_BINDING_LOCAL_LIGHTS) uniform highp usampler2D localLightTexture;   // RGBA32UI, 4 texels per light
#endif
layout(set = JANUS_SET_VIEW, binding = JANUS_BINDING_TILE_LISTS) uniform highp usampler2D tileDataTexture;     // R32UI

#ifndef TILE_DATA_ONLY
uvec4 localLightWord(int light, int word) {
    int e = light * 4 + word;
    return texelFetch(localLightTexture, ivec2(e % kDataTextureWidth, e / kDataTextureWidth), 0);
}
#endif
uint tileDataAt(int e) { return texelFetch(tileDataTexture, ivec2(e % kDataTextureWidth, e / kDataTextureWidth), 0).r; }

#else
#ifndef TILE_DATA_ONLY
layout(set = JANUS_SET_VIEW, binding = JANUS_BINDING_LOCAL_LIGHTS, std430) readonly buffer LocalLights { uvec4 lightWords[]; };
uvec4 localLightWord(int light, int word) { return lightWords[light * 4 + word]; }
#endif
layout(set = JANUS_SET_VIEW, binding = JANUS_BINDING_TILE_LISTS, std430) readonly buffer TileData { uint tileData[]; };
uint tileDataAt(int e) { return tileData[e]; }
#endif

#ifndef TILE_DATA_ONLY
// What local light `index` (a point or spot light; words per docs/LIGHTING.md) delivers at a
// world position: irradiance at normal incidence (inverse square with a window that reaches zero
// with zero slope at the range, times the squared spot cone), the unit direction towards it, and
// its rendering layers. Forward shading and the GI relight (shaders/gi/) light with this. (A
// struct, not out parameters: Mesa's GLSL compiler warns about the copies SPIRV-Cross makes of them.)
struct LocalLightSample {
    vec3 irradiance;
    vec3 toLight;
    uint layers;
};
LocalLightSample localLightIrradiance(int index, vec3 worldPosition) {
    uvec4 w0 = localLightWord(index, 0);
    uvec4 w1 = localLightWord(index, 1);
    uvec4 w2 = localLightWord(index, 2);
    uvec4 w3 = localLightWord(index, 3);
    vec3 toLight = uintBitsToFloat(w0.xyz) - worldPosition;
    float distanceSq = dot(toLight, toLight);
    toLight *= inversesqrt(max(distanceSq, 1e-12));
    float ratioSq = distanceSq * uintBitsToFloat(w0.w);
    float window = clamp(1.0 - ratioSq * ratioSq, 0.0, 1.0);
    float attenuation = window * window / max(distanceSq, 1e-4);
    vec2 spot = uintBitsToFloat(w3.xy);
    float cone = clamp(dot(uintBitsToFloat(w2.xyz), -toLight) * spot.x + spot.y, 0.0, 1.0);
    attenuation *= cone * cone;
    LocalLightSample result;
    result.irradiance = uintBitsToFloat(w1.rgb) * attenuation;
    result.toLight = toLight;
    result.layers = w2.w;
    return result;
}
#endif

#endif
