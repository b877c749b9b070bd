// A double-sided face lit and seen from behind must shade like the same face turned around (lit
// and seen from the front): its shadow lookup is offset along the normal of the side that is
// seen. Before the fix the offset used the unflipped normal, pushed the lookup behind the
// surface, and the face shadowed itself (3844 of 16384 pixels 190 steps darker). On every
// configuration.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "janus/renderer/renderer.h"
#include "renderer/renderer_test_support.h"

namespace janus::renderer {
namespace {

using test_support::Config;

// A double-sided unit quad in the xy plane facing +z (counter-clockwise seen from +z).
Mesh wall() {
    Mesh mesh;
    const glm::vec4 tangent(0.0f);
    mesh.vertices = {Vertex{{-0.5f, 0.0f, 0.0f}, {0, 0, 1}, {0, 1}, tangent}, Vertex{{0.5f, 0.0f, 0.0f}, {0, 0, 1}, {1, 1}, tangent},
                     Vertex{{0.5f, 1.0f, 0.0f}, {0, 0, 1}, {1, 0}, tangent}, Vertex{{-0.5f, 1.0f, 0.0f}, {0, 0, 1}, {0, 0}, tangent}};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.material = 0;
    return mesh;
}

// The camera and the light are on the +z side; `turned` rotates the wall by 180 degrees about y,
// so its back face is the one they see.
Scene wallSeenFrom(bool turned) {
    Scene scene;
    Material material;
    material.metallicFactor = 0.0f;
    material.roughnessFactor = 0.7f;
    material.doubleSided = true;
    scene.materials = {material};
    scene.meshes = {wall()};
    const glm::mat4 world = turned ? glm::rotate(glm::mat4(1.0f), glm::pi<float>(), glm::vec3(0, 1, 0)) : glm::mat4(1.0f);
    scene.instances = {Instance{0, world}};
    Light sun;
    sun.direction = glm::normalize(glm::vec3(0.2f, -0.3f, -1.0f));   // towards -z: onto the +z side
    sun.intensity = 3.0f;
    scene.lights = {sun};
    scene.camera.position = {0.0f, 0.5f, 2.2f};
    scene.camera.target = {0.0f, 0.5f, 0.0f};
    return scene;
}

class DoubleSidedShadowTest : public testing::TestWithParam<Config> {};

TEST_P(DoubleSidedShadowTest, AFaceLitFromBehindDoesNotShadowItself) {
    RenderSettings settings;
    settings.width = settings.height = test_support::kSize;
    const test_support::FrameOutput front = test_support::renderOneFrame(GetParam(), wallSeenFrom(false), settings);
    const test_support::FrameOutput back = test_support::renderOneFrame(GetParam(), wallSeenFrom(true), settings);
    ASSERT_EQ(front.report.passes.front().name, "shadow-map");
    // The turned wall is the mirror image (x -> -x) of the plain one, and the light sees it
    // from the same side: the same pixels up to the diagonal's rounding (1 step) and edge ties.
    const ImageDifference diff = compareImages(front.display, back.display, 1);
    EXPECT_LE(diff.differingPixels, 8u) << GetParam().name() << ": max difference " << diff.maxChannelDifference << " in "
                                        << diff.differingPixels << " pixels";
    // And it is lit: the centre is well above the ambient level.
    const uint8_t* centre = &back.display.pixels[(size_t(test_support::kSize / 2) * test_support::kSize + test_support::kSize / 2) * 4];
    EXPECT_GT(centre[0], 120) << GetParam().name();
}

INSTANTIATE_TEST_SUITE_P(Configs, DoubleSidedShadowTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
