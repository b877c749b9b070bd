// Degenerate geometry must not poison shading with NaN or Inf (issue 11, "Numerics"): a world
// matrix that squashes an axis to zero (no inverse, so no inverse-transpose normal matrix), zero
// normals and zero tangents from file data. Each renders finite and as the sound version of the
// same scene does, on every configuration.
#include <gtest/gtest.h>

#include <algorithm>
#include <tuple>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "janus/renderer/renderer.h"
#include "renderer/renderer_test_support.h"

namespace janus::renderer {
namespace {

using test_support::Config;

// A quad in the xy plane facing +z, seen head-on, lit by a sun from the camera's side.
Scene litQuad(glm::vec3 normal, glm::vec4 tangent, glm::mat4 world, bool normalMapped) {
    Scene scene;
    Material material;
    material.metallicFactor = 0.0f;
    material.roughnessFactor = 0.6f;
    if (normalMapped) {
        scene.textures.push_back(TextureImage{1, 1, {128, 128, 255, 255}, false, {}, "flat normal"});
        material.normalTexture = 0;
    }
    scene.materials = {material};
    Mesh quad;
    quad.vertices = {Vertex{{-0.5f, -0.5f, 0.0f}, normal, {0, 1}, tangent}, Vertex{{0.5f, -0.5f, 0.0f}, normal, {1, 1}, tangent},
                     Vertex{{0.5f, 0.5f, 0.0f}, normal, {1, 0}, tangent}, Vertex{{-0.5f, 0.5f, 0.0f}, normal, {0, 0}, tangent}};
    quad.indices = {0, 1, 2, 0, 2, 3};
    quad.material = 0;
    scene.meshes = {quad};
    scene.instances = {Instance{0, world}};
    Light sun;
    sun.direction = glm::normalize(glm::vec3(-0.2f, -0.1f, -1.0f));
    sun.intensity = 2.0f;
    scene.lights = {sun};
    scene.camera.position = {0.0f, 0.0f, 2.0f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    return scene;
}

float maxRadiance(const ImageRGBAF& hdr) {
    float m = 0.0f;
    for (size_t i = 0; i < hdr.pixels.size(); i += 4) m = std::max({m, hdr.pixels[i], hdr.pixels[i + 1], hdr.pixels[i + 2]});
    return m;
}

class DegenerateGeometryTest : public testing::TestWithParam<Config> {
protected:
    RenderSettings settings() const {
        RenderSettings s;
        s.width = s.height = 64;
        return s;
    }
};

TEST_P(DegenerateGeometryTest, AZeroScaleAxisShadesAsTheUnsquashedSurface) {
    const glm::vec4 tangent(1, 0, 0, 1);
    // The quad lies in z = 0, so squashing z changes no position, only the normal matrix.
    const test_support::FrameOutput sound = test_support::renderOneFrame(GetParam(), litQuad({0, 0, 1}, tangent, glm::mat4(1.0f), true), settings());
    const test_support::FrameOutput squashed = test_support::renderOneFrame(
        GetParam(), litQuad({0, 0, 1}, tangent, glm::scale(glm::mat4(1.0f), glm::vec3(1, 1, 0)), true), settings());
    test_support::expectFiniteHdr(squashed.hdr, GetParam().name());
    const ImageDifference diff = compareImages(sound.display, squashed.display, 1);
    EXPECT_EQ(diff.differingPixels, 0u) << GetParam().name() << ": max " << diff.maxChannelDifference << " steps in "
                                        << diff.differingPixels << " pixels";
}

TEST_P(DegenerateGeometryTest, ZeroNormalsAndTangentsStayFiniteAndBounded) {
    const test_support::FrameOutput sound =
        test_support::renderOneFrame(GetParam(), litQuad({0, 0, 1}, {1, 0, 0, 1}, glm::mat4(1.0f), true), settings());
    for (const auto& [normal, tangent, label] : {std::tuple{glm::vec3(0.0f), glm::vec4(1, 0, 0, 1), "zero normals"},
                                                  std::tuple{glm::vec3(0, 0, 1), glm::vec4(0.0f), "zero tangents"},
                                                  std::tuple{glm::vec3(0, 0, 1), glm::vec4(0, 0, 1, 1), "tangents along the normal"}}) {
        const test_support::FrameOutput out =
            test_support::renderOneFrame(GetParam(), litQuad(normal, tangent, glm::mat4(1.0f), true), settings());
        const std::string what = fmt::format("{}: {}", GetParam().name(), label);
        test_support::expectFiniteHdr(out.hdr, what);
        // Zero normals face the camera, which here is nearly the true normal; degenerate tangents
        // fall back to the unmapped normal, which the flat normal map gives anyway. Nothing blows
        // up to the fp16 cap, as a NaN clamped by min() could.
        EXPECT_LE(maxRadiance(out.hdr), 1.5f * maxRadiance(sound.hdr)) << what;
        EXPECT_GT(maxRadiance(out.hdr), 0.5f * maxRadiance(sound.hdr)) << what;
    }
}

INSTANTIATE_TEST_SUITE_P(Configs, DegenerateGeometryTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
