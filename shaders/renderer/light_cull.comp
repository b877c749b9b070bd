#version 450
#extension GL_GOOGLE_include_directive : require
#include "janus/shaders/bindings.h"
// Forward+ tile lists, compute path: one 16x16 workgroup per screen tile. Depth bounds from the
// prepass (TilesDepth), a per-light bitmask in shared memory, then an ordered compaction so each
// tile's list is ascending like the CPU builder's (docs/LIGHTING.md).
#include "renderer/light_culling_common.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

layout(set = 0, binding = JANUS_BINDING_CULL_UNIFORMS, std140) uniform CullUniforms {
    mat4 view;
    mat4 projection;
    mat4 inverseProjection;
    uvec4 grid;     // x width, y height, z tileSize, w maxLightsPerTile
    uvec4 counts;   // x tilesX, y tilesY, z lightCount, w mode (1 Tiles2D, 2 TilesDepth)
    vec4 planes;    // x near, y far, z 1 = ranges from the near plane (transparent surfaces; TileGrid::rangeFromNearPlane)
} cull;
layout(set = 0, binding = JANUS_BINDING_CULL_DEPTH) uniform sampler2D depthTexture;
layout(set = 0, binding = JANUS_BINDING_CULL_LIGHTS, std430) readonly buffer LocalLights { uvec4 lightWords[]; };
layout(set = 0, binding = JANUS_BINDING_CULL_TILE_LISTS, std430) buffer TileData { uint tileData[]; };
layout(set = 0, binding = JANUS_BINDING_CULL_STATS, std430) buffer CullStats { uint overflowTiles; uint droppedLights; uint listedLights; uint densestTileLights; };

const uint kThreads = 256u;
const uint kMaskWords = 512u;   // 16384 lights (kMaxLocalLights)
const uint kModeTilesDepth = 2u;

shared uint minDepthBits;
shared uint maxDepthBits;
shared uint lightMask[kMaskWords];
shared uint prefix[kThreads];

void main() {
    uint local = gl_LocalInvocationIndex;
    uvec2 tile = gl_WorkGroupID.xy;
    uvec2 size = cull.grid.xy;
    uint tileSize = cull.grid.z, cap = cull.grid.w;
    uint tilesX = cull.counts.x, tileCount = cull.counts.x * cull.counts.y;
    uint lightCount = min(cull.counts.z, kMaskWords * 32u);
    bool useDepth = cull.counts.w == kModeTilesDepth;

    if (local == 0u) {
        minDepthBits = floatBitsToUint(1.0);   // depths are in [0, 1]: their bits order like the floats
        maxDepthBits = 0u;
    }
    for (uint w = local; w < kMaskWords; w += kThreads) lightMask[w] = 0u;
    barrier();

    uvec2 origin = tile * tileSize;
    uvec2 end = min(origin + uvec2(tileSize), size);
    if (useDepth) {
        for (uint y = origin.y + gl_LocalInvocationID.y; y < end.y; y += 16u)
            for (uint x = origin.x + gl_LocalInvocationID.x; x < end.x; x += 16u) {
                float z = texelFetch(depthTexture, ivec2(x, y), 0).r;
                if (z < 1.0) {   // 1 = cleared: no geometry, nothing to light
                    atomicMin(minDepthBits, floatBitsToUint(z));
                    atomicMax(maxDepthBits, floatBitsToUint(z));
                }
            }
    }
    barrier();

    TileRegion region = tileSlopes(cull.projection, tile, size, tileSize, cull.planes.x, cull.planes.y);
    if (useDepth) {
        float minDepth = uintBitsToFloat(minDepthBits), maxDepth = uintBitsToFloat(maxDepthBits);
        region.hasGeometry = minDepth <= maxDepth;
        float dMin = linearViewDepth(cull.projection, minDepth), dMax = linearViewDepth(cull.projection, maxDepth);
        region.dMin = dMin - depthMargin(cull.projection, minDepth, dMin);
        region.dMax = dMax + depthMargin(cull.projection, maxDepth, dMax);
        if (cull.planes.z != 0.0) {
            // Transparent surfaces lie in front of the depth: from the near plane on, and
            // anywhere where no depth was written.
            region.dMin = cull.planes.x;
            if (!region.hasGeometry) {
                region.hasGeometry = true;
                region.dMax = cull.planes.y;
            }
        }
    }
    if (region.hasGeometry) {
        for (uint i = local; i < lightCount; i += kThreads) {
            vec4 sphere = cullSphere(lightWords[4u * i], lightWords[4u * i + 1u], lightWords[4u * i + 2u], lightWords[4u * i + 3u]);
            vec3 center = (cull.view * vec4(sphere.xyz, 1.0)).xyz;
            if (sphereMeetsTile(center, sphere.w, region, useDepth))
                atomicOr(lightMask[i >> 5u], 1u << (i & 31u));
        }
    }
    barrier();

    // Ordered compaction: thread k owns mask words 2k and 2k+1; an inclusive scan of their bit
    // counts gives each thread the rank of its first light.
    uint word0 = lightMask[2u * local], word1 = lightMask[2u * local + 1u];
    uint own = uint(bitCount(word0) + bitCount(word1));
    prefix[local] = own;
    barrier();
    for (uint offset = 1u; offset < kThreads; offset <<= 1u) {
        uint add = local >= offset ? prefix[local - offset] : 0u;
        barrier();
        prefix[local] += add;
        barrier();
    }
    uint rank = prefix[local] - own;
    uint total = prefix[kThreads - 1u];
    uint tileIndex = tile.y * tilesX + tile.x;
    uint listBase = tileCount + tileIndex * cap;
    for (uint half_ = 0u; half_ < 2u && rank < cap; ++half_) {
        uint bits = half_ == 0u ? word0 : word1;
        uint base = (2u * local + half_) * 32u;
        while (bits != 0u && rank < cap) {
            int bit = findLSB(bits);
            bits &= bits - 1u;
            tileData[listBase + rank] = base + uint(bit);
            ++rank;
        }
    }
    if (local == 0u) {
        uint listed = min(total, cap);
        tileData[tileIndex] = listed;
        atomicAdd(listedLights, listed);
        atomicMax(densestTileLights, total);
        if (total > cap) {
            atomicAdd(overflowTiles, 1u);
            atomicAdd(droppedLights, total - cap);
        }
    }
}
