// The built-in reflection-probe scene (`janus render probes`): an open alcove on a glossy
// ground under a procedural sky, with two overlapping probes. What each part shows:
//   - the alcove's left half (red wall) and right half (green wall) each have a probe whose
//     box-projected reflections put the walls where they are on the floor and the spheres;
//   - the probes' influence boxes overlap by a metre in the middle, where they blend;
//   - the ground in front of the alcove is outside both boxes: it reflects the sky;
//   - the alcove has no roof, so the probes' captures see the sky behind the walls.
#include <cmath>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "scene_internal.h"

namespace janus::renderer {
namespace {

// A clear-day sky: a bright horizon fading to blue at the zenith, a darker ground below the
// horizon and a small sun (bright, not extreme: the sky's intensity scales it) along -sunTravel.
ImageRGBAF proceduralSky(uint32_t width, uint32_t height, glm::vec3 sunTravel) {
    ImageRGBAF sky{width, height, std::vector<float>(size_t(width) * height * 4)};
    const glm::vec3 toSun = -glm::normalize(sunTravel);
    for (uint32_t y = 0; y < height; ++y) {
        // Row 0 is +Y (up).
        const float theta = glm::pi<float>() * (float(y) + 0.5f) / float(height);
        for (uint32_t x = 0; x < width; ++x) {
            // u = 0.5 + atan(d.x, -d.z) / 2 pi (ggx_common.glsl's equirectUv).
            const float phi = glm::two_pi<float>() * (float(x) + 0.5f) / float(width) - glm::pi<float>();
            const glm::vec3 d(std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi));
            glm::vec3 radiance;
            if (d.y >= 0.0f) {
                const float t = std::pow(1.0f - d.y, 4.0f);
                radiance = glm::mix(glm::vec3(0.25f, 0.45f, 1.0f), glm::vec3(1.1f, 1.05f, 0.95f), t);
            } else {
                radiance = glm::mix(glm::vec3(0.35f, 0.3f, 0.25f), glm::vec3(0.15f, 0.13f, 0.11f), std::min(1.0f, -d.y * 3.0f));
            }
            if (glm::dot(d, toSun) > std::cos(glm::radians(2.5f))) radiance = glm::vec3(400.0f, 380.0f, 340.0f);
            float* p = sky.pixels.data() + (size_t(y) * width + x) * 4;
            p[0] = radiance.r, p[1] = radiance.g, p[2] = radiance.b, p[3] = 1.0f;
        }
    }
    return sky;
}

}  // namespace

using namespace detail;

Scene probesScene() {
    Scene scene;
    scene.name = "probes";
    const glm::mat4 I(1.0f);
    const float half = glm::half_pi<float>();
    auto quad = [&](int32_t material, glm::vec3 center, float angle, glm::vec3 axis, glm::vec2 halfSize) {
        const glm::mat4 world = glm::translate(I, center) * glm::rotate(I, angle, axis) * glm::scale(I, glm::vec3(halfSize, 1.0f));
        scene.instances.push_back(Instance{addMesh(scene, makeQuad(material)), world});
    };

    // Ground: glossy, wide enough to reach the horizon of a 256 px view.
    const int32_t ground = addMaterial(scene, "glossy ground", glm::vec3(0.2f), 0.0f, 0.12f);
    quad(ground, {0, 0, 0}, -half, {1, 0, 0}, {12.0f, 12.0f});
    // The alcove: x in [-3, 3], z in [-2, 0.5], walls 2.5 high, open at the front and the top.
    constexpr float height = 2.5f;
    const int32_t white = addMaterial(scene, "white wall", glm::vec3(0.75f), 0.0f, 0.8f);
    const int32_t red = addMaterial(scene, "red wall", glm::vec3(0.7f, 0.08f, 0.06f), 0.0f, 0.8f);
    const int32_t green = addMaterial(scene, "green wall", glm::vec3(0.12f, 0.5f, 0.1f), 0.0f, 0.8f);
    quad(white, {0, height / 2, -2.0f}, 0.0f, {0, 1, 0}, {3.0f, height / 2});        // back, faces +Z
    quad(red, {-3.0f, height / 2, -0.75f}, half, {0, 1, 0}, {1.25f, height / 2});    // left, faces +X
    quad(green, {3.0f, height / 2, -0.75f}, -half, {0, 1, 0}, {1.25f, height / 2});  // right, faces -X

    // Spheres: a chrome mirror and a rough gold in each half, a glossy blue one in the middle.
    const glm::mat4 small = glm::scale(I, glm::vec3(0.45f));
    const int32_t chrome = addMaterial(scene, "chrome", glm::vec3(0.95f), 1.0f, 0.05f);
    const int32_t gold = addMaterial(scene, "rough gold", glm::vec3(1.0f, 0.78f, 0.34f), 1.0f, 0.45f);
    const int32_t blue = addMaterial(scene, "glossy blue", glm::vec3(0.1f, 0.2f, 0.8f), 0.0f, 0.15f);
    const uint32_t chromeSphere = addMesh(scene, makeSphere(chrome)), goldSphere = addMesh(scene, makeSphere(gold));
    scene.instances.push_back(Instance{chromeSphere, glm::translate(I, {-1.8f, 0.45f, -1.0f}) * small});
    scene.instances.push_back(Instance{goldSphere, glm::translate(I, {-0.9f, 0.45f, -0.2f}) * small});
    scene.instances.push_back(Instance{addMesh(scene, makeSphere(blue)), glm::translate(I, {0.0f, 0.45f, -1.2f}) * small});
    scene.instances.push_back(Instance{goldSphere, glm::translate(I, {0.9f, 0.45f, -0.2f}) * small});
    scene.instances.push_back(Instance{chromeSphere, glm::translate(I, {1.8f, 0.45f, -1.0f}) * small});

    Light sun;
    sun.type = LightType::Directional;
    sun.color = glm::vec3(1.0f, 0.95f, 0.85f);
    sun.intensity = 3.0f;
    sun.direction = glm::normalize(glm::vec3(0.45f, -1.0f, -0.6f));
    scene.lights.push_back(sun);

    scene.environment.image = std::make_shared<ImageRGBAF>(proceduralSky(256, 128, sun.direction));
    scene.environment.intensity = 0.6f;
    scene.environment.exposure = 0.7f;

    // Two probes, one per half, overlapping over x in [-0.5, 0.5]; each projects onto its half of
    // the alcove (floor to wall top). The left one is refreshed every frame, sliced over three
    // frames; the right one once, all at once.
    ReflectionProbe left;
    left.name = "left";
    left.position = glm::vec3(-1.5f, 1.0f, -0.75f);
    left.influence = Box{{-3.05f, -0.05f, -2.05f}, {0.5f, height, 0.55f}};
    left.blendDistance = 0.5f;
    left.parallax = Box{{-3.0f, 0.0f, -2.0f}, {3.0f, height, 0.5f}};
    left.resolution = 64;
    left.nearPlane = 0.05f;
    left.farPlane = 60.0f;
    left.update = ProbeUpdate::EveryFrame;
    left.timeSlicing = ProbeTimeSlicing::AllFacesThenMips;
    ReflectionProbe right = left;
    right.name = "right";
    right.position = glm::vec3(1.5f, 1.0f, -0.75f);
    right.influence = Box{{-0.5f, -0.05f, -2.05f}, {3.05f, height, 0.55f}};
    right.resolution = 128;
    right.update = ProbeUpdate::Once;
    right.timeSlicing = ProbeTimeSlicing::None;
    scene.reflectionProbes = {left, right};

    scene.camera.position = glm::vec3(0.0f, 1.6f, 4.2f);
    scene.camera.target = glm::vec3(0.0f, 0.6f, -1.0f);
    scene.camera.fovYRadians = glm::radians(60.0f);
    scene.camera.nearPlane = 0.05f;
    scene.camera.farPlane = 60.0f;
    return scene;
}

}  // namespace janus::renderer
