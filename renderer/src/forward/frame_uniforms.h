// The frame uniform block of the scene passes (internal to the renderer): the std140 mirror of
// forward_common.glsl's FrameUniforms (set JANUS_SET_VIEW, binding JANUS_BINDING_FRAME_UNIFORMS),
// shared by forward shading, the GI bake and the GI relight.
#pragma once

#include <span>

#include <glm/glm.hpp>

#include "forward/lighting_settings.h"
#include "janus/renderer/scene.h"

namespace janus::renderer {

// std140 mirrors of forward_common.glsl's frame block (set JANUS_SET_VIEW).
struct DirectionalLightData {
    glm::vec4 direction;        // w unused
    glm::vec4 colorIntensity;   // w renderingLayers as uint bits
};
struct FrameUniforms {
    glm::mat4 viewProjection;
    glm::mat4 worldToShadow;
    glm::vec4 cameraPosition;   // w 1: the eye; w 0: the unit direction towards an orthographic camera
    glm::vec4 ambientColor;
    glm::vec4 shadowParams;
    glm::ivec4 lightCounts;
    glm::ivec4 tileGrid;
    DirectionalLightData directionalLights[kMaxDirectionalLights];
    glm::vec4 skyParams;        // ImageBasedLighting::shadingParams()
};
static_assert(sizeof(FrameUniforms) == 208 + 32 * kMaxDirectionalLights + 16, "FrameUniforms must match std140");

// The view-independent part of the frame uniforms: the ambient colour and the directional lights
// (the main one first: the shaders shadow directional light 0). Passes that light without a
// view (the GI relight) start from this too.
FrameUniforms sceneFrameUniforms(const Scene& scene);
// The same for a light list and ambient colour (Renderer::setLights).
FrameUniforms sceneFrameUniforms(std::span<const Light> lights, const glm::vec3& ambientColor);

}  // namespace janus::renderer
