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

#endif
