// The built-in probe-GI scene (`janus render gi-rooms`, docs/GI.md "Visibility"): two rooms side
// by side under one roof, a wall with a doorway between them, and an irradiance volume over both.
//   - the left room's light is a large warm panel on its back wall (emission, no lamp: the
//     reference path tracer meets an area light often, so its images are quiet);
//   - the right room is lit only through the doorway;
//   - the volume's probes stand half a metre either side of the wall, so trilinear weights alone
//     would carry the left room's light through it (IrradianceVolume::visibility stops that).
// Every wall, the floor and the roof are closed slabs (boxes), so the probes see their front faces
// from either side.
#include <glm/gtc/matrix_transform.hpp>

#include "scene_internal.h"

namespace janus::renderer {

using namespace detail;

Scene giRoomsScene() {
    Scene scene;
    scene.name = "gi-rooms";
    // A slab of material m over [lo, hi].
    auto slab = [&](int32_t material, glm::vec3 lo, glm::vec3 hi, const char* name) {
        const glm::mat4 world = glm::scale(glm::translate(glm::mat4(1.0f), (lo + hi) * 0.5f), (hi - lo) * 0.5f);
        scene.instances.push_back(Instance{addMesh(scene, makeBox(material)), world, 1u, name});
    };
    // Inside: x in [-4, 4] (the wall at |x| < 0.1), y in [0, 2.5], z in [-1.5, 1.5].
    constexpr float kHeight = 2.5f, kThickness = 0.2f;
    const int32_t white = addMaterial(scene, "white plaster", glm::vec3(0.75f), 0.0f, 0.9f);
    const int32_t grey = addMaterial(scene, "grey floor", glm::vec3(0.5f), 0.0f, 0.8f);
    slab(grey, {-4.0f, -kThickness, -1.5f}, {4.0f, 0.0f, 1.5f}, "floor");
    slab(white, {-4.0f - kThickness, -kThickness, -1.5f - kThickness}, {-4.0f, kHeight + kThickness, 1.5f + kThickness}, "left wall");
    slab(white, {4.0f, -kThickness, -1.5f - kThickness}, {4.0f + kThickness, kHeight + kThickness, 1.5f + kThickness}, "right wall");
    slab(white, {-4.0f, -kThickness, -1.5f - kThickness}, {4.0f, kHeight + kThickness, -1.5f}, "back wall");
    slab(white, {-4.0f, -kThickness, 1.5f}, {4.0f, kHeight + kThickness, 1.5f + kThickness}, "front wall");
    // The wall between the rooms, with a doorway at z in [0.5, 1.3] up to 2 m.
    slab(white, {-0.1f, 0.0f, -1.5f}, {0.1f, kHeight, 0.5f}, "middle wall");
    slab(white, {-0.1f, 0.0f, 1.3f}, {0.1f, kHeight, 1.5f}, "middle wall, front");
    slab(white, {-0.1f, 2.0f, 0.5f}, {0.1f, kHeight, 1.3f}, "lintel");
    slab(white, {-4.0f, kHeight, -1.5f}, {4.0f, kHeight + kThickness, 1.5f}, "roof");
    // The left room's light: a glowing panel just off its back wall.
    const int32_t glow = addMaterial(scene, "warm panel", glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(4.0f, 2.4f, 1.2f));
    slab(glow, {-3.5f, 0.5f, -1.5f}, {-0.5f, 2.0f, -1.45f}, "warm panel");
    scene.environment.ambientColor = glm::vec3(0.0f);   // every bit of light is the panel's
    scene.environment.exposure = 1.5f;

    // In the right room's front corner, looking back at the wall and the doorway.
    scene.camera.position = glm::vec3(3.6f, 1.7f, 1.3f);
    scene.camera.target = glm::vec3(0.0f, 0.8f, -0.4f);
    scene.camera.fovYRadians = glm::radians(60.0f);

    IrradianceVolume volume;
    volume.name = "gi-rooms";
    volume.bounds = Box{{-4.0f, 0.0f, -1.5f}, {4.0f, kHeight, 1.5f}};
    volume.probeCounts = glm::uvec3(8, 2, 3);   // x at +-0.5 beside the wall, 1 m apart
    volume.farPlane = 20.0f;
    scene.irradianceVolume = volume;
    return scene;
}

}  // namespace janus::renderer
