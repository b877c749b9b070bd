#version 450
#extension GL_GOOGLE_include_directive : require
#include "janus/shaders/bindings.h"
// Debug view "tiles": local lights per tile as a heat colour blended over the display image
// (blue = none, red = the scale's top: the cap, or 256 lights when the cap is higher, so that one
// colour means one density whatever an automatic cap chose; more stays red). Tiles at the cap, where lights may have
// been dropped, also get a white diagonal hatch: only where the cap is below the light count (an
// automatic cap of every light drops none). Drawn after tonemapping with alpha blending.
#define TILE_DATA_ONLY 1
#include "renderer/light_access.glsl"

layout(set = 0, binding = JANUS_BINDING_HEATMAP_UNIFORMS, std140) uniform HeatmapUniforms {
    ivec4 grid;   // x tileSize, y tilesX, z the count shown red, w tileCount
    ivec4 marks;  // x the count from which a tile is hatched (maxLightsPerTile, or above it when no tile can drop a light)
} heatmap;

layout(location = 0) out vec4 outColor;

vec3 heatColor(float t) {
    // blue -> green -> red
    return t < 0.5 ? mix(vec3(0.0, 0.0, 1.0), vec3(0.0, 1.0, 0.0), t * 2.0)
                   : mix(vec3(0.0, 1.0, 0.0), vec3(1.0, 0.0, 0.0), t * 2.0 - 1.0);
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    ivec2 tileXY = pixel / heatmap.grid.x;
    int count = int(tileDataAt(tileXY.y * heatmap.grid.y + tileXY.x));
    bool atCap = count >= heatmap.marks.x;
    vec4 color = vec4(heatColor(min(float(count) / float(heatmap.grid.z), 1.0)), 0.45);
    ivec2 inTile = pixel - tileXY * heatmap.grid.x;
    // Tile outlines keep neighbouring tiles of equal count apart.
    if (inTile.x == 0 || inTile.y == 0) color = vec4(0.0, 0.0, 0.0, 0.35);
    // Opaque: every heat colour has a zero channel, so pure white marks the cap unambiguously.
    if (atCap && ((pixel.x + pixel.y) & 7) < 2) color = vec4(1.0);
    outColor = color;
}
