// What each mesh draw binds reaches that draw, on every configuration: its own uniforms (one set
// moved by a dynamic offset per draw), its material's textures (a set per material, bound when the
// material changes) and, in the shadow map, its own caster matrix (one set, an offset per caster).
// A draw that kept the previous draw's material set or the first slot's matrix would show here.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include <array>
#include <string>

#include "janus/renderer/renderer.h"
#include "renderer/renderer_test_support.h"
#include "scene/scene_internal.h"

namespace janus::renderer {
namespace {

using test_support::Config;

class PerDrawBindingsTest : public testing::TestWithParam<Config> {};

// The linear radiance of the HDR pixel at (x, y), row 0 on top.
glm::vec3 radianceAt(const ImageRGBAF& image, uint32_t x, uint32_t y) {
    const float* p = &image.pixels[(size_t(y) * image.width + x) * 4];
    return {p[0], p[1], p[2]};
}

TextureImage solidTexture(const std::array<uint8_t, 4>& rgba, const std::string& name) {
    TextureImage texture;
    texture.width = texture.height = 1;
    texture.rgba.assign(rgba.begin(), rgba.end());
    texture.srgb = true;
    texture.name = name;
    return texture;
}

// Four unlit quads in a row, drawn in the order red, green, red, blue (materials 0, 1, 0, 2, each
// a white factor times a 1x1 texture): every quad must show its own material's texture, so the
// material set changes between draws of one pipeline and back.
TEST_P(PerDrawBindingsTest, EachDrawShowsItsOwnMaterialsTexture) {
    Scene scene;
    const std::array<std::array<uint8_t, 4>, 3> colours{{{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}}};
    for (size_t m = 0; m < colours.size(); ++m) {
        scene.textures.push_back(solidTexture(colours[m], fmt::format("solid {}", m)));
        Material material;
        material.unlit = true;
        material.baseColorTexture = int32_t(m);
        scene.materials.push_back(material);
        scene.meshes.push_back(detail::makeQuad(int32_t(m)));
    }
    const std::array<uint32_t, 4> quadMaterial{0, 1, 0, 2};
    for (size_t i = 0; i < quadMaterial.size(); ++i)
        scene.instances.push_back(Instance{quadMaterial[i], test_support::quadFacing({-3.0f + 2.0f * float(i), 0.0f, 0.0f}, {0, 0, 1}, 1.6f)});
    scene.camera.projection = CameraProjection::Orthographic;
    scene.camera.orthographicHalfHeight = 1.0f;   // 128 x 32 pixels: 8 x 2 metres
    scene.camera.position = {0.0f, 0.0f, 5.0f};
    RenderSettings settings;
    settings.width = 128;
    settings.height = 32;
    const test_support::FrameOutput frame = test_support::renderOneFrame(GetParam(), scene, settings);
    for (size_t i = 0; i < quadMaterial.size(); ++i) {
        const glm::vec3 radiance = radianceAt(frame.hdr, uint32_t(16 + 32 * i), 16);
        const size_t channel = quadMaterial[i];
        SCOPED_TRACE(fmt::format("{}: quad {} (material {}) shows ({}, {}, {})", GetParam().name(), i, channel, radiance.r,
                                 radiance.g, radiance.b));
        // Unlit: the texture's colour itself (one channel 1, the others 0), up to the sampler's rounding.
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(radiance[c], size_t(c) == channel ? 1.0f : 0.0f, 0.01f);
    }
}

// A floor and two boxes floating above it at different places, lit by a sun at 45 degrees: each
// box's shadow lies on the floor where its own matrix puts it, and the floor between them is lit.
// Seen from straight above (orthographic), so the shadows, offset 2 m from their boxes, are in view.
TEST_P(PerDrawBindingsTest, EachShadowCasterCastsFromItsOwnPlace) {
    Scene scene;
    Material floorMaterial;
    floorMaterial.metallicFactor = 0.0f;
    floorMaterial.roughnessFactor = 1.0f;
    scene.materials = {floorMaterial};
    scene.meshes = {detail::makeQuad(0), detail::makeBox(0)};
    scene.instances.push_back(Instance{0, test_support::quadFacing({0.0f, 0.0f, 0.0f}, {0, 1, 0}, 6.0f)});
    for (const float z : {-1.5f, 1.5f})
        scene.instances.push_back(
            Instance{1, glm::scale(glm::translate(glm::mat4(1.0f), {-1.0f, 2.0f, z}), glm::vec3(0.4f))});
    Light sun;
    sun.direction = glm::normalize(glm::vec3(1.0f, -1.0f, 0.0f));   // shadows 2 m towards +x of the boxes
    sun.intensity = 3.0f;
    scene.lights = {sun};
    scene.camera.projection = CameraProjection::Orthographic;
    scene.camera.orthographicHalfHeight = 3.0f;   // 64 x 64 pixels: x and z in -3..3
    scene.camera.position = {0.0f, 6.0f, 0.0f};
    scene.camera.up = {0.0f, 0.0f, -1.0f};        // row 0 at z = -3
    RenderSettings settings;
    settings.width = settings.height = 64;
    const test_support::FrameOutput frame = test_support::renderOneFrame(GetParam(), scene, settings);
    ASSERT_EQ(frame.report.passes.front().name, "shadow-map");
    auto floorAt = [&](float x, float z) {
        return radianceAt(frame.hdr, uint32_t((x + 3.0f) / 6.0f * 64.0f), uint32_t((z + 3.0f) / 6.0f * 64.0f)).g;
    };
    const float lit = floorAt(1.0f, 0.0f);
    SCOPED_TRACE(fmt::format("{}: lit floor {}, under the shadows {} and {}, far side {}", GetParam().name(), lit,
                             floorAt(1.0f, -1.5f), floorAt(1.0f, 1.5f), floorAt(-2.5f, 0.0f)));
    EXPECT_GT(lit, 0.3f);
    EXPECT_NEAR(floorAt(-2.5f, 0.0f), lit, 0.02f * lit);   // no shadow there either
    // In a shadow only the ambient light is left (0.03 by default, times the albedo's 1 / pi share).
    EXPECT_LT(floorAt(1.0f, -1.5f), 0.1f * lit);
    EXPECT_LT(floorAt(1.0f, 1.5f), 0.1f * lit);
}

INSTANTIATE_TEST_SUITE_P(Configs, PerDrawBindingsTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
