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

}  // namespace
}  // namespace janus::renderer
