#include "janus/renderer/scene_view.h"

#include <cmath>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "janus/renderer/light_grid.h"

namespace janus::renderer {

SceneView makeCameraView(const Camera& camera, uint32_t width, uint32_t height, std::string name) {
    SceneView view;
    view.name = std::move(name);
    view.view = makeView(camera);
    view.projection = makeProjection(camera, width, height);
    view.position = camera.position;
    view.nearPlane = camera.nearPlane;
    view.farPlane = camera.farPlane;
    view.width = width;
    view.height = height;
    return view;
}

// From the cube map face selection table of the Vulkan and GL specs: face +X has s = -z and
// t = -y, so its column 0 shows +Z and its row 0 shows +Y, and so on.
glm::vec3 cubeFaceDirection(uint32_t face) {
    static const glm::vec3 directions[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    if (face >= 6) throw RendererError(fmt::format("cube face {} does not exist (faces are 0..5)", face));
    return directions[face];
}

glm::vec3 cubeFaceUp(uint32_t face) {
    static const glm::vec3 ups[6] = {{0, 1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};
    if (face >= 6) throw RendererError(fmt::format("cube face {} does not exist (faces are 0..5)", face));
    return ups[face];
}

const char* cubeFaceName(uint32_t face) {
    static const char* names[6] = {"+X", "-X", "+Y", "-Y", "+Z", "-Z"};
    return face < 6 ? names[face] : "?";
}

std::array<SceneView, 6> makeCubeFaceViews(const glm::vec3& position, uint32_t size, float nearPlane, float farPlane,
                                           const std::string& namePrefix) {
    if (size == 0) throw RendererError("cube views: the face size must be at least 1");
    if (!(nearPlane > 0.0f) || !(farPlane > nearPlane) || !std::isfinite(farPlane))
        throw RendererError(fmt::format("cube views: near {} and far {} must be finite with 0 < near < far", nearPlane, farPlane));
    if (!std::isfinite(position.x) || !std::isfinite(position.y) || !std::isfinite(position.z))
        throw RendererError(fmt::format("cube views: the position ({}, {}, {}) must be finite", position.x, position.y, position.z));
    std::array<SceneView, 6> views;
    for (uint32_t face = 0; face < 6; ++face) {
        Camera camera;
        camera.position = position;
        camera.target = position + cubeFaceDirection(face);
        camera.up = cubeFaceUp(face);
        camera.fovYRadians = glm::radians(90.0f);
        camera.nearPlane = nearPlane;
        camera.farPlane = farPlane;
        SceneView& view = views[face];
        view = makeCameraView(camera, size, size, fmt::format("{} {}", namePrefix, cubeFaceName(face)));
        // An ordinary camera's column 0 shows its left; the face's column 0 shows its right.
        view.projection = glm::scale(glm::mat4(1.0f), glm::vec3(-1.0f, 1.0f, 1.0f)) * view.projection;
        view.mirrored = true;
    }
    return views;
}

}  // namespace janus::renderer
