// glTF's normalTexture.scale and occlusionTexture.strength: read by the loader (strength refused
// outside [0, 1], as the schema bounds it), and applied on every configuration: a black occlusion
// texture at strength s leaves 1 - s of the ambient light, and a tilted normal map at scale 0
// shades like the flat surface. Both were read as 1 before, whatever the file said.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "janus/renderer/renderer.h"
#include "janus/renderer/scene.h"
#include "renderer/gltf_test_file.h"
#include "renderer/renderer_test_support.h"
#include "scene/scene_internal.h"

namespace janus::renderer {
namespace {

using test_support::Config;
using test_support::sceneErrorOf;
using test_support::TinyGltf;

TEST(MaterialScalarsLoading, NormalScaleAndOcclusionStrengthAreRead) {
    TinyGltf file;
    file.addUvsAndNormalMap();
    file.gltf["materials"][0]["normalTexture"]["scale"] = 0.5;
    file.gltf["materials"][0]["occlusionTexture"] = {{"index", 0}, {"strength", 0.25}};
    const Scene scene = loadScene(file.write());
    EXPECT_EQ(scene.materials.at(0).normalScale, 0.5f);
    EXPECT_EQ(scene.materials.at(0).occlusionStrength, 0.25f);
}

TEST(MaterialScalarsLoading, DefaultsAreOne) {
    TinyGltf file;
    file.addUvsAndNormalMap();
    const Scene scene = loadScene(file.write());
    EXPECT_EQ(scene.materials.at(0).normalScale, 1.0f);
    EXPECT_EQ(scene.materials.at(0).occlusionStrength, 1.0f);
}

TEST(MaterialScalarsLoading, OcclusionStrengthOutsideZeroToOneIsRefused) {
    TinyGltf file;
    file.addUvsAndNormalMap();
    file.gltf["materials"][0]["name"] = "stone";
    file.gltf["materials"][0]["occlusionTexture"] = {{"index", 0}, {"strength", 1.5}};
    const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
    EXPECT_NE(message.find("stone"), std::string::npos) << message;
    EXPECT_NE(message.find("occlusionTexture.strength 1.5 outside [0, 1]"), std::string::npos) << message;
}

// A 1x1 data texture (not sRGB) of one RGBA8 value.
TextureImage oneTexel(uint8_t r, uint8_t g, uint8_t b) {
    TextureImage image;
    image.width = image.height = 1;
    image.rgba = {r, g, b, 255};
    return image;
}

// A quad facing the camera; its material's textures: 0 black occlusion, 1 a normal map tilted
// 45 degrees towards +x. One directional light from the upper left, and an ambient colour.
Scene litQuad(Material material) {
    Scene scene;
    scene.textures = {oneTexel(0, 0, 0), oneTexel(218, 128, 218)};   // (0.71, 0, 0.71) * 0.5 + 0.5
    material.baseColorFactor = glm::vec4(0.8f, 0.7f, 0.6f, 1.0f);
    material.metallicFactor = 0.0f;
    material.roughnessFactor = 0.6f;
    scene.materials = {material};
    scene.meshes = {detail::makeQuad(0)};
    for (Vertex& v : scene.meshes[0].vertices) v.tangent = glm::vec4(1, 0, 0, 1);
    scene.instances = {Instance{0, test_support::quadFacing({0, 0, 0}, {0, 0, 1}, 4.0f)}};
    Light sun;
    sun.direction = glm::normalize(glm::vec3(0.6f, -0.3f, -1.0f));
    sun.intensity = 2.0f;
    scene.lights = {sun};
    scene.environment.ambientColor = glm::vec3(0.2f);
    scene.camera.position = {0, 0, 3};
    scene.camera.target = {0, 0, 0};
    return scene;
}

glm::vec3 centre(const ImageRGBAF& hdr) {
    const size_t at = (size_t(hdr.height / 2) * hdr.width + hdr.width / 2) * 4;
    return {hdr.pixels[at], hdr.pixels[at + 1], hdr.pixels[at + 2]};
}

class MaterialScalarsTest : public test_support::ConfigTest {
protected:
    glm::vec3 render(const Scene& scene) {
        RenderSettings settings = settingsOfSize(64, 64);
        settings.lighting.shadows = false;
        return centre(test_support::renderOneFrame(GetParam(), scene, settings).hdr);
    }
};

// The ambient term is the only one occlusion scales: with the light off, radiance at strength s
// is (1 - s) of the unoccluded radiance.
TEST_P(MaterialScalarsTest, OcclusionStrengthScalesTheAmbientLight) {
    Material occluded;
    occluded.occlusionTexture = 0;
    Scene scene = litQuad(occluded);
    scene.lights.clear();
    scene.materials[0].occlusionStrength = 0.0f;
    const glm::vec3 unoccluded = render(scene);
    ASSERT_GT(unoccluded.r, 0.05f);
    for (float strength : {0.25f, 1.0f}) {
        scene.materials[0].occlusionStrength = strength;
        const glm::vec3 result = render(scene);
        for (int c = 0; c < 3; ++c)
            // Two RGBA16F values, each within a half's last place (2^-10 of it; drivers may round
            // towards zero) of the exact one.
            EXPECT_NEAR(result[c], unoccluded[c] * (1.0f - strength), unoccluded[c] * 2e-3f + 1e-6f)
                << "strength " << strength << ", channel " << c;
    }
}

TEST_P(MaterialScalarsTest, NormalScaleZeroShadesLikeTheFlatSurface) {
    const glm::vec3 flat = render(litQuad(Material{}));
    Material mapped;
    mapped.normalTexture = 1;
    const glm::vec3 tilted = render(litQuad(mapped));
    mapped.normalScale = 0.0f;
    const glm::vec3 scaledToZero = render(litQuad(mapped));
    EXPECT_GT(std::abs(tilted.r - flat.r), 0.05f * flat.r) << "the tilted normal map should change the shading";
    // Two RGBA16F values as above; the normal itself differs by fp32 rounding only.
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(scaledToZero[c], flat[c], flat[c] * 2e-3f) << "channel " << c;
}

INSTANTIATE_TEST_SUITE_P(Configs, MaterialScalarsTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
