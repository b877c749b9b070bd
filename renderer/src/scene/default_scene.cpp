// The built-in scene (no files): a closed Cornell-like room with a row of dielectric spheres of
// increasing roughness, a row of metallic ones, a tall box and a ceiling lamp panel. Sized so a
// 256x256 image shows every object, and so later features (many lights, reflection probes,
// probe GI) have coloured walls to bounce and shiny spheres to reflect.
#include <cmath>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "scene_internal.h"

namespace janus::renderer {
namespace detail {

// A unit quad in the XY plane facing +Z (counter-clockwise seen from +Z), 2x2 units.
Mesh makeQuad(int32_t material) {
    Mesh mesh;
    const glm::vec3 corners[4] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    const glm::vec2 uvs[4] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    for (int i = 0; i < 4; ++i) mesh.vertices.push_back(Vertex{corners[i], {0, 0, 1}, uvs[i], {1, 0, 0, 1}});
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.material = material;
    return mesh;
}

// A unit cube (-1..1) with per-face normals and tangents.
Mesh makeBox(int32_t material) {
    Mesh mesh;
    const glm::vec3 normals[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const glm::vec3& n : normals) {
        // Two axes spanning the face, ordered so (u x v) == n keeps the winding counter-clockwise.
        const glm::vec3 u = std::abs(n.y) > 0.5f ? glm::vec3(1, 0, 0) : glm::normalize(glm::cross(glm::vec3(0, 1, 0), n));
        const glm::vec3 v = glm::cross(n, u);
        const uint32_t base = uint32_t(mesh.vertices.size());
        const glm::vec2 corners[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
        for (const glm::vec2& c : corners)
            mesh.vertices.push_back(Vertex{n + u * c.x + v * c.y, n, (c * glm::vec2(1, -1) + 1.0f) * 0.5f, glm::vec4(u, 1)});
        for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) mesh.indices.push_back(base + i);
    }
    mesh.material = material;
    return mesh;
}

// A UV sphere of radius 1, counter-clockwise from outside.
Mesh makeSphere(int32_t material, uint32_t slices, uint32_t stacks) {
    Mesh mesh;
    for (uint32_t stack = 0; stack <= stacks; ++stack) {
        const float theta = glm::pi<float>() * float(stack) / float(stacks);   // 0 at the north pole
        for (uint32_t slice = 0; slice <= slices; ++slice) {
            const float phi = glm::two_pi<float>() * float(slice) / float(slices);
            const glm::vec3 n(std::sin(theta) * std::sin(phi), std::cos(theta), std::sin(theta) * std::cos(phi));
            const glm::vec3 tangent(std::cos(phi), 0.0f, -std::sin(phi));
            mesh.vertices.push_back(Vertex{n, n, {float(slice) / float(slices), float(stack) / float(stacks)}, glm::vec4(tangent, 1)});
        }
    }
    const uint32_t row = slices + 1;
    for (uint32_t stack = 0; stack < stacks; ++stack) {
        for (uint32_t slice = 0; slice < slices; ++slice) {
            const uint32_t a = stack * row + slice, b = a + row;
            if (stack != 0) mesh.indices.insert(mesh.indices.end(), {a, b, a + 1});
            if (stack != stacks - 1) mesh.indices.insert(mesh.indices.end(), {a + 1, b, b + 1});
        }
    }
    mesh.material = material;
    return mesh;
}

int32_t addMaterial(Scene& scene, std::string name, glm::vec3 color, float metallic, float roughness, glm::vec3 emissive) {
    Material material;
    material.name = std::move(name);
    material.baseColorFactor = glm::vec4(color, 1.0f);
    material.metallicFactor = metallic;
    material.roughnessFactor = roughness;
    material.emissiveFactor = emissive;
    scene.materials.push_back(std::move(material));
    return int32_t(scene.materials.size() - 1);
}

uint32_t addMesh(Scene& scene, Mesh mesh) {
    scene.meshes.push_back(std::move(mesh));
    return uint32_t(scene.meshes.size() - 1);
}

}  // namespace detail

using namespace detail;

Scene defaultScene() {
    Scene scene;
    scene.name = "default";

    // Room interior: x in [-2, 2], y in [0, 3], z in [-2, 2]. Each wall is the +Z-facing unit
    // quad rotated to face inwards, so back-face culling keeps only the insides.
    constexpr float halfWidth = 2.0f, height = 3.0f, halfDepth = 2.0f;
    const int32_t white = addMaterial(scene, "white wall", glm::vec3(0.73f), 0.0f, 0.9f);
    const int32_t red = addMaterial(scene, "red wall", glm::vec3(0.63f, 0.065f, 0.05f), 0.0f, 0.9f);
    const int32_t green = addMaterial(scene, "green wall", glm::vec3(0.14f, 0.45f, 0.091f), 0.0f, 0.9f);
    const uint32_t whiteQuad = addMesh(scene, makeQuad(white));
    const uint32_t redQuad = addMesh(scene, makeQuad(red));
    const uint32_t greenQuad = addMesh(scene, makeQuad(green));
    const glm::mat4 I(1.0f);
    auto wall = [&](uint32_t mesh, glm::vec3 center, float angle, glm::vec3 axis, glm::vec2 halfSize) {
        glm::mat4 world = glm::translate(I, center) * glm::rotate(I, angle, axis) * glm::scale(I, glm::vec3(halfSize, 1.0f));
        scene.instances.push_back(Instance{mesh, world});
    };
    const float half = glm::half_pi<float>();
    wall(whiteQuad, {0, 0, 0}, -half, {1, 0, 0}, {halfWidth, halfDepth});                     // floor, faces +Y
    wall(whiteQuad, {0, height, 0}, half, {1, 0, 0}, {halfWidth, halfDepth});                 // ceiling, faces -Y
    wall(whiteQuad, {0, height / 2, -halfDepth}, 0.0f, {0, 1, 0}, {halfWidth, height / 2});   // back, faces +Z
    wall(whiteQuad, {0, height / 2, halfDepth}, glm::pi<float>(), {0, 1, 0}, {halfWidth, height / 2});  // front, behind the camera
    wall(redQuad, {-halfWidth, height / 2, 0}, half, {0, 1, 0}, {halfDepth, height / 2});     // left, faces +X
    wall(greenQuad, {halfWidth, height / 2, 0}, -half, {0, 1, 0}, {halfDepth, height / 2});   // right, faces -X

    // A lamp panel just under the ceiling: emissive only, so it reads as the light source.
    const int32_t lamp = addMaterial(scene, "lamp", glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(6.0f, 5.6f, 5.0f));
    wall(addMesh(scene, makeQuad(lamp)), {0, height - 0.01f, -0.5f}, half, {1, 0, 0}, {0.6f, 0.4f});

    // Two rows of five spheres: dielectric (front) and gold metal (back), roughness rising left
    // to right, so specular highlights go from sharp to broad.
    const uint32_t sphereCount = 5;
    constexpr float radius = 0.24f;
    for (uint32_t i = 0; i < sphereCount; ++i) {
        const float roughness = 0.05f + 0.95f * float(i) / float(sphereCount - 1);
        const float x = -1.2f + 0.6f * float(i);
        const int32_t plastic = addMaterial(scene, "plastic " + std::to_string(i), glm::vec3(0.1f, 0.25f, 0.8f), 0.0f, roughness);
        const int32_t gold = addMaterial(scene, "gold " + std::to_string(i), glm::vec3(1.0f, 0.78f, 0.34f), 1.0f, roughness);
        const glm::mat4 scale = glm::scale(I, glm::vec3(radius));
        scene.instances.push_back(Instance{addMesh(scene, makeSphere(plastic)), glm::translate(I, {x, radius, -0.4f}) * scale});
        scene.instances.push_back(Instance{addMesh(scene, makeSphere(gold)), glm::translate(I, {x, radius, -1.1f}) * scale});
    }

    // A tall box in the back-right corner, turned so two faces catch different light.
    const int32_t boxMaterial = addMaterial(scene, "box", glm::vec3(0.73f), 0.0f, 0.6f);
    scene.instances.push_back(Instance{addMesh(scene, makeBox(boxMaterial)),
                                       glm::translate(I, {1.1f, 0.7f, -1.45f}) * glm::rotate(I, 0.35f, {0, 1, 0}) *
                                           glm::scale(I, {0.35f, 0.7f, 0.3f})});

    // A warm key light from the upper right (it lights the floor, the back wall and the red
    // wall) and a dim cool fill from the left so the green wall is not black.
    Light key;
    key.type = LightType::Directional;
    key.color = glm::vec3(1.0f, 0.95f, 0.85f);
    key.intensity = 2.0f;
    key.direction = glm::normalize(glm::vec3(-0.55f, -1.0f, -0.45f));
    scene.lights.push_back(key);
    Light fill = key;
    fill.color = glm::vec3(0.75f, 0.85f, 1.0f);
    fill.intensity = 0.6f;
    fill.direction = glm::normalize(glm::vec3(0.8f, -0.5f, -0.3f));
    scene.lights.push_back(fill);

    scene.environment.ambientColor = glm::vec3(0.05f);
    scene.environment.exposure = 1.0f;

    scene.camera.position = glm::vec3(0.0f, 1.7f, 1.9f);
    scene.camera.target = glm::vec3(0.0f, 0.8f, -1.2f);
    scene.camera.fovYRadians = glm::radians(72.0f);
    scene.camera.nearPlane = 0.02f;
    scene.camera.farPlane = 20.0f;

    // Where future probe features place their volumes: the room's centre.
    scene.markers.push_back(Marker{"IrradianceVolume", glm::translate(I, {0, height / 2, 0}) * glm::scale(I, {halfWidth, height / 2, halfDepth})});
    scene.markers.push_back(Marker{"ReflectionCubemap", glm::translate(I, {0, 1.0f, 0})});
    return scene;
}

}  // namespace janus::renderer
