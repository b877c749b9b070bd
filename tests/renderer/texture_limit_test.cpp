// A scene texture larger than the device's largest 2D texture is uploaded downscaled (with a
// warning) instead of failing the renderer (createTexture threw InvalidDescription before).
// The glTF loader refuses images over 16384 pixels on a side, so such textures come from scenes
// built in code or from devices with a smaller limit; here the texture is one texel wider than
// each backend's limit. On every configuration.
#include <gtest/gtest.h>

#include <cmath>

#include <fmt/format.h>

#include "janus/renderer/renderer.h"
#include "renderer/renderer_test_support.h"
#include "scene/scene_internal.h"

namespace janus::renderer {
namespace {

using test_support::Config;

class TextureLimitTest : public testing::TestWithParam<Config> {};

TEST_P(TextureLimitTest, TextureWiderThanTheDeviceLimitIsDownscaledAndStillShows) {
    const uint32_t limit = test_support::deviceFor(GetParam().backend).capabilities().limits.maxTextureSize2D;
    ASSERT_GT(limit, 0u);

    // A quad that shows only its emissive texture: uniform green, one texel wider than the limit.
    Scene scene;
    TextureImage texture;
    texture.name = "too wide";
    texture.width = limit + 1;
    texture.height = 2;
    texture.srgb = true;
    for (uint32_t i = 0; i < texture.width * texture.height; ++i) texture.rgba.insert(texture.rgba.end(), {0, 255, 0, 255});
    scene.textures = {std::move(texture)};
    Material material;
    material.baseColorFactor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    material.emissiveFactor = glm::vec3(1.0f);
    material.emissiveTexture = 0;
    scene.materials = {material};
    scene.meshes = {detail::makeQuad(0)};
    scene.instances = {Instance{0, glm::mat4(1.0f)}};
    scene.environment.ambientColor = glm::vec3(0.0f);
    scene.camera.position = {0.0f, 0.0f, 2.0f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};

    RenderSettings settings;
    settings.width = settings.height = test_support::kSize;
    testing::internal::CaptureStderr();
    const test_support::FrameOutput frame = test_support::renderOneFrame(GetParam(), scene, settings);
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_NE(err.find(fmt::format("texture 'too wide' is {}x2, larger than the device's largest 2D texture ({}); uploading it "
                                   "downscaled to {}x2",
                                   limit + 1, limit, limit)),
              std::string::npos)
        << err;

    const float* centre = &frame.hdr.pixels[(size_t(test_support::kSize / 2) * test_support::kSize + test_support::kSize / 2) * 4];
    // sRGB 255 green, filtered: within a step of 1.0 in linear light.
    EXPECT_NEAR(centre[0], 0.0f, 1e-3f) << GetParam().name();
    EXPECT_NEAR(centre[1], 1.0f, 0.01f) << GetParam().name();
    EXPECT_NEAR(centre[2], 0.0f, 1e-3f) << GetParam().name();
}

INSTANTIATE_TEST_SUITE_P(Configs, TextureLimitTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
