// Light packing, the CPU tile builder and the culling analysis (CPU only, no device).
// Conservativeness is checked against findMissingLights' per-pixel brute force on synthetic
// depth buffers with lights at the hard spots (docs/LIGHTING.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <limits>
#include <random>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "janus/renderer/light_grid.h"

namespace janus::renderer {
namespace {

Light pointLight(glm::vec3 position, float range, glm::vec3 color = glm::vec3(1.0f), float intensity = 1.0f) {
    Light light;
    light.type = LightType::Point;
    light.position = position;
    light.range = range;
    light.color = color;
    light.intensity = intensity;
    return light;
}

Light spotLight(glm::vec3 position, glm::vec3 direction, float range, float inner, float outer) {
    Light light = pointLight(position, range);
    light.type = LightType::Spot;
    light.direction = direction;
    light.innerConeAngle = inner;
    light.outerConeAngle = outer;
    return light;
}

Camera testCamera() {
    Camera camera;
    camera.position = {0.0f, 1.5f, 4.0f};
    camera.target = {0.0f, 0.8f, 0.0f};
    camera.nearPlane = 0.1f;
    camera.farPlane = 50.0f;
    return camera;
}

// The same place seen through an orthographic camera whose near plane is at the eye.
Camera orthographicTestCamera() {
    Camera camera = testCamera();
    camera.projection = CameraProjection::Orthographic;
    camera.orthographicHalfHeight = 2.0f;
    camera.nearPlane = 0.0f;
    return camera;
}

struct CameraCase {
    const char* name;
    Camera camera;
};

void PrintTo(const CameraCase& cameraCase, std::ostream* os) { *os << cameraCase.name; }

std::vector<CameraCase> cameraCases() { return {{"perspective", testCamera()}, {"orthographic", orthographicTestCamera()}}; }

bool isOrthographic(const TileGrid& grid) { return isOrthographicProjection(grid.projection); }

// Stored depth for view distance d: the projection's z / w at z = -d (perspective: P32 / d - P22,
// the inverse of d = P32 / (z + P22); orthographic: P32 - P22 d).
float storedDepth(const TileGrid& grid, double d) {
    if (isOrthographic(grid)) return float(double(grid.projection[3][2]) - double(grid.projection[2][2]) * d);
    return float(double(grid.projection[3][2]) / d - double(grid.projection[2][2]));
}

// The view-space ray through pixel (x, y)'s centre as origin + d * direction, d the distance
// along the view axis: from the eye for perspective, parallel to the axis for orthographic.
struct PixelRay {
    glm::dvec3 origin, direction;
};
PixelRay pixelRay(const TileGrid& grid, uint32_t x, uint32_t y) {
    const double ndcX = 2.0 * (x + 0.5) / grid.width - 1.0, ndcY = 2.0 * (y + 0.5) / grid.height - 1.0;
    const double a = ndcX / grid.projection[0][0], b = ndcY / grid.projection[1][1];
    if (isOrthographic(grid)) return {{a, b, 0.0}, {0.0, 0.0, -1.0}};
    return {{0.0, 0.0, 0.0}, {a, b, -1.0}};
}

// A room: floor y = 0, back wall z = -3, side walls x = +-2.5; the sky (depth 1) above y = 3.
std::vector<float> roomDepth(const TileGrid& grid) {
    const glm::dmat4 toWorld = glm::inverse(glm::dmat4(grid.view));
    std::vector<float> depth(size_t(grid.width) * grid.height, 1.0f);
    for (uint32_t y = 0; y < grid.height; ++y)
        for (uint32_t x = 0; x < grid.width; ++x) {
            const PixelRay ray = pixelRay(grid, x, y);
            const glm::dvec3 eye = glm::dvec3(toWorld * glm::dvec4(ray.origin, 1.0));
            const glm::dvec3 dir = glm::dmat3(toWorld) * ray.direction;
            double best = std::numeric_limits<double>::infinity();
            auto consider = [&](double t) {
                if (t <= 0.0) return;
                const glm::dvec3 p = eye + t * dir;
                if (p.y < -1e-9 || p.y > 3.0 || p.z < -3.0 - 1e-9 || std::abs(p.x) > 2.5 + 1e-9) return;
                best = std::min(best, t);
            };
            if (dir.y != 0) consider(-eye.y / dir.y);
            if (dir.z != 0) consider((-3.0 - eye.z) / dir.z);
            if (dir.x != 0) consider((2.5 - eye.x) / dir.x), consider((-2.5 - eye.x) / dir.x);
            if (best >= grid.nearPlane && best <= grid.farPlane) depth[size_t(y) * grid.width + x] = storedDepth(grid, best);
        }
    return depth;
}

std::vector<float> staircaseDepth(const TileGrid& grid) {
    std::vector<float> depth(size_t(grid.width) * grid.height, 1.0f);
    for (uint32_t y = 0; y < grid.height; ++y)
        for (uint32_t x = 0; x < grid.width; ++x) {
            if ((x / 13 + y / 11) % 5 == 4) continue;   // holes of sky
            depth[size_t(y) * grid.width + x] = storedDepth(grid, 0.3 + 0.45 * (x / 9) + 0.2 * (y / 17));
        }
    return depth;
}

std::vector<float> randomDepth(const TileGrid& grid, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> distance(grid.nearPlane, 12.0);
    std::uniform_int_distribution<int> sky(0, 9);
    std::vector<float> depth(size_t(grid.width) * grid.height, 1.0f);
    for (float& z : depth)
        if (sky(rng) != 0) z = storedDepth(grid, distance(rng));
    return depth;
}

// Lights at the hard spots plus a deterministic scatter of small ones.
Scene hardLightsScene(const Camera& camera) {
    Scene scene;
    scene.camera = camera;
    auto& lights = scene.lights;
    lights.push_back(pointLight(camera.position, 1.0f));                                   // camera inside
    const glm::vec3 forward = glm::normalize(camera.target - camera.position);
    lights.push_back(pointLight(camera.position + forward * camera.nearPlane + glm::vec3(0.3f, 0, 0), 0.4f));   // straddles near
    lights.push_back(pointLight(camera.position - forward * 0.6f, 1.2f));                  // behind the camera, reaching in
    lights.push_back(pointLight(camera.position - forward * 3.0f, 0.5f));                  // behind, reaching nothing
    lights.push_back(pointLight({6.0f, 1.0f, 0.0f}, 4.0f));                                // off-screen, reaching in
    lights.push_back(pointLight({0.0f, 1.0f, -1.0f}, 1000.0f));                            // huge
    lights.push_back(spotLight({0.0f, 2.9f, -1.0f}, {0, -1, 0}, 4.0f, 0.3f, 0.3f));        // inner == outer
    lights.push_back(spotLight({-2.0f, 0.5f, -2.5f}, {1, 0, 0.2f}, 3.0f, 0.1f, 0.6f));
    lights.push_back(pointLight({0.0f, 0.0f, 0.0f}, 0.05f));                               // tiny, on the floor
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> ux(-2.8f, 2.8f), uy(-0.2f, 3.2f), uz(-3.3f, 2.0f), ur(0.05f, 1.5f);
    for (int i = 0; i < 60; ++i) {
        if (i % 3 == 0)
            lights.push_back(spotLight({ux(rng), uy(rng), uz(rng)}, {ux(rng), -1.0f, ux(rng)}, ur(rng) * 2.0f, 0.2f, 0.7f));
        else
            lights.push_back(pointLight({ux(rng), uy(rng), uz(rng)}, ur(rng)));
    }
    return scene;
}

std::string describe(const std::vector<MissingLight>& missing) {
    std::string text;
    for (const MissingLight& m : missing) text += fmt::format(" light {} at pixel ({}, {});", m.light, m.x, m.y);
    return text;
}

struct DepthCase {
    const char* name;
    std::vector<float> depth;
};

std::vector<DepthCase> depthCases(const TileGrid& grid) {
    return {{"room", roomDepth(grid)}, {"staircase", staircaseDepth(grid)}, {"random", randomDepth(grid, 3)}};
}

TEST(LightGrid, PackedLayoutMatchesTheShaders) {
    EXPECT_EQ(offsetof(PackedLight, position), 0u);
    EXPECT_EQ(offsetof(PackedLight, invRangeSq), 12u);
    EXPECT_EQ(offsetof(PackedLight, radiance), 16u);
    EXPECT_EQ(offsetof(PackedLight, type), 28u);
    EXPECT_EQ(offsetof(PackedLight, direction), 32u);
    EXPECT_EQ(offsetof(PackedLight, renderingLayers), 44u);
    EXPECT_EQ(offsetof(PackedLight, spotScale), 48u);
    EXPECT_EQ(offsetof(PackedLight, spotOffset), 52u);
    EXPECT_EQ(offsetof(PackedLight, shadowIndex), 56u);
    EXPECT_EQ(offsetof(CullUniforms, grid), 192u);
    EXPECT_EQ(offsetof(CullUniforms, counts), 208u);
    EXPECT_EQ(offsetof(CullUniforms, planes), 224u);
}

TEST(LightGrid, PacksValuesAndSkipsLightsThatLightNothing) {
    Scene scene;
    Light sun;   // directional: not a local light
    scene.lights.push_back(sun);
    Light point = pointLight({1, 2, 3}, 2.0f, {0.5f, 1.0f, 0.25f}, 4.0f);
    point.renderingLayers = 0x6u;
    scene.lights.push_back(point);
    scene.lights.push_back(spotLight({0, 1, 0}, {0, -2, 0}, 5.0f, 0.4f, 0.4f));   // inner == outer
    scene.lights.push_back(pointLight({0, 0, 0}, 0.0f));                           // range 0
    scene.lights.push_back(pointLight({0, 0, 0}, -1.0f));                          // negative range
    scene.lights.push_back(pointLight({0, 0, 0}, 1.0f, glm::vec3(0.0f)));          // black
    scene.lights.push_back(pointLight({0, 0, 0}, 1.0f, glm::vec3(1.0f), 0.0f));    // zero intensity
    Light noRange = pointLight({0, 0, 0}, 1.0f, {0.2f, 0.8f, 0.1f}, 50.0f);
    noRange.range.reset();
    scene.lights.push_back(noRange);

    const PackedLights packed = packLocalLights(scene, 0.01f);
    ASSERT_EQ(packed.lights.size(), 3u);
    EXPECT_EQ(packed.skipped, 4u);
    EXPECT_EQ(packed.sceneLightIndex, (std::vector<uint32_t>{1, 2, 7}));

    const PackedLight& p = packed.lights[0];
    EXPECT_EQ(p.type, kLocalLightTypePoint);
    EXPECT_EQ(p.position, glm::vec3(1, 2, 3));
    EXPECT_FLOAT_EQ(p.invRangeSq, 0.25f);
    EXPECT_EQ(p.radiance, glm::vec3(2.0f, 4.0f, 1.0f));
    EXPECT_EQ(p.renderingLayers, 0x6u);
    EXPECT_EQ(p.spotScale, 0.0f);
    EXPECT_EQ(p.spotOffset, 1.0f);
    EXPECT_EQ(p.shadowIndex, -1);

    const PackedLight& s = packed.lights[1];
    EXPECT_EQ(s.type, kLocalLightTypeSpot);
    EXPECT_EQ(s.direction, glm::vec3(0, -1, 0));   // normalised
    ASSERT_TRUE(std::isfinite(s.spotScale) && std::isfinite(s.spotOffset));
    // The cone is 1 just inside the edge and 0 just outside, even with no falloff band.
    const float cosOuter = std::cos(0.4f);
    EXPECT_NEAR(s.spotScale, 1e4f, 1.0f);
    EXPECT_GT(std::clamp(std::cos(0.39f) * s.spotScale + s.spotOffset, 0.0f, 1.0f), 0.99f);
    EXPECT_EQ(std::clamp(std::cos(0.41f) * s.spotScale + s.spotOffset, 0.0f, 1.0f), 0.0f);
    EXPECT_NEAR(cosOuter * s.spotScale + s.spotOffset, 0.0f, 1e-2f);   // float cancellation of ~1e4-sized terms

    // No range: radius where max(colour) * intensity / r^2 falls to the cut-off.
    const float radius = std::sqrt(0.8f * 50.0f / 0.01f);
    EXPECT_FLOAT_EQ(cullingRadius(noRange, 0.01f), radius);
    EXPECT_NEAR(packed.lights[2].invRangeSq, 1.0f / (radius * radius), 1e-9f);
    EXPECT_TRUE(std::isinf(cullingRadius(noRange, 0.0f)));
    EXPECT_EQ(packLocalLights(scene, 0.0f).lights[2].invRangeSq, 0.0f);   // infinite: Naive only
    EXPECT_EQ(cullingRadius(point, 0.0f), 2.0f);                          // a glTF range wins over the cut-off
}

// A range (or cut-off radius) whose square underflows to 0 used to pack as invRangeSq = 0, the
// encoding of an infinite range: the tiniest light lit the whole scene.
TEST(LightGrid, TinyRangesStayTinyInsteadOfBecomingInfinite) {
    Scene scene;
    scene.lights.push_back(pointLight({0, 0, 0}, 1e-25f));
    Light dim = pointLight({1, 0, 0}, 1.0f, glm::vec3(1.0f), 1e-38f);
    dim.range.reset();   // radius from the cut-off: sqrt(1e-38 / 0.01) = 1e-18, whose square is at the edge
    scene.lights.push_back(dim);
    const PackedLights packed = packLocalLights(scene, 0.01f);
    ASSERT_EQ(packed.lights.size(), 2u);
    for (const PackedLight& light : packed.lights) {
        EXPECT_TRUE(std::isfinite(light.invRangeSq));
        EXPECT_GT(light.invRangeSq, 1e35f) << "a tiny light must have a tiny range, not an infinite one";
    }
}

// The automatic cap: the light count (no tile meets more), within 1024, the 32 MiB budget (never
// below 256 for it) and the device.
TEST(LightGrid, AnAutomaticCapIsTheLightCountWithinTheBudgetAndTheDevice) {
    const size_t tiles1080p = 120 * 68, tiles4k = 240 * 135, tiles8k = 480 * 270;
    EXPECT_EQ(autoMaxLightsPerTile(24, 256), 24u);
    EXPECT_EQ(autoMaxLightsPerTile(300, 256), 300u);
    EXPECT_EQ(autoMaxLightsPerTile(5000, 256), kMaxLightsPerTileLimit);
    EXPECT_EQ(autoMaxLightsPerTile(2048, tiles1080p), 1024u) << "1080p in 16 px tiles holds 1024 within 32 MiB";
    const uint32_t at4k = autoMaxLightsPerTile(2048, tiles4k);
    EXPECT_EQ(at4k, uint32_t(kAutoTileListBudgetBytes / (4 * tiles4k) - 1));
    EXPECT_LE(uint64_t(tiles4k) * (1 + at4k) * 4, kAutoTileListBudgetBytes);
    EXPECT_GT(uint64_t(tiles4k) * (2 + at4k) * 4, kAutoTileListBudgetBytes) << "the largest cap within the budget";
    EXPECT_EQ(autoMaxLightsPerTile(2048, tiles8k), kAutoMaxLightsPerTileFloor) << "the budget never takes it below the floor";
    EXPECT_EQ(autoMaxLightsPerTile(100, tiles8k), 100u) << "nor above the light count";
    EXPECT_EQ(autoMaxLightsPerTile(2048, tiles8k, 40), 40u) << "the device's limit wins over the floor";
    EXPECT_EQ(autoMaxLightsPerTile(0, 256), 1u);
    EXPECT_EQ(autoMaxLightsPerTile(2048, 0), 1024u);
    EXPECT_EQ(autoMaxLightsPerTile(2048, size_t(1) << 40), kAutoMaxLightsPerTileFloor) << "a budget below one word a tile is the floor";
}

TEST(LightGrid, TooManyLightsNamesTheLimit) {
    Scene scene;
    scene.lights.assign(kMaxLocalLights + 1, pointLight({0, 0, 0}, 1.0f));
    try {
        packLocalLights(scene, 0.01f);
        FAIL() << "expected RendererError";
    } catch (const RendererError& error) {
        EXPECT_NE(std::string(error.what()).find("16385"), std::string::npos) << error.what();
        EXPECT_NE(std::string(error.what()).find("16384"), std::string::npos) << error.what();
    }
}

// The orthographic projection by hand: the view box [-h * aspect, h * aspect] x [-h, h] x
// [near, far] maps to NDC [-1, 1]^2 x [0, 1] with y flipped (NDC y = -1 is row 0, the top).
TEST(LightGrid, OrthographicProjectionMapsTheViewBoxToClipSpace) {
    Camera camera;
    camera.projection = CameraProjection::Orthographic;
    camera.orthographicHalfHeight = 2.0f;
    camera.nearPlane = 1.0f;
    camera.farPlane = 11.0f;
    const glm::mat4 projection = makeProjection(camera, 300, 200);   // aspect 1.5: half width 3
    auto ndc = [&](glm::vec3 view) {
        const glm::vec4 clip = projection * glm::vec4(view, 1.0f);
        EXPECT_EQ(clip.w, 1.0f);
        return glm::vec3(clip) / clip.w;
    };
    const glm::vec3 topRightNear = ndc({3.0f, 2.0f, -1.0f}), bottomLeftFar = ndc({-3.0f, -2.0f, -11.0f});
    const glm::vec3 middle = ndc({0.75f, -0.5f, -6.0f});
    EXPECT_NEAR(topRightNear.x, 1.0f, 1e-6f);
    EXPECT_NEAR(topRightNear.y, -1.0f, 1e-6f);
    EXPECT_NEAR(topRightNear.z, 0.0f, 1e-6f);
    EXPECT_NEAR(bottomLeftFar.x, -1.0f, 1e-6f);
    EXPECT_NEAR(bottomLeftFar.y, 1.0f, 1e-6f);
    EXPECT_NEAR(bottomLeftFar.z, 1.0f, 1e-6f);
    EXPECT_NEAR(middle.x, 0.25f, 1e-6f);
    EXPECT_NEAR(middle.y, 0.25f, 1e-6f);
    EXPECT_NEAR(middle.z, 0.5f, 1e-6f);
}

// An orthographic camera at the origin looking down -Z, 2 x 2 world units seen from distance 0 to
// `far`, as a 32 x 32 grid of 16-pixel tiles.
TileGrid orthographicGridDownZ(float far) {
    Camera camera;
    camera.position = glm::vec3(0.0f);
    camera.target = glm::vec3(0.0f, 0.0f, -1.0f);
    camera.projection = CameraProjection::Orthographic;
    camera.orthographicHalfHeight = 1.0f;
    camera.nearPlane = 0.0f;
    camera.farPlane = far;
    return makeTileGrid(camera, 32, 32, 16, kMaxLocalLights);
}

// Orthographic tiles are boxes: what a tile lists does not depend on how far along the view axis
// a light is, and a light beside the view box is listed nowhere however far away it is (through
// a perspective tile, whose planes open out, both would differ).
TEST(LightGrid, OrthographicTilesAreBoxes) {
    const TileGrid grid = orthographicGridDownZ(500.0f);   // 2 x 2 tiles of 1 x 1 world units
    for (float distance : {0.5f, 20.0f, 400.0f}) {
        Scene scene;
        scene.lights.push_back(pointLight({0.8f, 0.8f, -distance}, 0.1f));    // upper right tile only
        scene.lights.push_back(pointLight({1.3f, 0.0f, -distance}, 0.2f));    // right of the view box
        scene.lights.push_back(pointLight({-0.5f, -0.05f, -distance}, 0.1f)); // both left tiles
        const PackedLights packed = packLocalLights(scene, 0.01f);
        const TileLists lists = buildTileListsCpu(grid, packed.lights, {});
        auto tileList = [&](uint32_t tx, uint32_t ty) {
            const size_t tile = size_t(ty) * lists.tilesX + tx;
            return std::vector<uint32_t>(lists.indices.begin() + tile * lists.maxLightsPerTile,
                                         lists.indices.begin() + tile * lists.maxLightsPerTile + lists.counts[tile]);
        };
        // Row 0 is the top (+y).
        EXPECT_EQ(tileList(1, 0), std::vector<uint32_t>{0u}) << distance;
        EXPECT_EQ(tileList(0, 0), std::vector<uint32_t>{2u}) << distance;
        EXPECT_EQ(tileList(0, 1), std::vector<uint32_t>{2u}) << distance;
        EXPECT_EQ(tileList(1, 1), std::vector<uint32_t>{}) << distance;
    }
}

// Orthographic depth is linear in distance: a wall's stored depth reads back within a tenth of a
// millimetre at any distance (perspective: metres at 600 m, see above), so a light just in front
// of the wall is listed and one just behind is not.
TEST(LightGrid, OrthographicDepthBoundsAreTightAtAnyDistance) {
    const TileGrid grid = orthographicGridDownZ(1000.0f);
    for (double wall : {1.0, 37.5, 600.0, 999.0}) {
        const std::vector<float> depth(32 * 32, storedDepth(grid, wall));
        Scene scene;
        // The margins allow 1e-5 of the distance (1 cm at 1 km) for float rounding: 3 cm is beyond it.
        scene.lights.push_back(pointLight({0.0f, 0.0f, float(-(wall - 0.1))}, 0.13f));   // reaches 3 cm into the wall
        scene.lights.push_back(pointLight({0.0f, 0.0f, float(-(wall + 0.1))}, 0.07f));   // stops 3 cm behind it
        const TileLists lists = buildTileListsCpu(grid, packLocalLights(scene, 0.01f).lights, depth);
        for (uint32_t t = 0; t < grid.tileCount(); ++t) {
            ASSERT_EQ(lists.counts[t], 1u) << "wall at " << wall << ", tile " << t;
            EXPECT_EQ(lists.indices[t * lists.maxLightsPerTile], 0u) << "wall at " << wall << ", tile " << t;
        }
    }
}

// The tests below run through a perspective camera and an orthographic one at the same place.
class LightGridCameras : public testing::TestWithParam<CameraCase> {};

TEST_P(LightGridCameras, ListsAreConservativeOnBothModes) {
    const Camera camera = GetParam().camera;
    const PackedLights packed = packLocalLights(hardLightsScene(camera), 0.01f);
    for (uint32_t tileSize : {16u, 32u}) {
        // 100 x 75: partial tiles on the right and bottom edges.
        const TileGrid grid = makeTileGrid(camera, 100, 75, tileSize, kMaxLocalLights);
        for (const DepthCase& c : depthCases(grid)) {
            for (bool useDepth : {false, true}) {
                const std::span<const float> depth = useDepth ? std::span<const float>(c.depth) : std::span<const float>();
                const TileLists lists = buildTileListsCpu(grid, packed.lights, depth);
                const auto missing = findMissingLights(grid, packed.lights, lists, c.depth);
                EXPECT_TRUE(missing.empty()) << c.name << (useDepth ? " depth" : " 2d") << " tile " << tileSize << ":"
                                             << describe(missing);
                for (uint32_t t = 0; t < grid.tileCount(); ++t)
                    for (uint32_t k = 1; k < lists.counts[t]; ++k)
                        ASSERT_LT(lists.indices[t * lists.maxLightsPerTile + k - 1], lists.indices[t * lists.maxLightsPerTile + k]);
            }
        }
    }
}

// Far / near = 1e5 (near 0.01 m, far 1 km): a wall 600 m away has D32F depth steps of about 2 m,
// so its stored depth can read back a metre nearer than the wall. A light whose sphere reaches
// 0.2 m in front of the wall lights it, and the tiles around it must list it; the old margin
// (1e-5 of the distance: 6 mm) culled it wherever the depth rounded towards the camera.
TEST(LightGrid, DepthMarginsFollowD32FPrecisionAtFarOverNearOf1e5) {
    Camera camera;
    camera.position = glm::vec3(0.0f);
    camera.target = glm::vec3(0.0f, 0.0f, -1.0f);
    camera.nearPlane = 0.01f;
    camera.farPlane = 1000.0f;
    const TileGrid grid = makeTileGrid(camera, 32, 32, 16, kMaxLocalLights);   // 4 tiles meet on the view axis
    uint32_t found = 0;
    for (double wall = 500.0; wall < 700.0 && found < 8; wall += 0.37) {
        const float z = storedDepth(grid, wall);
        const double readBack = double(grid.projection[3][2]) / (double(z) + double(grid.projection[2][2]));
        if (readBack > wall - 0.5) continue;   // only walls whose depth rounds at least 0.5 m nearer
        ++found;
        Scene scene;
        scene.lights.push_back(pointLight({0.0f, 0.0f, float(-(wall + 2.0))}, 2.2f));
        const PackedLights packed = packLocalLights(scene, 0.01f);
        const TileLists lists = buildTileListsCpu(grid, packed.lights, std::vector<float>(32 * 32, z));
        for (uint32_t t = 0; t < grid.tileCount(); ++t)
            EXPECT_EQ(lists.counts[t], 1u) << "wall at " << wall << " m (its depth reads " << readBack << " m), tile " << t;
    }
    EXPECT_GE(found, 4u) << "too few walls whose depth rounds towards the camera: the test checks nothing";
    // The margin stays small where depth is precise: 1 m away it is well under a millimetre.
    std::vector<float> near(32 * 32, storedDepth(grid, 1.0));
    Scene behind;
    behind.lights.push_back(pointLight({0.0f, 0.0f, -1.01f}, 0.005f));   // 5 mm behind the 1 m wall, 5 mm radius
    const TileLists lists = buildTileListsCpu(grid, packLocalLights(behind, 0.01f).lights, near);
    for (uint32_t t = 0; t < grid.tileCount(); ++t) EXPECT_EQ(lists.counts[t], 0u) << "tile " << t << ": a light behind the wall is listed";
}

TEST_P(LightGridCameras, HardLightsAreListedWhereTheyLight) {
    const Camera camera = GetParam().camera;
    const PackedLights packed = packLocalLights(hardLightsScene(camera), 0.01f);
    const TileGrid grid = makeTileGrid(camera, 100, 75, 16, kMaxLocalLights);
    std::vector<float> depth = roomDepth(grid);
    std::fill(depth.begin(), depth.begin() + 16 * grid.width, 1.0f);   // the top tile row sees only sky
    const TileLists lists = buildTileListsCpu(grid, packed.lights, depth);
    auto listedSomewhere = [&](uint32_t light) {
        for (uint32_t t = 0; t < grid.tileCount(); ++t)
            for (uint32_t k = 0; k < lists.counts[t]; ++k)
                if (lists.indices[t * lists.maxLightsPerTile + k] == light) return true;
        return false;
    };
    EXPECT_TRUE(listedSomewhere(5));    // huge
    EXPECT_FALSE(listedSomewhere(3));   // behind the camera, out of reach: culling does cull
    for (uint32_t tx = 0; tx < grid.tilesX(); ++tx)
        EXPECT_EQ(lists.counts[tx], 0u) << "tile " << tx << " has no geometry and must list nothing in TilesDepth";
}

TEST_P(LightGridCameras, SpotBoundsAreConservativeAndTighter) {
    const Camera camera = GetParam().camera;
    Scene scene;
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> ux(-2.8f, 2.8f), uy(-0.2f, 3.2f), uz(-3.3f, 2.0f), unit(-1.0f, 1.0f);
    std::uniform_real_distribution<float> angle(0.02f, 1.5707f), range(0.3f, 4.0f);
    for (int i = 0; i < 80; ++i) {
        const float outer = angle(rng);
        // Every other spot has inner == outer (the guarded hard edge).
        const float inner = i % 2 == 0 ? outer : outer * 0.5f;
        scene.lights.push_back(spotLight({ux(rng), uy(rng), uz(rng)}, {unit(rng), unit(rng), unit(rng)}, range(rng), inner, outer));
    }
    const PackedLights packed = packLocalLights(scene, 0.01f);
    const TileGrid grid = makeTileGrid(camera, 100, 75, 16, kMaxLocalLights);
    for (const DepthCase& c : depthCases(grid))
        for (bool useDepth : {false, true}) {
            const std::span<const float> depth = useDepth ? std::span<const float>(c.depth) : std::span<const float>();
            const TileLists lists = buildTileListsCpu(grid, packed.lights, depth);
            const auto missing = findMissingLights(grid, packed.lights, lists, c.depth);
            EXPECT_TRUE(missing.empty()) << c.name << (useDepth ? " depth" : " 2d") << ":" << describe(missing);
            // The check means something only if the cones do reach geometry.
            EXPECT_GT(measureCullingEfficiency(grid, packed.lights, &lists, c.depth).contributing, 1000u) << c.name;
        }
    // The same lights as points (range spheres) are listed in more tiles than the cone bounds.
    std::vector<PackedLight> asPoints = packed.lights;
    for (PackedLight& light : asPoints) light.type = kLocalLightTypePoint, light.spotScale = 0.0f, light.spotOffset = 1.0f;
    TileBuildStats spots, points;
    buildTileListsCpu(grid, packed.lights, {}, &spots);
    buildTileListsCpu(grid, asPoints, {}, &points);
    EXPECT_LT(spots.listedLights, points.listedLights);
}

TEST_P(LightGridCameras, DepthListsAreSubsetsOf2DLists) {
    const Camera camera = GetParam().camera;
    const PackedLights packed = packLocalLights(hardLightsScene(camera), 0.01f);
    const TileGrid grid = makeTileGrid(camera, 100, 75, 16, kMaxLocalLights);
    for (const DepthCase& c : depthCases(grid)) {
        const TileLists flat = buildTileListsCpu(grid, packed.lights, {});
        const TileLists deep = buildTileListsCpu(grid, packed.lights, c.depth);
        for (uint32_t t = 0; t < grid.tileCount(); ++t) {
            const uint32_t* a = flat.indices.data() + t * flat.maxLightsPerTile;
            const uint32_t* b = deep.indices.data() + t * deep.maxLightsPerTile;
            EXPECT_TRUE(std::includes(a, a + flat.counts[t], b, b + deep.counts[t])) << c.name << " tile " << t;
        }
    }
}

TEST(LightGrid, OutputDoesNotDependOnThreadCount) {
    const Camera camera = testCamera();
    const PackedLights packed = packLocalLights(hardLightsScene(camera), 0.01f);
    const TileGrid grid = makeTileGrid(camera, 160, 90, 16, 8);
    const std::vector<float> depth = randomDepth(grid, 11);
    TileBuildStats reference;
    const TileLists one = buildTileListsCpu(grid, packed.lights, depth, &reference, 1);
    for (unsigned threads : {2u, 3u, 8u, 0u}) {
        TileBuildStats stats;
        const TileLists many = buildTileListsCpu(grid, packed.lights, depth, &stats, threads);
        EXPECT_EQ(many.counts, one.counts) << threads;
        EXPECT_EQ(many.indices, one.indices) << threads;
        EXPECT_EQ(stats.listedLights, reference.listedLights);
        EXPECT_EQ(stats.overflowTiles, reference.overflowTiles);
        EXPECT_EQ(stats.droppedLights, reference.droppedLights);
        EXPECT_EQ(stats.densestTileLights, reference.densestTileLights);
    }
}

TEST(LightGrid, OverflowKeepsTheLowestIndicesAndIsCounted) {
    const Camera camera = testCamera();
    const PackedLights packed = packLocalLights(hardLightsScene(camera), 0.01f);
    const TileGrid uncappedGrid = makeTileGrid(camera, 100, 75, 32, kMaxLocalLights);
    const TileGrid cappedGrid = makeTileGrid(camera, 100, 75, 32, 3);
    const std::vector<float> depth = roomDepth(uncappedGrid);
    TileBuildStats uncappedStats, cappedStats;
    const TileLists uncapped = buildTileListsCpu(uncappedGrid, packed.lights, depth, &uncappedStats);
    const TileLists capped = buildTileListsCpu(cappedGrid, packed.lights, depth, &cappedStats);
    EXPECT_EQ(uncappedStats.overflowTiles, 0u);
    EXPECT_EQ(uncappedStats.droppedLights, 0u);
    uint32_t overflowTiles = 0, densest = 0;
    uint64_t dropped = 0, listed = 0;
    for (uint32_t t = 0; t < uncappedGrid.tileCount(); ++t) {
        const uint32_t all = uncapped.counts[t];
        densest = std::max(densest, all);
        ASSERT_EQ(capped.counts[t], std::min(all, 3u));
        for (uint32_t k = 0; k < capped.counts[t]; ++k)
            EXPECT_EQ(capped.indices[t * 3 + k], uncapped.indices[t * uncapped.maxLightsPerTile + k]);
        if (all > 3) ++overflowTiles, dropped += all - 3;
        listed += capped.counts[t];
    }
    EXPECT_GT(overflowTiles, 0u);
    EXPECT_EQ(cappedStats.overflowTiles, overflowTiles);
    EXPECT_EQ(cappedStats.droppedLights, dropped);
    EXPECT_EQ(cappedStats.listedLights, listed);
    EXPECT_EQ(uncappedStats.listedLights, listed + dropped);
    // The densest tile's count, capped or not: the cap that would drop nothing.
    EXPECT_GT(densest, 3u);
    EXPECT_EQ(cappedStats.densestTileLights, densest);
    EXPECT_EQ(uncappedStats.densestTileLights, densest);
}

TEST_P(LightGridCameras, BruteForceCatchesARemovedLight) {
    const Camera camera = GetParam().camera;
    const PackedLights packed = packLocalLights(hardLightsScene(camera), 0.01f);
    const TileGrid grid = makeTileGrid(camera, 100, 75, 16, kMaxLocalLights);
    const std::vector<float> depth = roomDepth(grid);
    TileLists lists = buildTileListsCpu(grid, packed.lights, depth);
    // Drop the huge light 5, which lights every geometry pixel, from the first tile that lists it.
    bool removed = false;
    for (uint32_t t = 0; t < grid.tileCount() && !removed; ++t) {
        uint32_t* list = lists.indices.data() + t * lists.maxLightsPerTile;
        uint32_t* end = list + lists.counts[t];
        uint32_t* hit = std::find(list, end, 5u);
        if (hit == end) continue;
        std::copy(hit + 1, end, hit);
        --lists.counts[t];
        removed = true;
    }
    ASSERT_TRUE(removed);
    const auto missing = findMissingLights(grid, packed.lights, lists, depth, 4);
    ASSERT_FALSE(missing.empty());
    EXPECT_EQ(missing[0].light, 5u);
    EXPECT_LE(missing.size(), 4u);
}

TEST_P(LightGridCameras, DepthAwareCullingIsMoreEfficient) {
    const Camera camera = GetParam().camera;
    Scene scene = hardLightsScene(camera);
    scene.lights.erase(scene.lights.begin(), scene.lights.begin() + 9);   // the scatter only: a room full of small lights
    const PackedLights packed = packLocalLights(scene, 0.01f);
    const TileGrid grid = makeTileGrid(camera, 160, 120, 16, kMaxLocalLights);
    const std::vector<float> depth = roomDepth(grid);
    const CullingEfficiency naive = measureCullingEfficiency(grid, packed.lights, nullptr, depth);
    const TileLists flatLists = buildTileListsCpu(grid, packed.lights, {});
    const TileLists deepLists = buildTileListsCpu(grid, packed.lights, depth);
    const CullingEfficiency flat = measureCullingEfficiency(grid, packed.lights, &flatLists, depth);
    const CullingEfficiency deep = measureCullingEfficiency(grid, packed.lights, &deepLists, depth);
    // Conservative lists evaluate every contributing light, so all three see the same contributions.
    EXPECT_EQ(flat.contributing, naive.contributing);
    EXPECT_EQ(deep.contributing, naive.contributing);
    EXPECT_GT(naive.contributing, 0u);
    EXPECT_LT(flat.performed, naive.performed);
    EXPECT_LT(deep.performed, flat.performed);
    EXPECT_GT(deep.ratio(), flat.ratio());
    EXPECT_GT(flat.ratio(), naive.ratio());
}

TEST(LightGrid, TileDataRoundTrips) {
    const Camera camera = testCamera();
    const PackedLights packed = packLocalLights(hardLightsScene(camera), 0.01f);
    const TileGrid grid = makeTileGrid(camera, 100, 75, 16, 5);
    const TileLists lists = buildTileListsCpu(grid, packed.lights, {});
    const std::vector<uint32_t> data = flattenTileData(lists);
    ASSERT_EQ(data.size(), size_t(grid.tileCount()) * 6);
    for (uint32_t t = 0; t < grid.tileCount(); ++t) {
        EXPECT_EQ(data[t], lists.counts[t]);
        for (uint32_t k = 0; k < lists.counts[t]; ++k)
            EXPECT_EQ(data[grid.tileCount() + t * 5 + k], lists.indices[t * 5 + k]);
    }
    const TileLists back = unflattenTileData(data, 16, grid.tilesX(), grid.tilesY(), 5);
    EXPECT_EQ(back.counts, lists.counts);
    EXPECT_EQ(back.indices, lists.indices);
    EXPECT_THROW(unflattenTileData(std::span(data).first(data.size() - 1), 16, grid.tilesX(), grid.tilesY(), 5), RendererError);
}

// Transparent surfaces are not in the prepass depth (docs/LIGHTING.md, "Culling"): with
// rangeFromNearPlane, TilesDepth lists lights between the camera and the depth, and lights in
// tiles without depth; the side planes still cull.
TEST(LightGrid, RangesFromTheNearPlaneListLightsInFrontOfTheDepthAndWhereThereIsNone) {
    Camera camera;
    camera.position = {0.0f, 0.0f, 4.0f};
    camera.target = {0.0f, 0.0f, 0.0f};
    camera.fovYRadians = 0.8726646f;   // 50 degrees
    camera.nearPlane = 0.1f;
    camera.farPlane = 50.0f;
    const TileGrid base = makeTileGrid(camera, 64, 64, 16, 32);
    // Depth: the left half holds a wall 10 units away, the right half nothing.
    const glm::vec4 clip = base.projection * glm::vec4(0.0f, 0.0f, -10.0f, 1.0f);
    std::vector<float> depth(64 * 64, 1.0f);
    for (uint32_t y = 0; y < 64; ++y)
        for (uint32_t x = 0; x < 32; ++x) depth[y * 64 + x] = clip.z / clip.w;
    // Two short-range lights 2 units in front of the camera, in front of tile columns 0 (wall
    // behind) and 3 (nothing behind); tile columns span view slopes x/d of about 0.233 each.
    PackedLight left, right;
    left.position = {-0.7f, 0.0f, 2.0f};
    right.position = {0.7f, 0.0f, 2.0f};
    left.invRangeSq = right.invRangeSq = 1.0f / (0.2f * 0.2f);
    const std::vector<PackedLight> lights = {left, right};
    auto listed = [&](const TileLists& lists, uint32_t tx, uint32_t ty, uint32_t light) {
        const size_t tile = size_t(ty) * lists.tilesX + tx;
        for (uint32_t k = 0; k < lists.counts[tile]; ++k)
            if (lists.indices[tile * lists.maxLightsPerTile + k] == light) return true;
        return false;
    };
    const TileLists opaqueOnly = buildTileListsCpu(base, lights, depth);
    EXPECT_FALSE(listed(opaqueOnly, 0, 1, 0)) << "the wall is far behind the light";
    EXPECT_FALSE(listed(opaqueOnly, 3, 1, 1)) << "no depth, no list";
    TileGrid fromNear = base;
    fromNear.rangeFromNearPlane = true;
    const TileLists withGlass = buildTileListsCpu(fromNear, lights, depth);
    EXPECT_TRUE(listed(withGlass, 0, 1, 0));
    EXPECT_TRUE(listed(withGlass, 3, 1, 1));
    EXPECT_FALSE(listed(withGlass, 0, 1, 1)) << "still culled sideways";
    EXPECT_FALSE(listed(withGlass, 3, 1, 0)) << "still culled sideways";
    EXPECT_EQ(makeCullUniforms(fromNear, 2, LightCulling::TilesDepth).planes.z, 1.0f);
    EXPECT_EQ(makeCullUniforms(base, 2, LightCulling::TilesDepth).planes.z, 0.0f);
}

INSTANTIATE_TEST_SUITE_P(Projections, LightGridCameras, testing::ValuesIn(cameraCases()),
                         [](const testing::TestParamInfo<CameraCase>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace janus::renderer
