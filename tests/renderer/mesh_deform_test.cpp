// The GPU mesh deformer (renderer/src/deform/): skins and morph targets on the compute path
// (deform.comp) and the fallback path (deform_points.vert into texels, copied to a buffer), on
// every configuration, against values computed here by hand; both paths give the same bits.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "core/gpu_scene.h"
#include "deform/mesh_deformer.h"
#include "janus/renderer/renderer.h"
#include "janus/renderer/scene.h"
#include "gltf_test_file.h"
#include "renderer_test_support.h"

namespace janus::renderer {
namespace {

using test_support::Config;

// Four vertices of a quad in z = 0, facing +z, coloured and with UVs (which pass through).
// Vertices 0 and 1 follow joint 0 alone, 2 half joint 0 and half joint 1, 3 joint 1 alone.
// Two morph targets move vertex 1 up and vertex 3 along x, and tilt vertex 1's normal.
Scene deformedQuadScene() {
    Scene scene;
    Mesh mesh;
    const glm::vec3 positions[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    for (int v = 0; v < 4; ++v) {
        Vertex vertex;
        vertex.position = positions[v];
        vertex.normal = {0, 0, 1};
        vertex.uv = glm::vec2(positions[v]);
        vertex.tangent = {1, 0, 0, -1};
        vertex.color = {0.25f * float(v), 0.5f, 1.0f, 0.75f};
        mesh.vertices.push_back(vertex);
    }
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.joints = {{0, 0, 0, 0}, {0, 1, 0, 0}, {0, 1, 0, 0}, {1, 0, 0, 0}};
    mesh.weights = {{1, 0, 0, 0}, {1, 0, 0, 0}, {0.5f, 0.5f, 0, 0}, {1, 0, 0, 0}};
    MorphTarget up, along;
    up.positions = {{0, 0, 0}, {0, 2, 0}, {0, 0, 0}, {0, 0, 0}};
    up.normals = {{0, 0, 0}, {1, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    along.positions = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {4, 0, 0}};
    mesh.morphTargets = {up, along};
    mesh.morphWeights = {0.0f, 0.0f};
    scene.meshes.push_back(mesh);
    Instance instance;
    instance.mesh = 0;
    instance.nodeName = "quad";
    instance.skin = 0;
    // Joint 0 moves by (10, 0, 0); joint 1 turns 90 degrees about z (x -> y, y -> -x).
    instance.jointMatrices = {glm::translate(glm::mat4(1.0f), glm::vec3(10, 0, 0)),
                              glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(0, 0, 1))};
    instance.morphWeights = {0.5f, 0.25f};
    scene.instances.push_back(instance);
    // The skin's joints are two root nodes; the joint matrices are set here directly (what
    // poseScene would derive from the nodes is beside the point of these tests).
    scene.nodes.resize(2);
    scene.nodes[0].name = "joint 0";
    scene.nodes[1].name = "joint 1";
    scene.skins.push_back(Skin{"skin", {0, 1}, {glm::mat4(1.0f), glm::mat4(1.0f)}});
    return scene;
}

// By hand: morph, then skin.
//   v0: (0,0,0)                                   -> joint 0: (10, 0, 0)
//   v1: (1,0,0) + 0.5 (0,2,0) = (1,1,0)           -> joint 0: (11, 1, 0); normal (0.5, 0, 1) normalised
//   v2: (1,1,0); 0.5 (11,1,0) + 0.5 (-1,1,0)      -> (5, 1, 0); normal (0,0,1)
//   v3: (0,1,0) + 0.25 (4,0,0) = (1,1,0)          -> joint 1: (-1, 1, 0); tangent (1,0,0) -> (0,1,0)
const glm::vec3 kExpectedPositions[4] = {{10, 0, 0}, {11, 1, 0}, {5, 1, 0}, {-1, 1, 0}};

std::vector<Vertex> readVertices(rhi::IDevice& device, const rhi::BufferHandle& buffer, size_t count) {
    const std::vector<std::byte> bytes = device.readBuffer(buffer);
    EXPECT_GE(bytes.size(), count * sizeof(Vertex));
    std::vector<Vertex> vertices(count);
    std::memcpy(vertices.data(), bytes.data(), std::min(bytes.size(), count * sizeof(Vertex)));
    return vertices;
}

class MeshDeformTest : public test_support::ConfigTest {};

TEST_P(MeshDeformTest, MorphsThenSkinsEveryVertex) {
    const Scene scene = deformedQuadScene();
    validateScene(scene);
    GpuScene gpuScene(device(), scene);
    MeshDeformer deformer(device(), scene, gpuScene, GetParam().path);
    const rhi::BufferHandle posed = deformer.posedVertices(0);
    ASSERT_TRUE(posed);
    EXPECT_EQ(gpuScene.instanceVertices(0), posed) << "the instance is drawn from its posed vertices";
    const std::vector<Vertex> vertices = readVertices(device(), posed, 4);
    const std::string label = GetParam().name();
    for (int v = 0; v < 4; ++v) {
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(vertices[v].position[c], kExpectedPositions[v][c], 1e-5f) << label << " vertex " << v;
        // What deformation does not touch passes through unchanged.
        EXPECT_EQ(vertices[v].uv, scene.meshes[0].vertices[v].uv) << label << " vertex " << v;
        EXPECT_EQ(vertices[v].color, scene.meshes[0].vertices[v].color) << label << " vertex " << v;
        EXPECT_EQ(vertices[v].tangent.w, -1.0f) << label << " vertex " << v;
    }
    const glm::vec3 tilted = glm::normalize(glm::vec3(0.5f, 0.0f, 1.0f));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(vertices[1].normal[c], tilted[c], 1e-6f) << label;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(vertices[3].tangent[c], glm::vec3(0, 1, 0)[c], 1e-6f) << label;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(vertices[2].normal[c], glm::vec3(0, 0, 1)[c], 1e-6f) << label;
    const std::vector<PassReport> reports = deformer.takeStartupReports();
    ASSERT_EQ(reports.size(), 1u);
    EXPECT_EQ(reports[0].name, GetParam().path == FeaturePath::Compute ? "mesh-deform-compute" : "mesh-deform-fallback");
    EXPECT_EQ(reports[0].dispatches + reports[0].draws, 1u);
    expectNoMessages();
}

// The compute path and the fallback path run the same GLSL (deform_common.glsl) on the same
// device: the posed vertices are the same bits.
TEST_P(MeshDeformTest, ComputeAndFallbackGiveTheSameBits) {
    if (GetParam().path != FeaturePath::Compute) GTEST_SKIP() << "compared from the compute configurations";
    const Scene scene = deformedQuadScene();
    GpuScene computeScene(device(), scene), fallbackScene(device(), scene);
    MeshDeformer compute(device(), scene, computeScene, FeaturePath::Compute);
    MeshDeformer fallback(device(), scene, fallbackScene, FeaturePath::Fallback);
    const std::vector<Vertex> a = readVertices(device(), compute.posedVertices(0), 4);
    const std::vector<Vertex> b = readVertices(device(), fallback.posedVertices(0), 4);
    EXPECT_EQ(std::memcmp(a.data(), b.data(), 4 * sizeof(Vertex)), 0) << GetParam().name();
    expectNoMessages();
}

// A scene without skins or morph targets does no deformation work.
TEST_P(MeshDeformTest, StaticScenesHaveNoDeformPass) {
    Scene scene = deformedQuadScene();
    scene.meshes[0].joints.clear();
    scene.meshes[0].weights.clear();
    scene.meshes[0].morphTargets.clear();
    scene.meshes[0].morphWeights.clear();
    scene.instances[0].morphWeights.clear();
    scene.instances[0].skin = -1;
    scene.instances[0].jointMatrices.clear();
    EXPECT_FALSE(MeshDeformer::needed(scene));
    RenderSettings settings = settingsOfSize(32, 32);
    const test_support::FrameOutput output = test_support::renderOneFrame(GetParam(), scene, settings);
    EXPECT_FALSE(test_support::hasPassStartingWith(output.report, "mesh-deform")) << test_support::passNames(output.report);
    const test_support::FrameOutput deformed = test_support::renderOneFrame(GetParam(), deformedQuadScene(), settings);
    EXPECT_EQ(test_support::countPasses(deformed.report, "mesh-deform"), 1u) << test_support::passNames(deformed.report);
}

// SimpleSkin (two joints, rotating) and AnimatedMorphCube (two morph targets, weights animated):
// what the GPU poses matches the CPU reference (posedVertices) at several times, on both paths.
// Tolerance: float math in a different order on the CPU (1e-5 of the model's unit size).
TEST_P(MeshDeformTest, KhronosModelsMatchTheCpuReferenceAtSeveralTimes) {
    for (const char* model : {"SimpleSkin", "AnimatedMorphCube"}) {
        Scene scene = loadScene(test_support::khronosModel(model));
        ASSERT_FALSE(scene.animations.empty()) << model;
        for (float time : {0.0f, 0.7f, 1.9f, 100.0f}) {
            poseScene(scene, time, 0);
            GpuScene gpuScene(device(), scene);
            MeshDeformer deformer(device(), scene, gpuScene, GetParam().path);
            uint32_t checked = 0;
            for (uint32_t i = 0; i < scene.instances.size(); ++i) {
                if (!MeshDeformer::deforms(scene, scene.instances[i])) continue;
                const std::vector<Vertex> expected = posedVertices(scene, scene.instances[i]);
                const std::vector<Vertex> actual = readVertices(device(), deformer.posedVertices(i), expected.size());
                for (size_t v = 0; v < expected.size(); ++v)
                    for (int c = 0; c < 3; ++c) {
                        ASSERT_NEAR(actual[v].position[c], expected[v].position[c], 1e-5f * (1.0f + std::abs(expected[v].position[c])))
                            << GetParam().name() << " " << model << " t=" << time << " vertex " << v;
                        ASSERT_NEAR(actual[v].normal[c], expected[v].normal[c], 1e-5f)
                            << GetParam().name() << " " << model << " t=" << time << " vertex " << v << " normal";
                    }
                ++checked;
            }
            EXPECT_GT(checked, 0u) << model << ": no deformed instance";
        }
    }
    expectNoMessages();
}

TEST(MeshDeformValidation, BadSkinsAndMorphsAreSceneErrors) {
    auto messageOf = [](const Scene& scene) {
        try {
            validateScene(scene);
        } catch (const SceneError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    Scene scene = deformedQuadScene();
    scene.meshes[0].joints[2] = {0, 7, 0, 0};
    EXPECT_NE(messageOf(scene).find("vertex 2 of mesh 0 uses joint 7, but skin 0 has 2 joints"), std::string::npos) << messageOf(scene);
    scene = deformedQuadScene();
    scene.meshes[0].morphTargets[1].positions.pop_back();
    EXPECT_NE(messageOf(scene).find("morph target 1 has 3 displacements for 4 vertices"), std::string::npos) << messageOf(scene);
    scene = deformedQuadScene();
    scene.instances[0].morphWeights = {1.0f};
    EXPECT_NE(messageOf(scene).find("instance 0 has 1 morph weights but its mesh 0 has 2 morph targets"), std::string::npos) << messageOf(scene);
    scene = deformedQuadScene();
    scene.meshes[0].weights.pop_back();
    EXPECT_NE(messageOf(scene).find("mesh 0 has 4 joint sets and 3 weight sets for 4 vertices"), std::string::npos) << messageOf(scene);
    scene = deformedQuadScene();
    scene.meshes[0].morphTargets.resize(kMaxMorphTargets + 1);
    scene.meshes[0].morphWeights.resize(kMaxMorphTargets + 1);
    scene.instances[0].morphWeights.resize(kMaxMorphTargets + 1);
    EXPECT_NE(messageOf(scene).find("mesh 0 has 65 morph targets; at most 64"), std::string::npos) << messageOf(scene);
}

INSTANTIATE_TEST_SUITE_P(Configs, MeshDeformTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
