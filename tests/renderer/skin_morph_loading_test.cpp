// Skins, morph targets and animations at the loader (issue 13): what is read from crafted files,
// the clear errors for bad ones, CPU reference positions of SimpleSkin and AnimatedMorphCube at
// several times (expected values computed here from the files' own data, independently of the
// code under test), and the six animated Khronos models posed at t = 0.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "gltf_test_file.h"
#include "janus/renderer/scene.h"

namespace janus::renderer {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test_support::sceneErrorOf;
using test_support::TinyGltf;

using test_support::contains;

using test_support::khronosModel;

bool hasWarning(const Scene& scene, const std::string& part) {
    for (const std::string& warning : scene.warnings)
        if (contains(warning, part)) return true;
    return false;
}

// --- crafted files ------------------------------------------------------------------------------

// The tiny triangle skinned: node 0 (the mesh, with skin 0) and joints node 1 ("hip", a root at
// +1 Y) with child node 2 ("knee", +1 Y further). JOINTS_0 as UNSIGNED_BYTE, WEIGHTS_0 as FLOAT.
struct SkinnedFile {
    TinyGltf file;
    SkinnedFile(const uint8_t (&joints)[3][4], const float (&weights)[3][4]) {
        json& attributes = file.gltf["meshes"][0]["primitives"][0]["attributes"];
        attributes["JOINTS_0"] = file.addAccessor(joints, sizeof(joints), {{"componentType", 5121}, {"count", 3}, {"type", "VEC4"}});
        attributes["WEIGHTS_0"] = file.addAccessor(weights, sizeof(weights), {{"componentType", 5126}, {"count", 3}, {"type", "VEC4"}});
        file.gltf["nodes"][0]["skin"] = 0;
        file.gltf["nodes"].push_back({{"name", "hip"}, {"translation", {0, 1, 0}}, {"children", {2}}});
        file.gltf["nodes"].push_back({{"name", "knee"}, {"translation", {0, 1, 0}}});
        file.gltf["scenes"][0]["nodes"] = {0, 1};
        file.gltf["skins"] = json::array({{{"name", "legs"}, {"joints", {1, 2}}}});
    }
    // An animation sampler from float keyframe times and values (`type` of the output).
    void addAnimation(const std::vector<float>& times, const std::vector<float>& values, const std::string& type, int node,
                      const std::string& path, const std::string& interpolation = "LINEAR") {
        const int input = file.addAccessor(times.data(), times.size() * 4, {{"componentType", 5126}, {"count", times.size()}, {"type", "SCALAR"}});
        const size_t width = type == "VEC3" ? 3 : type == "VEC4" ? 4 : 1;
        const int output = file.addAccessor(values.data(), values.size() * 4,
                                            {{"componentType", 5126}, {"count", values.size() / width}, {"type", type}});
        if (!file.gltf.contains("animations")) file.gltf["animations"] = json::array();
        file.gltf["animations"].push_back({{"name", fmt::format("clip{}", file.gltf["animations"].size())},
                                           {"samplers", json::array({{{"input", input}, {"output", output}, {"interpolation", interpolation}}})},
                                           {"channels", json::array({{{"sampler", 0}, {"target", {{"node", node}, {"path", path}}}}})}});
    }
};

constexpr uint8_t kJoints[3][4] = {{0, 1, 0, 0}, {1, 0, 0, 0}, {0, 0, 0, 0}};
constexpr float kWeights[3][4] = {{0.5f, 0.25f, 0, 0}, {1, 0, 0, 0}, {0, 0, 0, 0}};

TEST(GltfSkins, JointsWeightsAndTheSkinAreRead) {
    SkinnedFile skinned(kJoints, kWeights);
    skinned.file.gltf["nodes"][0]["translation"] = {5, 0, 0};   // ignored: the joints place a skinned mesh
    const Scene scene = loadScene(skinned.file.write());
    ASSERT_EQ(scene.skins.size(), 1u);
    EXPECT_EQ(scene.skins[0].name, "legs");
    EXPECT_EQ(scene.skins[0].joints, (std::vector<uint32_t>{1, 2}));
    EXPECT_EQ(scene.skins[0].inverseBindMatrices, std::vector<glm::mat4>(2, glm::mat4(1.0f)));   // none in the file: identity
    const Mesh& mesh = scene.meshes.at(0);
    ASSERT_EQ(mesh.joints.size(), 3u);
    // Renormalised to sum 1; a zero-weight influence points at joint 0.
    EXPECT_EQ(mesh.joints[0], glm::u16vec4(0, 1, 0, 0));
    EXPECT_NEAR(mesh.weights[0].x, 2.0f / 3.0f, 1e-7f);
    EXPECT_NEAR(mesh.weights[0].y, 1.0f / 3.0f, 1e-7f);
    EXPECT_EQ(mesh.joints[1], glm::u16vec4(1, 0, 0, 0));
    EXPECT_EQ(mesh.weights[1], glm::vec4(1, 0, 0, 0));
    // All weights zero: weight 1 on the vertex's first joint.
    EXPECT_EQ(mesh.weights[2], glm::vec4(1, 0, 0, 0));
    ASSERT_EQ(scene.instances.size(), 1u);
    const Instance& instance = scene.instances[0];
    EXPECT_EQ(instance.node, 0);
    EXPECT_EQ(instance.skin, 0);
    EXPECT_EQ(instance.world, glm::mat4(1.0f));
    ASSERT_EQ(instance.jointMatrices.size(), 2u);
    EXPECT_EQ(instance.jointMatrices[0], glm::translate(glm::mat4(1.0f), glm::vec3(0, 1, 0)));
    EXPECT_EQ(instance.jointMatrices[1], glm::translate(glm::mat4(1.0f), glm::vec3(0, 2, 0)));
    ASSERT_EQ(scene.nodes.size(), 3u);
    EXPECT_EQ(scene.nodes[2].parent, 1);
    EXPECT_EQ(scene.nodes[1].children, (std::vector<uint32_t>{2}));
    // Vertex 1 (1, 0, 0) hangs from the knee: (1, 2, 0).
    EXPECT_EQ(posedVertices(scene, instance)[1].position, glm::vec3(1, 2, 0));
}

TEST(GltfSkins, InverseBindMatricesAreRead) {
    SkinnedFile skinned(kJoints, kWeights);
    glm::mat4 matrices[2] = {glm::translate(glm::mat4(1.0f), glm::vec3(0, -1, 0)), glm::translate(glm::mat4(1.0f), glm::vec3(0, -2, 0))};
    skinned.file.gltf["skins"][0]["inverseBindMatrices"] =
        skinned.file.addAccessor(matrices, sizeof(matrices), {{"componentType", 5126}, {"count", 2}, {"type", "MAT4"}});
    const Scene scene = loadScene(skinned.file.write());
    EXPECT_EQ(scene.skins[0].inverseBindMatrices[1], matrices[1]);
    EXPECT_EQ(scene.instances[0].jointMatrices[0], glm::mat4(1.0f));   // bind pose: joint world * inverse bind = identity
    EXPECT_EQ(scene.instances[0].jointMatrices[1], glm::mat4(1.0f));
}

TEST(GltfSkins, ASecondSetKeepsTheFourStrongestOfEight) {
    SkinnedFile skinned(kJoints, kWeights);
    const uint8_t joints1[3][4] = {{1, 1, 1, 1}, {0, 1, 0, 1}, {0, 0, 0, 0}};
    const float weights1[3][4] = {{0.1f, 0.4f, 0.05f, 0.0f}, {0, 0, 0, 0}, {0, 0, 0, 0.5f}};
    json& attributes = skinned.file.gltf["meshes"][0]["primitives"][0]["attributes"];
    attributes["JOINTS_1"] = skinned.file.addAccessor(joints1, sizeof(joints1), {{"componentType", 5121}, {"count", 3}, {"type", "VEC4"}});
    attributes["WEIGHTS_1"] = skinned.file.addAccessor(weights1, sizeof(weights1), {{"componentType", 5126}, {"count", 3}, {"type", "VEC4"}});
    const Scene scene = loadScene(skinned.file.write());
    const Mesh& mesh = scene.meshes.at(0);
    // Vertex 0: 0.5 (joint 0), 0.25 (1), 0.1 (1), 0.4 (1), 0.05 (1) -> 0.5, 0.4, 0.25, 0.1 of sum 1.25.
    EXPECT_EQ(mesh.joints[0], glm::u16vec4(0, 1, 1, 1));
    EXPECT_NEAR(mesh.weights[0].x, 0.4f, 1e-7f);
    EXPECT_NEAR(mesh.weights[0].y, 0.32f, 1e-7f);
    EXPECT_NEAR(mesh.weights[0].z, 0.2f, 1e-7f);
    EXPECT_NEAR(mesh.weights[0].w, 0.08f, 1e-7f);
    // Vertex 2: only the second set carries weight.
    EXPECT_EQ(mesh.joints[2].x, 0);
    EXPECT_EQ(mesh.weights[2], glm::vec4(1, 0, 0, 0));
}

TEST(GltfSkins, NormalizedIntegerWeightsAreRead) {
    SkinnedFile skinned(kJoints, kWeights);
    const uint8_t weights[3][4] = {{255, 0, 0, 0}, {51, 204, 0, 0}, {0, 0, 0, 0}};
    skinned.file.gltf["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] =
        skinned.file.addAccessor(weights, sizeof(weights), {{"componentType", 5121}, {"normalized", true}, {"count", 3}, {"type", "VEC4"}});
    const Scene scene = loadScene(skinned.file.write());
    EXPECT_EQ(scene.meshes[0].joints[1], glm::u16vec4(0, 1, 0, 0));   // strongest first
    EXPECT_NEAR(scene.meshes[0].weights[1].x, 0.8f, 1e-6f);
    EXPECT_NEAR(scene.meshes[0].weights[1].y, 0.2f, 1e-6f);
}

TEST(GltfSkins, AJointPastTheSkinIsAnErrorNamingMeshAndNode) {
    const uint8_t joints[3][4] = {{0, 1, 0, 0}, {2, 0, 0, 0}, {0, 0, 0, 0}};
    SkinnedFile skinned(joints, kWeights);
    const std::string message = sceneErrorOf([&] { loadScene(skinned.file.write()); });
    EXPECT_TRUE(contains(message, "node 'triangle node': mesh 'triangle' primitive 0 gives vertex 1 weight on joint 2, but the node's "
                                  "skin 0 ('legs') has 2 joints"))
        << message;
}

TEST(GltfSkins, WeightsOfTheWrongTypeAreAnError) {
    for (const json& type : {json{{"componentType", 5121}, {"count", 3}, {"type", "VEC4"}},                          // not normalized
                             json{{"componentType", 5120}, {"normalized", true}, {"count", 3}, {"type", "VEC4"}},    // signed
                             json{{"componentType", 5125}, {"count", 3}, {"type", "VEC4"}}}) {                       // UNSIGNED_INT
        SkinnedFile skinned(kJoints, kWeights);
        const uint32_t data[3][4] = {};
        skinned.file.gltf["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] = skinned.file.addAccessor(data, sizeof(data), type);
        const std::string message = sceneErrorOf([&] { loadScene(skinned.file.write()); });
        EXPECT_TRUE(contains(message, "mesh 'triangle' primitive 0 WEIGHTS_0 accessor")) << message;
        EXPECT_TRUE(contains(message, "allowed: FLOAT, or normalized UNSIGNED_BYTE or UNSIGNED_SHORT")) << message;
    }
    SkinnedFile floatJoints(kJoints, kWeights);
    floatJoints.file.gltf["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = 3;   // the FLOAT weights accessor
    const std::string message = sceneErrorOf([&] { loadScene(floatJoints.file.write()); });
    EXPECT_TRUE(contains(message, "JOINTS_0 accessor 3 is FLOAT, which glTF does not allow here; allowed: UNSIGNED_BYTE or UNSIGNED_SHORT"))
        << message;
}

TEST(GltfSkins, BadSkinsAreErrors) {
    {
        SkinnedFile skinned(kJoints, kWeights);
        skinned.file.gltf["skins"][0]["joints"] = json(std::vector<int>(kMaxSkinJoints + 1, 1));
        const std::string message = sceneErrorOf([&] { loadScene(skinned.file.write()); });
        EXPECT_TRUE(contains(message, fmt::format("skin 0 ('legs') has {} joints; Janus skins with at most {}", kMaxSkinJoints + 1, kMaxSkinJoints)))
            << message;
    }
    {
        SkinnedFile skinned(kJoints, kWeights);
        const glm::mat4 one(1.0f);
        skinned.file.gltf["skins"][0]["inverseBindMatrices"] =
            skinned.file.addAccessor(&one, sizeof(one), {{"componentType", 5126}, {"count", 1}, {"type", "MAT4"}});
        const std::string message = sceneErrorOf([&] { loadScene(skinned.file.write()); });
        EXPECT_TRUE(contains(message, "skin 0 ('legs') inverseBindMatrices accessor 4 has 1 matrices for 2 joints")) << message;
    }
    {   // 1100 nodes sharing a 4096-joint skin would need 4.5 Mi joint matrices
        SkinnedFile skinned(kJoints, kWeights);
        skinned.file.gltf["skins"][0]["joints"] = json(std::vector<int>(kMaxSkinJoints, 1));
        json& nodes = skinned.file.gltf["nodes"];
        for (int n = 0; n < 1100; ++n) {
            nodes.push_back({{"mesh", 0}, {"skin", 0}});
            skinned.file.gltf["scenes"][0]["nodes"].push_back(nodes.size() - 1);
        }
        const std::string message = sceneErrorOf([&] { loadScene(skinned.file.write()); });
        EXPECT_TRUE(contains(message, "the skinned instances need more than 4194304 joint matrices")) << message;
    }
    {
        SkinnedFile skinned(kJoints, kWeights);
        skinned.file.gltf["skins"][0]["joints"] = {1, 9};
        const std::string message = sceneErrorOf([&] { loadScene(skinned.file.write()); });
        EXPECT_TRUE(contains(message, "has joint node 9, which does not exist")) << message;
    }
}

// A mesh with joints drawn by a node without a skin (and the reverse) is drawn rigidly, with a warning.
TEST(GltfSkins, SkinAndJointsMismatchesAreDrawnUnskinned) {
    SkinnedFile skinned(kJoints, kWeights);
    skinned.file.gltf["nodes"][0].erase("skin");
    skinned.file.gltf["nodes"][0]["translation"] = {5, 0, 0};
    const Scene scene = loadScene(skinned.file.write());
    ASSERT_EQ(scene.instances.size(), 1u);
    EXPECT_EQ(scene.instances[0].skin, -1);
    EXPECT_TRUE(scene.meshes[scene.instances[0].mesh].joints.empty());
    EXPECT_EQ(glm::vec3(scene.instances[0].world[3]), glm::vec3(5, 0, 0));
    EXPECT_TRUE(hasWarning(scene, "has JOINTS_0/WEIGHTS_0 but node 'triangle node' has no skin"));
}

// --- morph targets ----------------------------------------------------------------------------

// The tiny triangle with morph targets: `targets` position displacements per target (3 vec3 each).
struct MorphFile {
    TinyGltf file;
    explicit MorphFile(const std::vector<std::vector<float>>& targets) {
        json list = json::array();
        for (const std::vector<float>& displacements : targets)
            list.push_back({{"POSITION", file.addAccessor(displacements.data(), displacements.size() * 4,
                                                          {{"componentType", 5126}, {"count", displacements.size() / 3}, {"type", "VEC3"}})}});
        file.gltf["meshes"][0]["primitives"][0]["targets"] = list;
    }
};

const std::vector<float> kUp = {0, 1, 0, 0, 1, 0, 0, 1, 0};
const std::vector<float> kOut = {0, 0, 1, 0, 0, 2, 0, 0, 3};

TEST(GltfMorphTargets, TargetsAndDefaultWeightsAreRead) {
    MorphFile morph({kUp, kOut});
    {
        const Scene scene = loadScene(morph.file.write());
        const Mesh& mesh = scene.meshes.at(0);
        ASSERT_EQ(mesh.morphTargets.size(), 2u);
        EXPECT_EQ(mesh.morphTargets[1].positions[2], glm::vec3(0, 0, 3));
        EXPECT_TRUE(mesh.morphTargets[1].normals.empty());
        EXPECT_EQ(mesh.morphWeights, std::vector<float>({0, 0}));   // no mesh.weights: zeros
        EXPECT_EQ(scene.instances[0].morphWeights, std::vector<float>({0, 0}));
    }
    morph.file.gltf["meshes"][0]["weights"] = {0.5, 0.25};
    {
        const Scene scene = loadScene(morph.file.write());
        EXPECT_EQ(scene.meshes[0].morphWeights, std::vector<float>({0.5f, 0.25f}));
        EXPECT_EQ(scene.instances[0].morphWeights, std::vector<float>({0.5f, 0.25f}));
        EXPECT_EQ(posedVertices(scene, scene.instances[0])[2].position, glm::vec3(0, 1.5f, 0.75f));
    }
    morph.file.gltf["nodes"][0]["weights"] = {1.0, 0.0};   // the node's weights win for its instances
    {
        const Scene scene = loadScene(morph.file.write());
        EXPECT_EQ(scene.instances[0].morphWeights, std::vector<float>({1.0f, 0.0f}));
        EXPECT_EQ(posedVertices(scene, scene.instances[0])[1].position, glm::vec3(1, 1, 0));
    }
}

TEST(GltfMorphTargets, SparseTargetsWork) {
    MorphFile morph({kUp});
    // A second target with no buffer view: zeros but for vertex 1, which moves (7, 8, 9).
    const uint8_t index = 1;
    const float value[3] = {7, 8, 9};
    const int indices = morph.file.addAccessor(&index, 1, {{"componentType", 5121}, {"count", 1}, {"type", "SCALAR"}});
    const int values = morph.file.addAccessor(value, sizeof(value), {{"componentType", 5126}, {"count", 1}, {"type", "VEC3"}});
    json& accessors = morph.file.gltf["accessors"];
    accessors.push_back({{"componentType", 5126}, {"count", 3}, {"type", "VEC3"},
                         {"sparse", {{"count", 1}, {"indices", {{"bufferView", accessors[size_t(indices)]["bufferView"]}, {"componentType", 5121}}},
                                     {"values", {{"bufferView", accessors[size_t(values)]["bufferView"]}}}}}});
    const size_t sparseTarget = accessors.size() - 1;
    morph.file.gltf["meshes"][0]["primitives"][0]["targets"].push_back({{"POSITION", sparseTarget}});
    const Scene scene = loadScene(morph.file.write());
    ASSERT_EQ(scene.meshes[0].morphTargets.size(), 2u);
    EXPECT_EQ(scene.meshes[0].morphTargets[1].positions,
              (std::vector<glm::vec3>{glm::vec3(0), glm::vec3(7, 8, 9), glm::vec3(0)}));

    // Its sparse index past the accessor's count: a clear error naming the morph target.
    const uint8_t bad = 3;
    const int badIndex = morph.file.addAccessor(&bad, 1, {{"componentType", 5121}, {"count", 1}, {"type", "SCALAR"}});
    accessors[sparseTarget]["sparse"]["indices"]["bufferView"] = accessors[size_t(badIndex)]["bufferView"];
    const std::string message = sceneErrorOf([&] { loadScene(morph.file.write()); });
    EXPECT_TRUE(contains(message, "mesh 'triangle' primitive 0 morph target 1 POSITION accessor")) << message;
    EXPECT_TRUE(contains(message, "sparse index 3 (entry 0), outside the accessor's 3 elements")) << message;
}

TEST(GltfMorphTargets, BadTargetsAreErrors) {
    {
        MorphFile morph({kUp, {0, 1, 0, 0, 1, 0}});   // two displacements for three vertices
        const std::string message = sceneErrorOf([&] { loadScene(morph.file.write()); });
        EXPECT_TRUE(contains(message, "mesh 'triangle' primitive 0 morph target 1 POSITION has 2 elements but the primitive's POSITION has 3"))
            << message;
    }
    {
        MorphFile morph({kUp});
        json& targets = morph.file.gltf["meshes"][0]["primitives"][0]["targets"];
        for (size_t t = 1; t <= kMaxMorphTargets; ++t) targets.push_back(targets[0]);
        const std::string message = sceneErrorOf([&] { loadScene(morph.file.write()); });
        EXPECT_TRUE(contains(message, fmt::format("has {} morph targets; Janus morphs with at most {}", kMaxMorphTargets + 1, kMaxMorphTargets)))
            << message;
    }
    {
        MorphFile morph({kUp, kOut});
        morph.file.gltf["meshes"][0]["weights"] = {1.0};
        const std::string message = sceneErrorOf([&] { loadScene(morph.file.write()); });
        EXPECT_TRUE(contains(message, "mesh 'triangle' has 1 default weights but 2 morph targets")) << message;
    }
    {
        MorphFile morph({kUp, kOut});
        morph.file.gltf["nodes"][0]["weights"] = {1.0, 0.0, 0.0};
        const std::string message = sceneErrorOf([&] { loadScene(morph.file.write()); });
        EXPECT_TRUE(contains(message, "node 'triangle node' has 3 morph weights but mesh 'triangle' primitive 0 has 2 morph targets")) << message;
    }
}

// --- animations -------------------------------------------------------------------------------

TEST(GltfAnimations, NodeAnimationsAreReadAndTheSceneIsPosedAtTimeZero) {
    SkinnedFile skinned(kJoints, kWeights);
    skinned.addAnimation({0.5f, 1.5f}, {0, 3, 0, 0, 5, 0}, "VEC3", 1, "translation");
    skinned.addAnimation({0.0f, 1.0f}, {0, 0, 0, 1, 0, 0, 1, 0}, "VEC4", 2, "rotation", "STEP");
    const Scene scene = loadScene(skinned.file.write());
    ASSERT_EQ(scene.animations.size(), 2u);
    const Animation& slide = scene.animations[0];
    EXPECT_EQ(slide.name, "clip0");
    EXPECT_EQ(slide.duration, 1.5f);
    ASSERT_EQ(slide.channels.size(), 1u);
    EXPECT_EQ(slide.channels[0].node, 1u);
    EXPECT_EQ(slide.channels[0].path, AnimationPath::Translation);
    EXPECT_EQ(slide.samplers[0].components, 3u);
    EXPECT_EQ(scene.animations[1].samplers[0].interpolation, Interpolation::Step);
    // Posed at t = 0 of animation 0, which clamps to its first keyframe: the hip at +3 Y.
    EXPECT_EQ(scene.posedAnimation, std::optional<size_t>(0));
    EXPECT_EQ(scene.posedTime, 0.0f);
    EXPECT_EQ(glm::vec3(scene.nodes[1].world[3]), glm::vec3(0, 3, 0));
    EXPECT_EQ(glm::vec3(scene.instances[0].jointMatrices[0][3]), glm::vec3(0, 3, 0));
    EXPECT_EQ(scene.nodes[1].translation, glm::vec3(0, 1, 0));   // the rest pose is kept
}

TEST(GltfAnimations, RotationsMayBeNormalizedIntegers) {
    SkinnedFile skinned(kJoints, kWeights);
    skinned.addAnimation({0.0f, 1.0f}, {0, 0, 0, 1, 0, 0, 0, 1}, "VEC4", 2, "rotation");
    const int16_t rotations[2][4] = {{0, 0, 0, 32767}, {0, 0, 32767, 0}};   // identity; 180 degrees about Z
    json& sampler = skinned.file.gltf["animations"][0]["samplers"][0];
    sampler["output"] = skinned.file.addAccessor(rotations, sizeof(rotations),
                                                 {{"componentType", 5122}, {"normalized", true}, {"count", 2}, {"type", "VEC4"}});
    Scene scene = loadScene(skinned.file.write());
    poseScene(scene, 0.5f, 0);
    const glm::vec3 x = glm::mat3(scene.nodes[2].world) * glm::vec3(1, 0, 0);
    EXPECT_NEAR(x.x, 0.0f, 1e-6f);   // 90 degrees about Z
    EXPECT_NEAR(x.y, 1.0f, 1e-6f);
    // Translations must be FLOAT.
    json& channel = skinned.file.gltf["animations"][0]["channels"][0];
    channel["target"]["path"] = "translation";
    const std::string message = sceneErrorOf([&] { loadScene(skinned.file.write()); });
    EXPECT_TRUE(contains(message, "animation 0 ('clip0') channel 0 animates translation with sampler 0, whose output is not VEC3 FLOAT"))
        << message;
}

TEST(GltfAnimations, MorphWeightsAreAnimated) {
    MorphFile morph({kUp, kOut});
    const std::vector<float> times = {0.0f, 2.0f};
    const std::vector<float> weights = {0, 0, 1, 0.5f};   // per keyframe, one per target
    const int input = morph.file.addAccessor(times.data(), 8, {{"componentType", 5126}, {"count", 2}, {"type", "SCALAR"}});
    const int output = morph.file.addAccessor(weights.data(), 16, {{"componentType", 5126}, {"count", 4}, {"type", "SCALAR"}});
    morph.file.gltf["animations"] = json::array({{{"samplers", json::array({{{"input", input}, {"output", output}}})},
                                                  {"channels", json::array({{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}})}}});
    Scene scene = loadScene(morph.file.write());
    EXPECT_EQ(scene.animations[0].samplers[0].components, 2u);
    poseScene(scene, 1.0f, 0);
    EXPECT_EQ(scene.instances[0].morphWeights, std::vector<float>({0.5f, 0.25f}));
    EXPECT_EQ(posedVertices(scene, scene.instances[0])[2].position, glm::vec3(0, 1.5f, 0.75f));
}

// A rigid node's animation moves its instance (and lights, markers and cameras ride along).
TEST(GltfAnimations, RigidNodesLightsAndMarkersFollowTheirNodes) {
    TinyGltf file;
    const std::vector<float> times = {0.0f, 1.0f};
    const std::vector<float> moves = {0, 0, 0, 10, 0, 0};
    const int input = file.addAccessor(times.data(), 8, {{"componentType", 5126}, {"count", 2}, {"type", "SCALAR"}});
    const int output = file.addAccessor(moves.data(), 24, {{"componentType", 5126}, {"count", 2}, {"type", "VEC3"}});
    file.gltf["nodes"][0]["children"] = {1, 2};
    file.gltf["nodes"].push_back({{"name", "lamp"}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    file.gltf["nodes"].push_back({{"name", "spot marker"}, {"translation", {0, 1, 0}}});
    file.gltf["extensionsUsed"] = {"KHR_lights_punctual"};
    file.gltf["extensions"] = {{"KHR_lights_punctual", {{"lights", json::array({{{"type", "point"}}})}}}};
    file.gltf["animations"] = json::array({{{"name", "slide"}, {"samplers", json::array({{{"input", input}, {"output", output}}})},
                                            {"channels", json::array({{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}})}}});
    Scene scene = loadScene(file.write());
    poseScene(scene, 0.5f, 0);
    EXPECT_EQ(glm::vec3(scene.instances[0].world[3]), glm::vec3(5, 0, 0));
    ASSERT_EQ(scene.lights.size(), 1u);
    EXPECT_EQ(scene.lights[0].node, 1);
    EXPECT_EQ(scene.lights[0].position, glm::vec3(5, 0, 0));
    ASSERT_EQ(scene.markers.size(), 1u);
    EXPECT_EQ(glm::vec3(scene.markers[0].world[3]), glm::vec3(5, 1, 0));
}

TEST(GltfAnimations, BadSamplersAreClearErrors) {
    auto errorOf = [](const std::vector<float>& times, const std::vector<float>& values, const std::string& interpolation = "LINEAR") {
        SkinnedFile skinned(kJoints, kWeights);
        skinned.addAnimation(times, values, "VEC3", 1, "translation", interpolation);
        return sceneErrorOf([&] { loadScene(skinned.file.write()); });
    };
    std::string message = errorOf({0.0f, 1.0f, 1.0f}, std::vector<float>(9, 0.0f));
    EXPECT_TRUE(contains(message, "animation 0 ('clip0') sampler 0 input is not strictly increasing: keyframe 2 at 1 s follows 1 s")) << message;
    message = errorOf({0.0f, 2.0f, 1.0f}, std::vector<float>(9, 0.0f));
    EXPECT_TRUE(contains(message, "keyframe 2 at 1 s follows 2 s")) << message;
    message = errorOf({-1.0f, 1.0f}, std::vector<float>(6, 0.0f));
    EXPECT_TRUE(contains(message, "animation 0 ('clip0') sampler 0 input has keyframe time -1 (keyframe 0); times must be finite and >= 0"))
        << message;
    message = errorOf({0.0f, 1.0f}, std::vector<float>(9, 0.0f));
    EXPECT_TRUE(contains(message, "animation 0 ('clip0') sampler 0 output accessor 5 has 3 elements for 2 keyframes; it needs 2 (one value per keyframe)"))
        << message;
    message = errorOf({0.0f, 1.0f}, std::vector<float>(6, 0.0f), "CUBICSPLINE");
    EXPECT_TRUE(contains(message, "has 2 elements for 2 keyframes; it needs 6 (in-tangent, value and out-tangent per keyframe for CUBICSPLINE)"))
        << message;
    message = errorOf({0.0f, 1.0f}, std::vector<float>(6, 0.0f), "SMOOTH");
    EXPECT_TRUE(contains(message, "sampler 0 has interpolation 'SMOOTH'; glTF allows LINEAR, STEP and CUBICSPLINE")) << message;

    // A weights output that is not keyframes x targets.
    MorphFile morph({kUp, kOut});
    const std::vector<float> times = {0.0f, 2.0f};
    const std::vector<float> weights = {0, 0, 1};
    const int input = morph.file.addAccessor(times.data(), 8, {{"componentType", 5126}, {"count", 2}, {"type", "SCALAR"}});
    const int output = morph.file.addAccessor(weights.data(), 12, {{"componentType", 5126}, {"count", 3}, {"type", "SCALAR"}});
    morph.file.gltf["animations"] = json::array({{{"samplers", json::array({{{"input", input}, {"output", output}}})},
                                                  {"channels", json::array({{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}})}}});
    message = sceneErrorOf([&] { loadScene(morph.file.write()); });
    EXPECT_TRUE(contains(message, "animation 0 sampler 0 output accessor 5 has 3 elements for 2 keyframes; it needs a multiple of 2")) << message;
}

TEST(GltfAnimations, BadChannelsAreErrorsOrSkipped) {
    {
        SkinnedFile skinned(kJoints, kWeights);
        skinned.file.gltf["nodes"][2].erase("translation");
        skinned.file.gltf["nodes"][2]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 1};
        skinned.addAnimation({0.0f, 1.0f}, std::vector<float>(6, 0.0f), "VEC3", 2, "translation");
        const std::string message = sceneErrorOf([&] { loadScene(skinned.file.write()); });
        EXPECT_TRUE(contains(message, "animation 0 ('clip0') channel 0 animates the translation of node 'knee', which has a 'matrix'")) << message;
    }
    {
        SkinnedFile skinned(kJoints, kWeights);
        skinned.addAnimation({0.0f, 1.0f}, std::vector<float>(6, 0.0f), "VEC3", 7, "translation");
        const std::string message = sceneErrorOf([&] { loadScene(skinned.file.write()); });
        EXPECT_TRUE(contains(message, "channel 0 targets node 7, which does not exist (the file has 3 nodes)")) << message;
    }
    {
        SkinnedFile skinned(kJoints, kWeights);
        skinned.addAnimation({0.0f, 1.0f}, std::vector<float>(6, 0.0f), "VEC3", 1, "rotation");
        const std::string message = sceneErrorOf([&] { loadScene(skinned.file.write()); });
        EXPECT_TRUE(contains(message, "animates rotation with sampler 0, whose output is not VEC4")) << message;
    }
    {
        SkinnedFile skinned(kJoints, kWeights);
        skinned.addAnimation({0.0f, 1.0f}, std::vector<float>(2, 0.0f), "SCALAR", 1, "weights");
        const std::string message = sceneErrorOf([&] { loadScene(skinned.file.write()); });
        EXPECT_TRUE(contains(message, "animates the morph weights of node 'hip', which has no mesh with morph targets")) << message;
    }
    {   // KHR_animation_pointer's path (and any other) is skipped with a warning
        SkinnedFile skinned(kJoints, kWeights);
        skinned.addAnimation({0.0f, 1.0f}, std::vector<float>(6, 0.0f), "VEC3", 1, "pointer");
        const Scene scene = loadScene(skinned.file.write());
        ASSERT_EQ(scene.animations.size(), 1u);
        EXPECT_TRUE(scene.animations[0].channels.empty());
        EXPECT_TRUE(hasWarning(scene, "animation 0 ('clip0') channel 0: ignoring target path 'pointer'"));
    }
    {   // KHR_animation_pointer proper: no target node (tinygltf alone would refuse the file), in .gltf and .glb
        SkinnedFile skinned(kJoints, kWeights);
        skinned.addAnimation({0.0f, 1.0f}, {0, 0, 0, 0, 6, 0}, "VEC3", 1, "translation");
        json& channels = skinned.file.gltf["animations"][0]["channels"];
        const json pointer = {{"sampler", 0},
                              {"target", {{"path", "pointer"}, {"extensions", {{"KHR_animation_pointer", {{"pointer", "/nodes/1/translation"}}}}}}}};
        channels.insert(channels.begin(), pointer);
        for (const fs::path& file : {skinned.file.write(), skinned.file.writeGlb()}) {
            Scene scene = loadScene(file);
            ASSERT_EQ(scene.animations.at(0).channels.size(), 1u) << file;
            EXPECT_TRUE(hasWarning(scene, "animation 0 ('clip0') channel 0: ignoring a channel without a target node (path 'pointer', "
                                          "KHR_animation_pointer)"))
                << file;
            poseScene(scene, 0.5f, 0);
            EXPECT_EQ(glm::vec3(scene.nodes[1].world[3]), glm::vec3(0, 3, 0)) << file;
        }
    }
}

TEST(GltfAnimations, AMatrixNodeIsDecomposedAndKeptExact) {
    TinyGltf file;
    const glm::mat4 m = glm::translate(glm::mat4(1.0f), glm::vec3(1, 2, 3)) * glm::mat4_cast(glm::angleAxis(0.5f, glm::vec3(0, 0, 1))) *
                        glm::scale(glm::mat4(1.0f), glm::vec3(2, 3, 4));
    json matrix = json::array();
    for (int i = 0; i < 16; ++i) matrix.push_back(glm::value_ptr(m)[i]);
    file.gltf["nodes"][0]["matrix"] = matrix;
    const Scene scene = loadScene(file.write());
    const Node& node = scene.nodes.at(0);
    ASSERT_TRUE(node.matrix.has_value());
    EXPECT_EQ(*node.matrix, m);
    EXPECT_EQ(scene.instances[0].world, m);
    EXPECT_NEAR(glm::length(node.translation - glm::vec3(1, 2, 3)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(node.scale - glm::vec3(2, 3, 4)), 0.0f, 1e-5f);
    EXPECT_NEAR(std::abs(glm::dot(node.rotation, glm::angleAxis(0.5f, glm::vec3(0, 0, 1)))), 1.0f, 1e-6f);
}

TEST(GltfAnimations, AHundredThousandDeepAnimatedChainLoadsAndPoses) {
    TinyGltf file;
    constexpr int kDepth = 100000;
    file.makeNodeChain(kDepth);
    const std::vector<float> times = {0.0f, 1.0f};
    const std::vector<float> moves = {0, 0, 0.5f, 0, 2, 0.5f};
    const int input = file.addAccessor(times.data(), 8, {{"componentType", 5126}, {"count", 2}, {"type", "SCALAR"}});
    const int output = file.addAccessor(moves.data(), 24, {{"componentType", 5126}, {"count", 2}, {"type", "VEC3"}});
    file.gltf["animations"] = json::array({{{"samplers", json::array({{{"input", input}, {"output", output}}})},
                                            {"channels", json::array({{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}})}}});
    Scene scene = loadScene(file.write());
    ASSERT_EQ(scene.nodes.size(), size_t(kDepth));
    EXPECT_EQ(scene.instances.at(0).world[3], glm::vec4(0, 0, 0.5f * kDepth, 1));
    poseScene(scene, 1.0f, 0);
    EXPECT_EQ(scene.instances.at(0).world[3], glm::vec4(0, 2, 0.5f * kDepth, 1));
}

// --- the scene file's "time" and "animation" ---------------------------------------------------

TEST(SceneFileAnimation, TimeAndAnimationKeysPoseTheScene) {
    SkinnedFile skinned(kJoints, kWeights);
    skinned.addAnimation({0.0f, 1.0f}, {0, 0, 0, 4, 0, 0}, "VEC3", 1, "translation");
    skinned.addAnimation({0.0f, 1.0f}, {0, 0, 0, 0, 8, 0}, "VEC3", 1, "translation");
    skinned.file.gltf["animations"][1]["name"] = "lift";
    skinned.file.write();
    auto load = [&](const json& keys) {
        json sceneFile = keys;
        sceneFile["gltf"] = "tri.gltf";
        return loadScene(skinned.file.writeText("scene.json", sceneFile.dump()));
    };
    Scene scene = load({{"time", 0.5}});
    EXPECT_EQ(scene.posedAnimation, std::optional<size_t>(0));
    EXPECT_EQ(scene.posedTime, 0.5f);
    EXPECT_EQ(glm::vec3(scene.nodes[1].world[3]), glm::vec3(2, 0, 0));
    scene = load({{"time", 0.25}, {"animation", "lift"}});
    EXPECT_EQ(scene.posedAnimation, std::optional<size_t>(1));
    EXPECT_EQ(glm::vec3(scene.nodes[1].world[3]), glm::vec3(0, 2, 0));
    scene = load({{"animation", 1}});
    EXPECT_EQ(scene.posedAnimation, std::optional<size_t>(1));
    EXPECT_EQ(scene.posedTime, 0.0f);

    std::string message = sceneErrorOf([&] { load({{"time", -1}}); });
    EXPECT_TRUE(contains(message, "scene.json: \"time\" must be a number of seconds >= 0, got -1")) << message;
    message = sceneErrorOf([&] { load({{"time", "soon"}}); });
    EXPECT_TRUE(contains(message, "\"time\" must be a number of seconds >= 0, got \"soon\"")) << message;
    message = sceneErrorOf([&] { load({{"animation", "walk"}}); });
    EXPECT_TRUE(contains(message, "\"animation\": no animation is named 'walk'; the scene's animations: 0 'clip0', 1 'lift'")) << message;
    message = sceneErrorOf([&] { load({{"animation", 2}}); });
    EXPECT_TRUE(contains(message, "\"animation\": animation index 2 is out of range")) << message;
    message = sceneErrorOf([&] { load({{"animation", true}}); });
    EXPECT_TRUE(contains(message, "\"animation\" must be an animation's name or index, got true")) << message;
}

// --- the Khronos sample models ------------------------------------------------------------------

// The floats of accessor `index` (FLOAT or UNSIGNED_SHORT, not sparse), read directly from the
// file: the test's own reader, independent of the loader.
std::vector<float> readAccessor(const fs::path& gltfPath, const json& gltf, size_t index) {
    const json& accessor = gltf["accessors"][index];
    const json& view = gltf["bufferViews"][accessor["bufferView"].get<size_t>()];
    const json& buffer = gltf["buffers"][view["buffer"].get<size_t>()];
    std::ifstream in(gltfPath.parent_path() / buffer["uri"].get<std::string>(), std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string type = accessor["type"];
    const size_t width = type == "SCALAR" ? 1 : type == "VEC2" ? 2 : type == "VEC3" ? 3 : type == "VEC4" ? 4 : 16;
    const bool shorts = accessor["componentType"] == 5123;
    const size_t componentSize = shorts ? 2 : 4;
    const size_t stride = view.value("byteStride", width * componentSize);
    const size_t start = view.value("byteOffset", size_t(0)) + accessor.value("byteOffset", size_t(0));
    std::vector<float> out;
    for (size_t e = 0; e < accessor["count"].get<size_t>(); ++e)
        for (size_t c = 0; c < width; ++c) {
            const char* p = bytes.data() + start + e * stride + c * componentSize;
            if (shorts) {
                uint16_t v;
                std::memcpy(&v, p, 2);
                out.push_back(float(v));
            } else {
                float v;
                std::memcpy(&v, p, 4);
                out.push_back(v);
            }
        }
    return out;
}

json readJson(const fs::path& path) {
    std::ifstream in(path);
    return json::parse(in);
}

// SimpleSkin: a strip of ten vertices skinned to joint 0 (node 1, at rest at the origin) and joint 1
// (node 2, at (0, 1, 0), turned about Z by the animation). Its rotations all turn about Z, so slerp
// is linear in the angle: the expected pose needs no quaternion code.
TEST(KhronosAnimated, SimpleSkinMatchesAHandComputedPoseAtSeveralTimes) {
    const fs::path path = khronosModel("SimpleSkin");
    const json gltf = readJson(path);
    const std::vector<float> positions = readAccessor(path, gltf, 1), joints = readAccessor(path, gltf, 2),
                             weights = readAccessor(path, gltf, 3), inverseBind = readAccessor(path, gltf, 4),
                             times = readAccessor(path, gltf, 5), rotations = readAccessor(path, gltf, 6);
    ASSERT_EQ(positions.size(), 30u);
    Scene scene = loadScene(path);
    ASSERT_EQ(scene.instances.size(), 1u);
    for (float time : {0.0f, 0.3f, 1.0f, 1.25f, 2.2f, 3.6f, 4.75f, 5.5f, 9.0f}) {
        poseScene(scene, time, 0);
        // The joint's angle at `time`: clamped, then linear between the keyframes' angles.
        float angle = 0.0f;
        auto keyAngle = [&](size_t k) { return 2.0f * std::atan2(rotations[k * 4 + 2], rotations[k * 4 + 3]); };
        if (time >= times.back()) angle = keyAngle(times.size() - 1);
        else
            for (size_t k = 0; k + 1 < times.size(); ++k)
                if (time >= times[k] && time < times[k + 1])
                    angle = keyAngle(k) + (keyAngle(k + 1) - keyAngle(k)) * (time - times[k]) / (times[k + 1] - times[k]);
        glm::mat4 joint[2];
        glm::mat4 bind[2];
        for (int j = 0; j < 2; ++j) bind[j] = glm::make_mat4(&inverseBind[size_t(j) * 16]);
        joint[0] = bind[0];   // node 1 has no transform
        joint[1] = glm::translate(glm::mat4(1.0f), glm::vec3(0, 1, 0)) * glm::rotate(glm::mat4(1.0f), angle, glm::vec3(0, 0, 1)) * bind[1];
        const std::vector<Vertex> posed = posedVertices(scene, scene.instances[0]);
        for (size_t v = 0; v < 10; ++v) {
            const glm::vec4 p(positions[v * 3], positions[v * 3 + 1], positions[v * 3 + 2], 1.0f);
            glm::vec4 expected(0.0f);
            for (size_t i = 0; i < 4; ++i) expected += weights[v * 4 + i] * (joint[size_t(joints[v * 4 + i])] * p);
            EXPECT_NEAR(glm::length(posed[v].position - glm::vec3(expected)), 0.0f, 2e-6f) << "vertex " << v << " at " << time << " s";
        }
    }
    // Sanity of the expectation itself: at 1 s the joint has turned 90 degrees, so the top vertex
    // (0.5, 2, 0), fully on joint 1, sits at (-1, 1.5, 0).
    poseScene(scene, 1.0f, 0);
    EXPECT_NEAR(glm::length(posedVertices(scene, scene.instances[0])[9].position - glm::vec3(-1.0f, 1.5f, 0.0f)), 0.0f, 2e-3f);
}

// AnimatedMorphCube: two morph targets whose weights the animation "Square" keys 127 times.
TEST(KhronosAnimated, AnimatedMorphCubeMatchesHandComputedWeightsAndPositions) {
    const fs::path path = khronosModel("AnimatedMorphCube");
    const json gltf = readJson(path);
    const json& primitive = gltf["meshes"][0]["primitives"][0];
    const std::vector<float> base = readAccessor(path, gltf, primitive["attributes"]["POSITION"].get<size_t>());
    const std::vector<float> target0 = readAccessor(path, gltf, primitive["targets"][0]["POSITION"].get<size_t>());
    const std::vector<float> target1 = readAccessor(path, gltf, primitive["targets"][1]["POSITION"].get<size_t>());
    const json& sampler = gltf["animations"][0]["samplers"][0];
    const std::vector<float> times = readAccessor(path, gltf, sampler["input"].get<size_t>());
    const std::vector<float> keyed = readAccessor(path, gltf, sampler["output"].get<size_t>());
    ASSERT_EQ(keyed.size(), times.size() * 2);
    Scene scene = loadScene(path);
    ASSERT_EQ(scene.instances.size(), 1u);
    for (float time : {0.0f, 0.51f, 1.0f, 1.7f, 2.3f, 3.05f, 4.0f, 4.19999743f, 6.0f}) {
        poseScene(scene, time, 0);
        float w[2] = {keyed[keyed.size() - 2], keyed[keyed.size() - 1]};
        for (size_t k = 0; k + 1 < times.size(); ++k)
            if (time >= times[k] && time < times[k + 1]) {
                const float s = (time - times[k]) / (times[k + 1] - times[k]);
                for (size_t t = 0; t < 2; ++t) w[t] = keyed[k * 2 + t] + (keyed[(k + 1) * 2 + t] - keyed[k * 2 + t]) * s;
            }
        ASSERT_EQ(scene.instances[0].morphWeights.size(), 2u);
        EXPECT_NEAR(scene.instances[0].morphWeights[0], w[0], 1e-6f) << time;
        EXPECT_NEAR(scene.instances[0].morphWeights[1], w[1], 1e-6f) << time;
        const std::vector<Vertex> posed = posedVertices(scene, scene.instances[0]);
        for (size_t v = 0; v < 24; ++v) {
            const glm::vec3 expected(base[v * 3] + w[0] * target0[v * 3] + w[1] * target1[v * 3],
                                     base[v * 3 + 1] + w[0] * target0[v * 3 + 1] + w[1] * target1[v * 3 + 1],
                                     base[v * 3 + 2] + w[0] * target0[v * 3 + 2] + w[1] * target1[v * 3 + 2]);
            EXPECT_NEAR(glm::length(posed[v].position - expected), 0.0f, 1e-7f) << "vertex " << v << " at " << time << " s";
        }
    }
    // Sanity of the expectation itself: somewhere in the clip the cube is visibly morphed.
    poseScene(scene, 1.0f, 0);
    EXPECT_GT(scene.instances[0].morphWeights[0] + scene.instances[0].morphWeights[1], 0.1f);
}

// The six animated models load and are posed at t = 0 of their first animation; every animation
// poses at its middle and end with finite posed vertices.
TEST(KhronosAnimated, TheAnimatedModelsLoadAndPose) {
    for (const char* model : {"SimpleSkin", "RiggedSimple", "CesiumMan", "Fox", "SimpleMorph", "AnimatedMorphCube"}) {
        SCOPED_TRACE(model);
        Scene scene;
        ASSERT_NO_THROW(scene = loadScene(khronosModel(model)));
        ASSERT_FALSE(scene.animations.empty());
        EXPECT_EQ(scene.posedAnimation, std::optional<size_t>(0));
        EXPECT_EQ(scene.posedTime, 0.0f);
        for (size_t a = 0; a < scene.animations.size(); ++a)
            for (float time : {0.0f, scene.animations[a].duration * 0.5f, scene.animations[a].duration}) {
                poseScene(scene, time, a);
                EXPECT_NO_THROW(validateScene(scene));
                for (const Instance& instance : scene.instances) {
                    if (instance.skin >= 0) {
                        EXPECT_EQ(instance.jointMatrices.size(), scene.skins[size_t(instance.skin)].joints.size());
                    }
                    for (const Vertex& v : posedVertices(scene, instance))
                        ASSERT_TRUE(std::isfinite(v.position.x + v.position.y + v.position.z + v.normal.x + v.normal.y + v.normal.z));
                }
            }
    }
    const Scene fox = loadScene(khronosModel("Fox"));
    ASSERT_EQ(fox.animations.size(), 3u);
    EXPECT_EQ(findAnimation(fox, "Walk"), 1u);
    EXPECT_EQ(fox.skins.at(0).joints.size(), 24u);
}

}  // namespace
}  // namespace janus::renderer
