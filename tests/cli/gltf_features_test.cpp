// What `janus check` says a glTF uses (apps/janus/gltf_features.cpp): every row of the feature
// table on a crafted JSON, its absence on a minimal file, .glb input, malformed input never
// throwing, and the Khronos sample models in ../shared/scenes/khronos.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gltf_features.h"

namespace janus::cli {
namespace {

using nlohmann::json;

json minimalGltf() {
    return {{"asset", {{"version", "2.0"}}},
            {"scenes", json::array({{{"nodes", {0}}}})},
            {"nodes", json::array({{{"mesh", 0}}})},
            {"meshes", json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", 0}}}}})}}})},
            {"accessors", json::array({{{"componentType", 5126}, {"count", 3}, {"type", "VEC3"}}})}};
}

bool uses(const GltfUsage& usage, std::string_view feature) {
    return std::find(usage.features.begin(), usage.features.end(), feature) != usage.features.end();
}

TEST(GltfFeatures, MinimalFileUsesNothing) {
    const GltfUsage usage = scanGltfUsage(minimalGltf().dump());
    EXPECT_TRUE(usage.error.empty()) << usage.error;
    EXPECT_TRUE(usage.features.empty()) << usage.features.front();
    EXPECT_TRUE(usage.extensionsUsed.empty());
    EXPECT_TRUE(usage.extensionsRequired.empty());
}

// Each feature of the table, added alone to the minimal file, is found, and nothing else is.
TEST(GltfFeatures, EveryTableRowIsDetectedAlone) {
    struct Case {
        std::string feature;
        void (*edit)(json& gltf);
    };
    const std::vector<Case> cases = {
        {"multiple-scenes", [](json& g) { g["scenes"].push_back({{"nodes", json::array()}}); }},
        {"perspective-camera", [](json& g) { g["cameras"] = json::array({{{"type", "perspective"}}}); }},
        {"orthographic-camera", [](json& g) { g["cameras"] = json::array({{{"type", "orthographic"}}}); }},
        {"skins", [](json& g) { g["skins"] = json::array({{{"joints", {0}}}}); }},
        {"animations", [](json& g) { g["animations"] = json::array({{{"channels", json::array()}, {"samplers", json::array()}}}); }},
        {"morph-targets", [](json& g) { g["meshes"][0]["primitives"][0]["targets"] = json::array({{{"POSITION", 0}}}); }},
        {"sparse-accessors", [](json& g) { g["accessors"][0]["sparse"] = {{"count", 1}}; }},
        {"points", [](json& g) { g["meshes"][0]["primitives"][0]["mode"] = 0; }},
        {"lines", [](json& g) { g["meshes"][0]["primitives"][0]["mode"] = 1; }},
        {"line-loop", [](json& g) { g["meshes"][0]["primitives"][0]["mode"] = 2; }},
        {"line-strip", [](json& g) { g["meshes"][0]["primitives"][0]["mode"] = 3; }},
        {"triangle-strip", [](json& g) { g["meshes"][0]["primitives"][0]["mode"] = 5; }},
        {"triangle-fan", [](json& g) { g["meshes"][0]["primitives"][0]["mode"] = 6; }},
        {"COLOR_0", [](json& g) { g["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = 0; }},
        {"TEXCOORD_1", [](json& g) { g["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] = 0; }},
        {"TEXCOORD_2+", [](json& g) { g["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_3"] = 0; }},
        {"TANGENT", [](json& g) { g["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = 0; }},
        {"JOINTS_1", [](json& g) { g["meshes"][0]["primitives"][0]["attributes"]["JOINTS_1"] = 0; }},
        {"textures", [](json& g) { g["textures"] = json::array({{{"source", 0}}}); }},
        {"alpha-mask", [](json& g) { g["materials"] = json::array({{{"alphaMode", "MASK"}}}); }},
        {"alpha-blend", [](json& g) { g["materials"] = json::array({{{"alphaMode", "BLEND"}}}); }},
        {"double-sided", [](json& g) { g["materials"] = json::array({{{"doubleSided", true}}}); }},
        {"byte-stride", [](json& g) { g["bufferViews"] = json::array({{{"buffer", 0}, {"byteLength", 12}, {"byteStride", 12}}}); }},
    };
    std::set<std::string> covered;
    for (const Case& c : cases) {
        json gltf = minimalGltf();
        c.edit(gltf);
        const GltfUsage usage = scanGltfUsage(gltf.dump());
        EXPECT_EQ(usage.features, std::vector<std::string>{c.feature}) << c.feature;
        covered.insert(c.feature);
    }
    // A new table row needs a case here.
    for (const GltfFeature& feature : gltfFeatures()) EXPECT_TRUE(covered.count(std::string(feature.name))) << feature.name;
}

TEST(GltfFeatures, NotUsedWhenOnlyDefaultsAreSpelledOut) {
    json gltf = minimalGltf();
    gltf["meshes"][0]["primitives"][0]["mode"] = 4;   // TRIANGLES
    gltf["materials"] = json::array({{{"alphaMode", "OPAQUE"}, {"doubleSided", false}}});
    gltf["skins"] = json::array();
    gltf["animations"] = json::array();
    gltf["meshes"][0]["primitives"][0]["targets"] = json::array();
    gltf["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 0;
    EXPECT_TRUE(scanGltfUsage(gltf.dump()).features.empty());
}

TEST(GltfFeatures, ExtensionsAsListed) {
    json gltf = minimalGltf();
    gltf["extensionsUsed"] = {"KHR_texture_transform", "KHR_materials_unlit", 7};
    gltf["extensionsRequired"] = {"KHR_materials_unlit"};
    const GltfUsage usage = scanGltfUsage(gltf.dump());
    EXPECT_EQ(usage.extensionsUsed, (std::vector<std::string>{"KHR_texture_transform", "KHR_materials_unlit"}));
    EXPECT_EQ(usage.extensionsRequired, std::vector<std::string>{"KHR_materials_unlit"});
}

std::string glb(const std::string& jsonText, uint32_t chunkType = 0x4E4F534Au) {
    std::string text = jsonText;
    while (text.size() % 4) text += ' ';
    std::string out = "glTF";
    auto u32 = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    u32(2);
    u32(uint32_t(12 + 8 + text.size()));
    u32(uint32_t(text.size()));
    u32(chunkType);
    return out + text;
}

TEST(GltfFeatures, ReadsTheJsonChunkOfAGlb) {
    json gltf = minimalGltf();
    gltf["skins"] = json::array({{{"joints", {0}}}});
    gltf["extensionsUsed"] = {"KHR_materials_emissive_strength"};
    const GltfUsage usage = scanGltfUsage(glb(gltf.dump()));
    EXPECT_TRUE(usage.error.empty()) << usage.error;
    EXPECT_EQ(usage.features, std::vector<std::string>{"skins"});
    EXPECT_EQ(usage.extensionsUsed, std::vector<std::string>{"KHR_materials_emissive_strength"});

    // From a file too, whatever its name.
    const std::filesystem::path path = std::filesystem::temp_directory_path() / "janus-gltf-features-test.gltf";
    std::ofstream(path, std::ios::binary) << glb(gltf.dump()) << std::string(100, '\0');   // a binary chunk's worth of junk after it
    EXPECT_EQ(scanGltfFile(path).features, std::vector<std::string>{"skins"});
    std::filesystem::remove(path);
}

TEST(GltfFeatures, MalformedInputIsAnErrorNotAnException) {
    for (const std::string& bytes : {std::string(), std::string("{"), std::string("[1, 2]"), std::string("glTF"),
                                     glb("{}", 0x004E4942u), glb("{}").substr(0, 22), glb("{not json")}) {
        const GltfUsage usage = scanGltfUsage(bytes);
        EXPECT_FALSE(usage.error.empty()) << bytes;
        EXPECT_TRUE(usage.features.empty());
    }
    // Wrong shapes everywhere read as "not used".
    const json odd = {{"meshes", 5},        {"scenes", "x"},   {"accessors", {1, 2}}, {"materials", json::array({7})},
                      {"cameras", {{"a", 1}}}, {"extensionsUsed", "KHR_x"}};
    const GltfUsage usage = scanGltfUsage(odd.dump());
    EXPECT_TRUE(usage.error.empty()) << usage.error;
    EXPECT_TRUE(usage.features.empty());
    EXPECT_FALSE(scanGltfFile("/no/such/file.gltf").error.empty());
}

#ifdef JANUS_SHARED_SCENES_DIR
// What the Khronos sample models (../shared/scenes/khronos/README.md) are known to exercise.
TEST(GltfFeatures, KhronosSampleModels) {
    const std::filesystem::path khronos = std::filesystem::path(JANUS_SHARED_SCENES_DIR) / "khronos";
    if (!std::filesystem::is_directory(khronos)) GTEST_SKIP() << khronos << " is missing (../shared beside the repository)";
    auto scan = [&](const std::string& model) { return scanGltfFile(khronos / model / "glTF" / (model + ".gltf")); };

    EXPECT_TRUE(uses(scan("BoxVertexColors"), "COLOR_0"));
    EXPECT_TRUE(uses(scan("VertexColorTest"), "COLOR_0"));
    const GltfUsage skin = scan("SimpleSkin");
    EXPECT_TRUE(uses(skin, "skins") && uses(skin, "animations"));
    EXPECT_FALSE(uses(skin, "morph-targets"));
    const GltfUsage morph = scan("AnimatedMorphCube");
    EXPECT_TRUE(uses(morph, "morph-targets") && uses(morph, "animations"));
    EXPECT_TRUE(uses(scan("SimpleSparseAccessor"), "sparse-accessors"));
    EXPECT_EQ(scan("MeshPrimitiveModes").features,
              (std::vector<std::string>{"points", "lines", "line-loop", "line-strip", "triangle-strip", "triangle-fan"}));
    EXPECT_TRUE(uses(scan("MultiUVTest"), "TEXCOORD_1"));
    EXPECT_TRUE(uses(scan("BoxInterleaved"), "byte-stride"));
    EXPECT_EQ(scan("TextureTransformTest").extensionsUsed, std::vector<std::string>{"KHR_texture_transform"});
    const GltfUsage unlit = scan("UnlitTest");
    EXPECT_EQ(unlit.extensionsRequired, std::vector<std::string>{"KHR_materials_unlit"});
    EXPECT_TRUE(scan("OrientationTest").extensionsUsed.empty());
}
#endif

}  // namespace
}  // namespace janus::cli
