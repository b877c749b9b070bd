// The bright-texel passes of the GGX prefilter (renderer/src/ibl/ggx_prefilter.cpp, docs/IBL.md
// "Bright texels"): the split (ggx_bright_split.*) writes the rest cube's mip 0 = the source without
// its bright texels, alpha = a marker on the texels taken out; the list (ggx_bright_list.*) finds
// them again through the rest's box-filtered alpha chain (which counts them) and lists them.
#ifndef JANUS_IBL_GGX_BRIGHT_GLSL
#define JANUS_IBL_GGX_BRIGHT_GLSL

#include "janus/shaders/bindings.h"
#include "ibl/cube_geometry.glsl"

// std140 mirror: renderer/src/ibl/ggx_prefilter.cpp.
layout(std140, set = 0, binding = JANUS_BINDING_BRIGHT_PARAMS) uniform BrightParams {
    ivec4 brightParams;   // x face (fallback split), y source face size (a power of two), z its top level (log2 size), w list capacity K
    vec4 brightLimits;    // x threshold: bright when r + g + b >= x * the cube's mean r + g + b; y the alpha marker A
};
layout(set = 0, binding = JANUS_BINDING_BRIGHT_SOURCE) uniform samplerCube brightSource;   // nearest

vec3 faceCentre(int face) { return cubeDirection(face, vec2(0.5)); }

#ifdef JANUS_IBL_BRIGHT_SPLIT
// The mean r + g + b over the cube's texels: the mean of the six 1x1 top levels of the box chain.
float brightMean() {
    float sum = 0.0;
    for (int face = 0; face < 6; ++face) {
        vec3 c = textureLod(brightSource, faceCentre(face), float(brightParams.z)).rgb;
        sum += c.r + c.g + c.b;
    }
    return sum / 6.0;
}

// Mip 0 of the rest: the source texel, or (0, 0, 0, A) where the texel is bright (`mean`: brightMean()).
vec4 splitTexel(int face, ivec2 texel, float mean) {
    // The rest is half float: keep it finite whatever the source's format.
    vec3 radiance = min(textureLod(brightSource, cubeTexelDirection(face, texel, brightParams.y), 0.0).rgb, vec3(65504.0));
    float s = radiance.r + radiance.g + radiance.b;
    bool bright = s > 0.0 && s >= brightLimits.x * mean;
    return bright ? vec4(0.0, 0.0, 0.0, brightLimits.y) : vec4(radiance, 0.0);
}
#endif

#ifdef JANUS_IBL_BRIGHT_LIST
layout(set = 0, binding = JANUS_BINDING_BRIGHT_REST) uniform samplerCube brightRest;   // nearest

// Bright texels under texel `texel` of level `level`: the box-filtered marker times the texels it
// averages (exact in half floats below 2048 per texel: counts and A = 256 are powers of two apart).
int brightCount(int face, ivec2 texel, int level) {
    int size = brightParams.y >> level;
    float marker = textureLod(brightRest, cubeTexelDirection(face, texel, size), float(level)).a;
    return int(round(marker * float(1 << (2 * level)) / brightLimits.y));
}

// List texel `column` of one row, two per entry: columns 0, 1 = the header (entries, 1 if more bright
// texels than K, all of them; then zeros); columns 2k + 2, 2k + 3 = the k-th bright texel in the order
// face, then down the quadtree (children (0,0), (1,0), (0,1), (1,1)): its radiance and 1, then
// (face, x, y, 1); zeros past the end.
vec4 listTexel(int column) {
    int top = brightParams.z;
    int capacity = brightParams.w;
    int entry = column / 2;
    bool second = column - 2 * entry == 1;
    int counts[6];
    int total = 0;
    for (int face = 0; face < 6; ++face) {
        counts[face] = brightCount(face, ivec2(0), top);
        total += counts[face];
    }
    if (entry == 0) return second ? vec4(0.0) : vec4(float(min(total, capacity)), total > capacity ? 1.0 : 0.0, float(min(total, 65504)), 0.0);
    int k = entry - 1;
    if (total > capacity || k >= total) return vec4(0.0);
    int face = 0;
    for (; face < 5 && k >= counts[face]; ++face) k -= counts[face];
    ivec2 texel = ivec2(0);
    for (int level = top - 1; level >= 0; --level) {
        texel *= 2;
        bool found = false;
        for (int child = 0; child < 4 && !found; ++child) {
            ivec2 c = texel + ivec2(child & 1, child >> 1);
            int n = brightCount(face, c, level);
            if (k < n) {
                texel = c;
                found = true;
            } else {
                k -= n;
            }
        }
        if (!found) return vec4(0.0);   // counts that do not add up (not a box filter): no entry
    }
    if (brightCount(face, texel, 0) != 1) return vec4(0.0);
    vec3 radiance = textureLod(brightSource, cubeTexelDirection(face, texel, brightParams.y), 0.0).rgb;
    return second ? vec4(float(face), vec2(texel), 1.0) : vec4(radiance, 1.0);
}
#endif

#endif
