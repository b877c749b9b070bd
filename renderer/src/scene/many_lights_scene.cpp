// manyLightsScene(): a long hall with pillars and boxes lit by many coloured point and spot
// lights, for Forward+ benchmarks and tests. The camera looks down the hall so the depth range
// inside one screen tile is often large (a pillar in front of the far wall), which is where
// depth-aware culling pays off over 2D tiles.
#include <cmath>
#include <cstdint>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "scene_internal.h"

namespace janus::renderer {
namespace {

// Own generator and float mapping: std::uniform_real_distribution differs between standard
// libraries, and the scene must be the same everywhere for benchmarks to compare.
class Random {
public:
    explicit Random(uint32_t seed) : m_state(0x9E3779B97F4A7C15ull ^ (uint64_t(seed) * 0xD1B54A32D192ED03ull)) {}
    uint32_t next() {   // splitmix64
        uint64_t z = (m_state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return uint32_t((z ^ (z >> 31)) >> 32);
    }
    float uniform() { return float(next() >> 8) * (1.0f / 16777216.0f); }   // [0, 1)
    float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }

private:
    uint64_t m_state;
};

// Fully saturated colour of hue h in [0, 1), mixed a little towards white so no channel is 0.
glm::vec3 hueColor(float h) {
    const glm::vec3 rgb = glm::clamp(glm::abs(glm::mod(h * 6.0f + glm::vec3(0, 4, 2), 6.0f) - 3.0f) - 1.0f, 0.0f, 1.0f);
    return glm::mix(rgb, glm::vec3(1.0f), 0.15f);
}

}  // namespace

Scene manyLightsScene(const ManyLightsOptions& options) {
    using namespace detail;
    Scene scene;
    scene.name = "many-lights";
    Random random(options.seed);

    // Hall interior: x in [-6, 6], y in [0, 4], z in [-12, 12].
    constexpr float halfWidth = 6.0f, height = 4.0f, halfDepth = 12.0f;
    const glm::mat4 I(1.0f);
    const float half = glm::half_pi<float>();
    const int32_t floorMaterial = addMaterial(scene, "floor", glm::vec3(0.55f), 0.0f, 0.35f);
    const int32_t wallMaterial = addMaterial(scene, "wall", glm::vec3(0.7f, 0.68f, 0.64f), 0.0f, 0.85f);
    const uint32_t floorQuad = addMesh(scene, makeQuad(floorMaterial));
    const uint32_t wallQuad = addMesh(scene, makeQuad(wallMaterial));
    auto place = [&](uint32_t mesh, const glm::mat4& world) { scene.instances.push_back(Instance{mesh, world}); };
    auto wall = [&](uint32_t mesh, glm::vec3 center, float angle, glm::vec3 axis, glm::vec2 halfSize) {
        place(mesh, glm::translate(I, center) * glm::rotate(I, angle, axis) * glm::scale(I, glm::vec3(halfSize, 1.0f)));
    };
    wall(floorQuad, {0, 0, 0}, -half, {1, 0, 0}, {halfWidth, halfDepth});
    wall(wallQuad, {0, height, 0}, half, {1, 0, 0}, {halfWidth, halfDepth});
    wall(wallQuad, {0, height / 2, -halfDepth}, 0.0f, {0, 1, 0}, {halfWidth, height / 2});
    wall(wallQuad, {0, height / 2, halfDepth}, glm::pi<float>(), {0, 1, 0}, {halfWidth, height / 2});
    wall(wallQuad, {-halfWidth, height / 2, 0}, half, {0, 1, 0}, {halfDepth, height / 2});
    wall(wallQuad, {halfWidth, height / 2, 0}, -half, {0, 1, 0}, {halfDepth, height / 2});

    // Two rows of floor-to-ceiling pillars, roughness varying along the hall.
    for (int row = 0; row < 6; ++row) {
        const float z = -10.0f + 4.0f * float(row);
        const float roughness = 0.15f + 0.15f * float(row);
        const uint32_t pillar = addMesh(scene, makeBox(addMaterial(scene, "pillar " + std::to_string(row), glm::vec3(0.8f, 0.78f, 0.72f),
                                                                   0.0f, roughness)));
        for (float x : {-3.5f, 3.5f}) place(pillar, glm::translate(I, {x, height / 2, z}) * glm::scale(I, {0.3f, height / 2, 0.3f}));
    }
    // Boxes of varied size, turn and roughness on the floor (depth steps inside tiles); a few metallic.
    for (int i = 0; i < 10; ++i) {
        const float roughness = random.uniform(0.1f, 1.0f);
        const bool metal = i % 4 == 3;
        const glm::vec3 color = metal ? glm::vec3(0.95f, 0.8f, 0.55f) : glm::vec3(random.uniform(0.3f, 0.8f));
        const uint32_t box = addMesh(scene, makeBox(addMaterial(scene, "box " + std::to_string(i), color, metal ? 1.0f : 0.0f, roughness)));
        const glm::vec3 size(random.uniform(0.25f, 0.8f), random.uniform(0.2f, 1.2f), random.uniform(0.25f, 0.8f));
        const glm::vec3 at(random.uniform(-2.8f, 2.8f), size.y, random.uniform(-11.0f, 8.0f));
        place(box, glm::translate(I, at) * glm::rotate(I, random.uniform(0.0f, glm::pi<float>()), {0, 1, 0}) * glm::scale(I, size));
    }

    // A dim moonlight so unlit corners are not black, and the shadow map has something to do.
    Light moon;
    moon.type = LightType::Directional;
    moon.color = glm::vec3(0.6f, 0.7f, 1.0f);
    moon.intensity = 0.15f;
    moon.direction = glm::normalize(glm::vec3(0.3f, -1.0f, -0.4f));
    scene.lights.push_back(moon);

    const float range = options.rangeFraction * 2.0f * halfWidth;
    for (uint32_t i = 0; i < options.lightCount; ++i) {
        Light light;
        light.type = random.uniform() < options.spotFraction ? LightType::Spot : LightType::Point;
        light.color = hueColor(random.uniform());
        light.intensity = options.intensity;
        light.position = glm::vec3(random.uniform(-halfWidth + 0.2f, halfWidth - 0.2f), random.uniform(0.2f, height - 0.2f),
                                   random.uniform(-halfDepth + 0.2f, halfDepth - 0.2f));
        if (options.rangeFraction > 0.0f) light.range = range;
        if (light.type == LightType::Spot) {
            // Mostly downwards, tilted up to ~45 degrees, so the cones land on floor and boxes.
            const float tilt = random.uniform(0.0f, 0.8f), turn = random.uniform(0.0f, glm::two_pi<float>());
            light.direction = glm::normalize(glm::vec3(std::sin(tilt) * std::cos(turn), -std::cos(tilt), std::sin(tilt) * std::sin(turn)));
            light.outerConeAngle = random.uniform(0.35f, 0.8f);
            light.innerConeAngle = light.outerConeAngle * 0.7f;
        }
        scene.lights.push_back(light);
    }

    scene.environment.ambientColor = glm::vec3(0.01f);
    scene.environment.exposure = 1.0f;
    scene.camera.position = glm::vec3(0.0f, 2.2f, 11.0f);
    scene.camera.target = glm::vec3(0.0f, 1.2f, -12.0f);
    scene.camera.fovYRadians = glm::radians(70.0f);
    scene.camera.nearPlane = 0.05f;
    scene.camera.farPlane = 60.0f;
    return scene;
}

}  // namespace janus::renderer
