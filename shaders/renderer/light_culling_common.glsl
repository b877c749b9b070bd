// Forward+ tile culling math, the GLSL twin of renderer/src/forward/light_grid_build.cpp
// (sphereMeetsTile and friends): same algorithm, same margins, float throughout, so the compute
// builder lists the same lights as the CPU builder (a few more through rounding, never fewer:
// the margins dwarf the rounding). docs/LIGHTING.md, "Culling".
#ifndef JANUS_LIGHT_CULLING_COMMON_GLSL
#define JANUS_LIGHT_CULLING_COMMON_GLSL

const float kRadiusRelativeMargin = 1e-3;   // float error of the view transform and planes, relative to the radius
const float kRadiusAbsoluteMargin = 1e-4;   // ...and absolute, for tiny lights (world units)
const float kDepthRelativeMargin = 1e-5;    // float error of depth linearisation (a few ulps)
const float kDepthUlps = 1.1920929e-7;      // 2 * 2^-24: a stored depth's error (its rounding plus P22's), in units of max(z, |P22|)

// Side planes x = ox + x * d, y = oy + y * d (d = -z): through the eye for a perspective tile
// (offsets 0), a box for an orthographic one (slopes 0).
struct TileRegion {
    float x0, x1, y0, y1;       // slopes
    float ox0, ox1, oy0, oy1;   // offsets
    float invNormX0, invNormX1, invNormY0, invNormY1;   // 1 / |plane normal|, per tile rather than per light
    float dMin, dMax;       // view distance range
    bool hasGeometry;
};

bool isOrthographic(mat4 projection) { return projection[2][3] == 0.0; }

// D32F depth -> distance along the view axis, for perspectiveRH_ZO and orthoRH_ZO alike.
float linearViewDepth(mat4 projection, float depth) {
    return (projection[3][2] - depth * projection[3][3]) / (projection[2][2] - depth * projection[2][3]);
}

// How far a tile's depth bound may be from its surfaces at distance d of stored depth z: the
// depth's rounding grows into dz * d^2 / |P32| (metres at far / near = 1e5). light_grid_build.cpp's
// depthMargin is the same formula.
float depthMargin(mat4 projection, float z, float d) {
    if (isOrthographic(projection)) {   // linear depth: dz / |P22| everywhere
        float orthoError = kDepthUlps * (abs(z) + abs(projection[3][2]));
        return d * kDepthRelativeMargin + orthoError / abs(projection[2][2]);
    }
    float zError = kDepthUlps * (abs(z) + abs(projection[2][2]));
    return d * kDepthRelativeMargin + zError * d * d / abs(projection[3][2]);
}

TileRegion tileSlopes(mat4 projection, uvec2 tile, uvec2 size, uint tileSize, float nearPlane, float farPlane) {
    uint px0 = tile.x * tileSize, px1 = min(px0 + tileSize, size.x);
    uint py0 = tile.y * tileSize, py1 = min(py0 + tileSize, size.y);
    float ndcX0 = 2.0 * float(px0) / float(size.x) - 1.0;
    float ndcX1 = 2.0 * float(px1) / float(size.x) - 1.0;
    float ndcY0 = 2.0 * float(py0) / float(size.y) - 1.0;
    float ndcY1 = 2.0 * float(py1) / float(size.y) - 1.0;
    float ax = ndcX0 / projection[0][0], bx = ndcX1 / projection[0][0];
    float ay = ndcY0 / projection[1][1], by = ndcY1 / projection[1][1];
    float slope = -projection[2][3], offset = projection[3][3];   // w = P33 - P23 * d
    TileRegion region;
    region.x0 = min(ax, bx) * slope;
    region.x1 = max(ax, bx) * slope;
    region.y0 = min(ay, by) * slope;
    region.y1 = max(ay, by) * slope;
    region.ox0 = min(ax, bx) * offset;
    region.ox1 = max(ax, bx) * offset;
    region.oy0 = min(ay, by) * offset;
    region.oy1 = max(ay, by) * offset;
    region.invNormX0 = 1.0 / sqrt(1.0 + region.x0 * region.x0);
    region.invNormX1 = 1.0 / sqrt(1.0 + region.x1 * region.x1);
    region.invNormY0 = 1.0 / sqrt(1.0 + region.y0 * region.y0);
    region.invNormY1 = 1.0 / sqrt(1.0 + region.y1 * region.y1);
    region.dMin = nearPlane;
    region.dMax = farPlane;
    region.hasGeometry = true;
    return region;
}

// Bounding sphere (world centre in xyz, radius with margins in w; w < 0 = infinite range) of what
// a packed light can reach: the range sphere, or for spots narrower than 90 degrees the smaller
// sphere around the spherical sector. Same as toCullLight() in light_grid_build.cpp.
vec4 cullSphere(uvec4 word0, uvec4 word1, uvec4 word2, uvec4 word3) {
    vec3 position = uintBitsToFloat(word0.xyz);
    float invRangeSq = uintBitsToFloat(word0.w);
    if (!(invRangeSq > 0.0)) return vec4(position, -1.0);
    float range = 1.0 / sqrt(invRangeSq);
    vec3 center = position;
    float radius = range;
    float spotScale = uintBitsToFloat(word3.x), spotOffset = uintBitsToFloat(word3.y);
    vec3 direction = uintBitsToFloat(word2.xyz);
    if (word1.w == 2u && spotScale > 0.0) {
        float cosOuter = -spotOffset / spotScale;
        if (cosOuter >= 0.70710678) {
            radius = range / (2.0 * cosOuter);
            center = position + direction * radius;
        } else if (cosOuter > 0.0) {
            radius = range * sqrt(1.0 - cosOuter * cosOuter);
            center = position + direction * (range * cosOuter);
        }
    }
    return vec4(center, radius * (1.0 + kRadiusRelativeMargin) + kRadiusAbsoluteMargin);
}

// Conservative: false only when the (margined) sphere is entirely outside the tile's region.
bool sphereMeetsTile(vec3 c, float r, TileRegion tile, bool useDepthBox) {
    if (!tile.hasGeometry) return false;
    if (r < 0.0) return true;
    float d = -c.z;
    if (d + r < tile.dMin || d - r > tile.dMax) return false;
    if ((c.x + tile.x1 * c.z - tile.ox1) * tile.invNormX1 > r) return false;
    if ((-c.x - tile.x0 * c.z + tile.ox0) * tile.invNormX0 > r) return false;
    if ((c.y + tile.y1 * c.z - tile.oy1) * tile.invNormY1 > r) return false;
    if ((-c.y - tile.y0 * c.z + tile.oy0) * tile.invNormY0 > r) return false;
    if (useDepthBox) {
        float boxMinX = min(tile.ox0 + tile.x0 * tile.dMin, tile.ox0 + tile.x0 * tile.dMax);
        float boxMaxX = max(tile.ox1 + tile.x1 * tile.dMin, tile.ox1 + tile.x1 * tile.dMax);
        float boxMinY = min(tile.oy0 + tile.y0 * tile.dMin, tile.oy0 + tile.y0 * tile.dMax);
        float boxMaxY = max(tile.oy1 + tile.y1 * tile.dMin, tile.oy1 + tile.y1 * tile.dMax);
        float ex = max(max(boxMinX - c.x, c.x - boxMaxX), 0.0);
        float ey = max(max(boxMinY - c.y, c.y - boxMaxY), 0.0);
        float ez = max(max(tile.dMin - d, d - tile.dMax), 0.0);
        if (ex * ex + ey * ey + ez * ez > r * r) return false;
    }
    return true;
}

#endif
