// Loader safety (issue 11): what a glTF may read (URIs inside or outside its folder, data: URIs),
// image size limits, node hierarchies (deep, cyclic, shared), quantized and normalised vertex
// attributes (KHR_mesh_quantization) and KHR_lights_punctual ranges <= 0. Every file is crafted
// here, in a temporary folder; docs/SCENES.md states the rules these tests pin.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "janus/renderer/image.h"
#include "janus/renderer/scene.h"
#include "renderer/gltf_test_file.h"

namespace janus::renderer {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test_support::sceneErrorOf;
using test_support::TinyGltf;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// --- node hierarchies --------------------------------------------------------------------------

TEST(GltfNodes, HundredThousandNestedNodesDoNotOverflowTheStack) {
    TinyGltf file;
    constexpr int kDepth = 100000;
    json nodes = json::array();
    for (int i = 0; i < kDepth; ++i) {
        json node = {{"translation", {0.0, 0.0, 0.5}}};
        if (i + 1 < kDepth) node["children"] = {i + 1};
        else node["mesh"] = 0;
        nodes.push_back(std::move(node));
    }
    file.gltf["nodes"] = std::move(nodes);
    const Scene scene = loadScene(file.write());
    ASSERT_EQ(scene.instances.size(), 1u);
    EXPECT_EQ(scene.instances[0].world[3].z, 0.5f * kDepth);   // every level's translation applied (exact in float)
    EXPECT_TRUE(scene.markers.empty());
}

TEST(GltfNodes, CycleIsAnErrorNamingTheNode) {
    TinyGltf file;
    file.gltf["nodes"] = json::array({{{"name", "a"}, {"children", {1}}}, {{"name", "b"}, {"children", {2}}},
                                      {{"name", "c"}, {"children", {0}}, {"mesh", 0}}});
    const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
    EXPECT_TRUE(contains(message, "node 0 ('a') is its own ancestor")) << message;
}

// Without a "scenes" list the roots are the nodes nobody names as a child, so a cycle has no
// root: it used to be skipped silently.
TEST(GltfNodes, CycleWithoutAScenesListIsAnError) {
    TinyGltf file;
    file.gltf.erase("scenes");
    file.gltf.erase("scene");
    file.gltf["nodes"] = json::array({{{"name", "a"}, {"children", {1}}, {"mesh", 0}}, {{"name", "b"}, {"children", {0}}}});
    const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
    EXPECT_TRUE(contains(message, "cycle")) << message;
    EXPECT_TRUE(contains(message, "'a'")) << message;
}

// A node with two parents would be instanced twice; a chain of them, 2^depth times.
TEST(GltfNodes, NodeWithTwoParentsIsAnError) {
    TinyGltf file;
    file.gltf["nodes"] = json::array({{{"name", "left"}, {"children", {2}}}, {{"name", "right"}, {"children", {2}}},
                                      {{"name", "shared"}, {"mesh", 0}}});
    file.gltf["scenes"][0]["nodes"] = {0, 1};
    const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
    EXPECT_TRUE(contains(message, "node 2 ('shared') is reached twice (again as a child of 'right')")) << message;
}

TEST(GltfNodes, ChildThatDoesNotExistIsNamed) {
    TinyGltf file;
    file.gltf["nodes"][0]["children"] = {7};
    const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
    EXPECT_TRUE(contains(message, "node 'triangle node' has child 7, which does not exist")) << message;
}

// --- vertex attributes: normalised integers and KHR_mesh_quantization ---------------------------

TEST(GltfAttributes, NormalizedIntegersAreNormalised) {
    TinyGltf file;
    const uint8_t uvs[3][4] = {{255, 0}, {51, 255}, {0, 102}};   // UNSIGNED_BYTE VEC2, stride 4
    const int8_t normals[3][4] = {{0, 0, 127}, {0, -128, 0}, {127, 0, 0}};   // BYTE VEC3, stride 4
    const int16_t tangents[3][4] = {{32767, 0, 0, -32767}, {0, 32767, 0, 32767}, {0, 0, -32768, 32767}};
    auto& attributes = file.gltf["meshes"][0]["primitives"][0]["attributes"];
    attributes["TEXCOORD_0"] = file.addAccessor(uvs, sizeof(uvs), {{"componentType", 5121}, {"normalized", true}, {"count", 3}, {"type", "VEC2"}}, 4);
    attributes["NORMAL"] = file.addAccessor(normals, sizeof(normals), {{"componentType", 5120}, {"normalized", true}, {"count", 3}, {"type", "VEC3"}}, 4);
    attributes["TANGENT"] = file.addAccessor(tangents, sizeof(tangents), {{"componentType", 5122}, {"normalized", true}, {"count", 3}, {"type", "VEC4"}});
    const Scene scene = loadScene(file.write());
    const std::vector<Vertex>& v = scene.meshes.at(0).vertices;
    EXPECT_EQ(v[0].uv, glm::vec2(1.0f, 0.0f));
    EXPECT_FLOAT_EQ(v[1].uv.x, 0.2f);
    EXPECT_FLOAT_EQ(v[2].uv.y, 0.4f);
    EXPECT_EQ(v[0].normal, glm::vec3(0, 0, 1));
    EXPECT_EQ(v[1].normal, glm::vec3(0, -1, 0));   // -128 / 127 clamps to -1
    EXPECT_EQ(v[0].tangent, glm::vec4(1, 0, 0, -1));
    EXPECT_EQ(v[2].tangent, glm::vec4(0, 0, -1, 1));
}

TEST(GltfAttributes, QuantizedPositionsAndTexcoordsKeepTheirIntegerValues) {
    TinyGltf file;
    file.gltf["extensionsUsed"] = {"KHR_mesh_quantization"};
    file.gltf["extensionsRequired"] = {"KHR_mesh_quantization"};
    const int16_t positions[3][4] = {{0, 0, 0}, {100, 0, 0}, {0, -100, 0}};   // SHORT VEC3, stride 8
    const uint16_t uvs[3][2] = {{3, 0}, {0, 65535}, {1, 1}};                  // UNSIGNED_SHORT VEC2
    auto& attributes = file.gltf["meshes"][0]["primitives"][0]["attributes"];
    attributes["POSITION"] = file.addAccessor(positions, sizeof(positions), {{"componentType", 5122}, {"count", 3}, {"type", "VEC3"}}, 8);
    attributes["TEXCOORD_0"] = file.addAccessor(uvs, sizeof(uvs), {{"componentType", 5123}, {"count", 3}, {"type", "VEC2"}});
    file.gltf["nodes"][0]["scale"] = {0.01, 0.01, 0.01};   // how quantized files dequantize
    const Scene scene = loadScene(file.write());
    const std::vector<Vertex>& v = scene.meshes.at(0).vertices;
    EXPECT_EQ(v[1].position, glm::vec3(100, 0, 0));
    EXPECT_EQ(v[2].position, glm::vec3(0, -100, 0));
    EXPECT_EQ(v[0].uv, glm::vec2(3, 0));
    EXPECT_EQ(v[1].uv, glm::vec2(0, 65535));
}

TEST(GltfAttributes, ComponentTypesGltfDoesNotAllowAreRefusedByName) {
    struct Case {
        const char* attribute;
        json accessor;
        std::string expected;
    };
    const uint8_t bytes[3][4] = {};
    const Case cases[] = {
        {"NORMAL", {{"componentType", 5121}, {"normalized", true}, {"type", "VEC3"}}, "NORMAL accessor 2 is normalized UNSIGNED_BYTE"},
        {"NORMAL", {{"componentType", 5120}, {"type", "VEC3"}}, "NORMAL accessor 2 is BYTE"},
        {"TANGENT", {{"componentType", 5122}, {"type", "VEC4"}}, "TANGENT accessor 2 is SHORT"},
        {"TEXCOORD_0", {{"componentType", 5125}, {"type", "VEC2"}}, "TEXCOORD_0 accessor 2 is UNSIGNED_INT"},
        {"POSITION", {{"componentType", 5126}, {"normalized", true}, {"type", "VEC3"}}, "POSITION accessor 2 is normalized FLOAT"},
    };
    for (const Case& c : cases) {
        TinyGltf file;
        json accessor = c.accessor;
        accessor["count"] = 1;
        file.gltf["meshes"][0]["primitives"][0]["attributes"][c.attribute] = file.addAccessor(bytes, sizeof(bytes), accessor, 16);
        if (std::string(c.attribute) == "POSITION") file.gltf["meshes"][0]["primitives"][0].erase("indices");
        const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
        EXPECT_TRUE(contains(message, c.expected + ", which glTF does not allow here")) << message;
    }
}

// --- KHR_lights_punctual range -----------------------------------------------------------------

// docs/SCENES.md: a light range <= 0 lights nothing (the renderer skips it with a warning). A
// glTF light that gives one keeps it; one without a range is infinite.
TEST(GltfLights, RangeZeroOrNegativeIsKeptAndNoRangeIsInfinite) {
    TinyGltf file;
    file.gltf["extensionsUsed"] = {"KHR_lights_punctual"};
    file.gltf["extensions"] = {{"KHR_lights_punctual",
                                {{"lights", json::array({{{"type", "point"}, {"intensity", 5}, {"range", 0}},
                                                         {{"type", "point"}, {"intensity", 5}, {"range", -2.5}},
                                                         {{"type", "point"}, {"intensity", 5}}})}}}};
    for (int i = 0; i < 3; ++i)
        file.gltf["nodes"].push_back({{"name", fmt::format("lamp {}", i)}, {"extensions", {{"KHR_lights_punctual", {{"light", i}}}}}});
    file.gltf["scenes"][0]["nodes"] = {0, 1, 2, 3};
    const Scene scene = loadScene(file.write());
    ASSERT_EQ(scene.lights.size(), 3u);
    ASSERT_TRUE(scene.lights[0].range.has_value());
    EXPECT_EQ(*scene.lights[0].range, 0.0f);
    ASSERT_TRUE(scene.lights[1].range.has_value());
    EXPECT_EQ(*scene.lights[1].range, -2.5f);
    EXPECT_FALSE(scene.lights[2].range.has_value());
}

}  // namespace
}  // namespace janus::renderer
