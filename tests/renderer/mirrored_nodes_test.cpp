// Mirrored nodes (a world matrix with a negative determinant): glTF says their front faces are
// clockwise. A floor and a single-sided occluder quad lit from above: the occluder mirrored
// (scale -1 along x, which leaves a centred quad where it was) must render exactly as the plain
// one, both in the forward pass and as a shadow caster. Before the fix, mirrored meshes drew
// inside-out: the occluder and its shadow vanished. On every configuration.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "janus/renderer/renderer.h"
#include "renderer/renderer_test_support.h"

namespace janus::renderer {
namespace {

using test_support::Config;

// A unit quad in the xz plane, facing +y (counter-clockwise seen from above).
Mesh quadFacingUp(int32_t material) {
    Mesh mesh;
    const glm::vec4 tangent(0.0f);
    mesh.vertices = {Vertex{{-0.5f, 0.0f, 0.5f}, {0, 1, 0}, {0, 1}, tangent}, Vertex{{0.5f, 0.0f, 0.5f}, {0, 1, 0}, {1, 1}, tangent},
                     Vertex{{0.5f, 0.0f, -0.5f}, {0, 1, 0}, {1, 0}, tangent}, Vertex{{-0.5f, 0.0f, -0.5f}, {0, 1, 0}, {0, 0}, tangent}};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.material = material;
    return mesh;
}

Scene floorAndOccluder(bool mirrored) {
    Scene scene;
    scene.name = mirrored ? "mirrored occluder" : "occluder";
    Material white;
    white.metallicFactor = 0.0f;
    white.roughnessFactor = 0.8f;
    Material red = white;
    red.baseColorFactor = {0.9f, 0.1f, 0.1f, 1.0f};
    scene.materials = {white, red};
    scene.meshes = {quadFacingUp(0), quadFacingUp(1)};
    scene.instances.push_back(Instance{0, glm::scale(glm::mat4(1.0f), glm::vec3(6.0f, 1.0f, 6.0f))});
    glm::mat4 occluder = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.6f, 0.0f));
    if (mirrored) occluder = occluder * glm::scale(glm::mat4(1.0f), glm::vec3(-1.0f, 1.0f, 1.0f));
    scene.instances.push_back(Instance{1, occluder});
    Light sun;
    sun.direction = glm::normalize(glm::vec3(0.25f, -1.0f, 0.1f));
    sun.intensity = 2.0f;
    scene.lights = {sun};
    scene.camera.position = {0.0f, 3.0f, 2.5f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    return scene;
}

class MirroredNodeTest : public testing::TestWithParam<Config> {};

TEST_P(MirroredNodeTest, AMirroredMeshAndItsShadowRenderAsTheUnmirroredOne) {
    RenderSettings settings;
    settings.width = settings.height = test_support::kSize;
    const Scene plain = floorAndOccluder(false);
    const Scene mirrored = floorAndOccluder(true);
    ASSERT_LT(glm::determinant(glm::mat3(mirrored.instances[1].world)), 0.0f);
    const test_support::FrameOutput expected = test_support::renderOneFrame(GetParam(), plain, settings);
    const test_support::FrameOutput actual = test_support::renderOneFrame(GetParam(), mirrored, settings);

    // The scene must show what is being compared: the red occluder (its shadow is covered by
    // the comparison, which fails without it: see the commit that added this test).
    const ImageRGBA8& image = expected.display;
    size_t red = 0;
    for (uint32_t i = 0; i < image.width * image.height; ++i)
        if (image.pixels[i * 4] > 2 * image.pixels[i * 4 + 1] + 20) ++red;
    EXPECT_GT(red, 100u) << "the occluder is not in view";

    // Mirroring a centred quad moves no surface: the same pixels. Its triangles are split along
    // the other diagonal, so an edge pixel may round differently by one step.
    const ImageDifference diff = compareImages(expected.display, actual.display, 1);
    EXPECT_EQ(diff.differingPixels, 0u) << GetParam().name() << ": max difference " << diff.maxChannelDifference << " in "
                                        << diff.differingPixels << " pixels";
    EXPECT_EQ(expected.report.passes.front().name, "shadow-map");
}

INSTANTIATE_TEST_SUITE_P(Configs, MirroredNodeTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
