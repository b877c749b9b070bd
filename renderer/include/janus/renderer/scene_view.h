// janus::renderer scene views: one camera the renderer draws the scene from. The main camera is
// one view; a cube capture (reflection probe, G-buffer cube) is six. Frame uniforms, the passes a
// view wants and its targets' formats are per view (docs/ARCHITECTURE.md, "Scene views").
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include <glm/glm.hpp>

#include "janus/renderer/scene.h"
#include "janus/renderer/settings.h"
#include "janus/rhi/format.h"

namespace janus::renderer {

// The optional passes a view asks for. A pass a view does not want is not run for it (and when
// no view wants it, its resources are not created).
struct ViewPasses {
    bool shadows = true;           // the main directional light's shadow map
    uint32_t shadowMapSize = 0;    // its size for this view; 0 = the renderer's (lighting settings)
    bool lightCulling = true;      // tiled local-light culling when the lighting settings choose it; else every light is looped
    bool tonemap = true;           // HDR -> display image (views that capture radiance leave it out)
    bool reflectionProbes = true;  // glossy reflections from the scene's probes (captures leave them out: no feedback)
};

// Whether a projection of the renderer's kind (symmetric perspective or orthographic, Vulkan clip
// conventions) is orthographic: its clip w is 1 rather than -z, so P23 is 0. Light culling and
// SceneView::orthographic() read it here; light_culling_common.glsl has the GLSL twin.
inline bool isOrthographicProjection(const glm::mat4& projection) { return projection[2][3] == 0.0f; }

struct SceneView {
    std::string name = "main";
    // World -> view and view -> clip with Vulkan's clip conventions (depth [0, 1], NDC y = -1 is
    // row 0 of the target). The projection is a symmetric perspective (w = -z) or orthographic
    // (w = 1) one; the renderer tells them apart by P23 (orthographic()) and assumes nothing more.
    glm::mat4 view{1.0f};
    glm::mat4 projection{1.0f};
    glm::vec3 position{0.0f};      // camera position in world space (specular, probe priorities)
    float nearPlane = 0.05f, farPlane = 100.0f;
    uint32_t width = 0, height = 0;
    rhi::Format colorFormat = rhi::Format::RGBA16_FLOAT;
    rhi::Format depthFormat = rhi::Format::D32_FLOAT;
    // Samples per pixel of the view's colour and depth targets (the pipelines drawing into them
    // say the same); > 1 only for the main view with RenderSettings::msaaSamples.
    uint32_t sampleCount = 1;
    // With sampleCount > 1: alpha-masked materials cover samples by their alpha around the cut-off
    // (RenderSettings::alphaToCoverage) rather than cutting whole pixels.
    bool alphaToCoverage = false;
    // True when the projection flips handedness (cube faces do): glTF's counter-clockwise front
    // faces then appear clockwise in the image, and the view's pipelines say so.
    bool mirrored = false;
    uint32_t renderingLayers = ~0u;   // only meshes whose rendering layers intersect these are drawn
    ViewPasses passes;
    DebugView debugView = DebugView::None;

    glm::mat4 viewProjection() const { return projection * view; }
    bool orthographic() const { return isOrthographicProjection(projection); }
    // The unit world direction opposite to the view direction (view space +z).
    glm::vec3 backward() const { return glm::normalize(glm::vec3(view[0][2], view[1][2], view[2][2])); }
    // The camera as shaders take it: (position, 1), or for an orthographic view, whose rays are
    // parallel, (backward(), 0), so that toCamera = xyz - worldPosition * w serves both.
    glm::vec4 homogeneousCamera() const { return orthographic() ? glm::vec4(backward(), 0.0f) : glm::vec4(position, 1.0f); }
};

// The scene camera as a view of width x height (the same matrices light culling uses).
SceneView makeCameraView(const Camera& camera, uint32_t width, uint32_t height, std::string name = "main");

// Cube faces in the RHI's order (+X, -X, +Y, -Y, +Z, -Z; docs/ARCHITECTURE.md, "Cube maps"):
// the direction a face looks along and the world direction that its row 0 shows.
glm::vec3 cubeFaceDirection(uint32_t face);
glm::vec3 cubeFaceUp(uint32_t face);
const char* cubeFaceName(uint32_t face);   // "+X", "-X", ...

// The six views that render a cube map at `position` face by face: 90 degree square frusta
// whose images are the faces as the cube map convention lays them out. That layout is the
// mirror image of an ordinary camera looking along the face's axis with cubeFaceUp() as up
// (column 0 shows what such a camera shows in its last column), so these views are `mirrored`.
std::array<SceneView, 6> makeCubeFaceViews(const glm::vec3& position, uint32_t size, float nearPlane, float farPlane,
                                           const std::string& namePrefix = "cube");

}  // namespace janus::renderer
