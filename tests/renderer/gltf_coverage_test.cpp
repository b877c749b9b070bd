// glTF features beyond the core triangle list (issue 13), at the loader: primitive modes, sparse
// accessors, vertex colours and the material extensions Janus reads. Rendering them is checked
// in gltf_coverage_render_test.cpp.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "gltf_test_file.h"
#include "janus/renderer/scene.h"

namespace janus::renderer {
namespace {

using nlohmann::json;
using test_support::sceneErrorOf;
using test_support::TinyGltf;

// A file whose one primitive has `positions` and the uint16 `indices` in glTF mode `mode`.
Scene loadWithMode(int mode, const std::vector<float>& positions, const std::vector<uint16_t>& indices) {
    TinyGltf file;
    const int position = file.addAccessor(positions.data(), positions.size() * 4,
                                          {{"componentType", 5126}, {"count", positions.size() / 3}, {"type", "VEC3"}});
    const int index = file.addAccessor(indices.data(), indices.size() * 2, {{"componentType", 5123}, {"count", indices.size()}, {"type", "SCALAR"}});
    json& primitive = file.gltf["meshes"][0]["primitives"][0];
    primitive["attributes"]["POSITION"] = position;
    primitive["indices"] = index;
    primitive["mode"] = mode;
    return loadScene(file.write());
}

const std::vector<float> kFivePositions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0};

TEST(GltfPrimitiveModes, TriangleStripBecomesAListKeepingTheWinding) {
    const Scene scene = loadWithMode(5, kFivePositions, {0, 1, 2, 3, 4});
    const Mesh& mesh = scene.meshes.at(0);
    EXPECT_EQ(mesh.topology, MeshTopology::Triangles);
    // glTF: triangle i = (v_i, v_{i+1+i%2}, v_{i+2-i%2}): every triangle counter-clockwise like the first.
    EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2, 2, 3, 4}));
    for (size_t t = 0; t < mesh.indices.size(); t += 3) {
        const glm::vec3 a = mesh.vertices[mesh.indices[t]].position, b = mesh.vertices[mesh.indices[t + 1]].position,
                        c = mesh.vertices[mesh.indices[t + 2]].position;
        EXPECT_GT(glm::cross(b - a, c - a).z, 0.0f) << "triangle " << t / 3 << " turned clockwise";
    }
    // Generated normals face the triangles' front (+z), as for a list.
    EXPECT_GT(mesh.vertices[0].normal.z, 0.9f);
}

TEST(GltfPrimitiveModes, TriangleFanBecomesAList) {
    const Scene scene = loadWithMode(6, kFivePositions, {0, 1, 3, 4});
    EXPECT_EQ(scene.meshes.at(0).indices, (std::vector<uint32_t>{1, 3, 0, 3, 4, 0}));
    EXPECT_EQ(scene.meshes.at(0).topology, MeshTopology::Triangles);
}

TEST(GltfPrimitiveModes, LineStripsAndLoopsBecomeLineLists) {
    const Scene strip = loadWithMode(3, kFivePositions, {0, 1, 2, 3});
    EXPECT_EQ(strip.meshes.at(0).topology, MeshTopology::Lines);
    EXPECT_EQ(strip.meshes.at(0).indices, (std::vector<uint32_t>{0, 1, 1, 2, 2, 3}));
    const Scene loop = loadWithMode(2, kFivePositions, {0, 1, 2, 3});
    EXPECT_EQ(loop.meshes.at(0).indices, (std::vector<uint32_t>{0, 1, 1, 2, 2, 3, 3, 0}));
    const Scene lines = loadWithMode(1, kFivePositions, {0, 1, 2, 3});
    EXPECT_EQ(lines.meshes.at(0).indices, (std::vector<uint32_t>{0, 1, 2, 3}));
    // No normals to shade with: drawn unlit, and no normals are made up.
    EXPECT_TRUE(lines.meshes.at(0).unlit);
    EXPECT_EQ(lines.meshes.at(0).vertices[0].normal, glm::vec3(0.0f));
}

TEST(GltfPrimitiveModes, PointsKeepTheirIndices) {
    const Scene scene = loadWithMode(0, kFivePositions, {4, 0, 2});
    EXPECT_EQ(scene.meshes.at(0).topology, MeshTopology::Points);
    EXPECT_EQ(scene.meshes.at(0).indices, (std::vector<uint32_t>{4, 0, 2}));
    EXPECT_TRUE(scene.meshes.at(0).unlit);
}

TEST(GltfPrimitiveModes, BadCountsAndUnknownModesAreErrors) {
    std::string message = sceneErrorOf([] { loadWithMode(1, kFivePositions, {0, 1, 2}); });
    EXPECT_NE(message.find("3 indices, which is not a whole number of lines"), std::string::npos) << message;
    message = sceneErrorOf([] { loadWithMode(4, kFivePositions, {0, 1, 2, 3}); });
    EXPECT_NE(message.find("not a whole number of triangles"), std::string::npos) << message;
    message = sceneErrorOf([] { loadWithMode(7, kFivePositions, {0, 1, 2}); });
    EXPECT_NE(message.find("has mode 7; glTF primitive modes are 0 (POINTS) to 6 (TRIANGLE_FAN)"), std::string::npos) << message;
    EXPECT_NE(message.find("mesh 'triangle' primitive 0"), std::string::npos) << message;
}

// --- sparse accessors ---------------------------------------------------------------------------

// The tiny triangle with its POSITION accessor made sparse: `indices` (uint16) replace those
// positions with `values`. `withBase` false: the accessor has no buffer view (zeros).
struct SparseFile {
    TinyGltf file;
    SparseFile(const std::vector<uint16_t>& indices, const std::vector<float>& values, bool withBase = true) {
        const int indexAccessor = file.addAccessor(indices.data(), indices.size() * 2, {{"componentType", 5123}, {"count", 1}, {"type", "SCALAR"}});
        const int valueAccessor = file.addAccessor(values.data(), values.size() * 4, {{"componentType", 5126}, {"count", 1}, {"type", "VEC3"}});
        json& position = file.gltf["accessors"][0];
        position["sparse"] = {{"count", indices.size()},
                              {"indices", {{"bufferView", file.gltf["accessors"][size_t(indexAccessor)]["bufferView"]}, {"componentType", 5123}}},
                              {"values", {{"bufferView", file.gltf["accessors"][size_t(valueAccessor)]["bufferView"]}}}};
        if (!withBase) position.erase("bufferView");
    }
};

TEST(GltfSparseAccessors, SubstitutionsReplaceTheBaseValues) {
    SparseFile sparse({0, 2}, {5, 6, 7, 8, 9, 10});
    const Scene scene = loadScene(sparse.file.write());
    const std::vector<Vertex>& v = scene.meshes.at(0).vertices;
    ASSERT_EQ(v.size(), 3u);
    EXPECT_EQ(v[0].position, glm::vec3(5, 6, 7));
    EXPECT_EQ(v[1].position, glm::vec3(1, 0, 0)) << "an element without a substitution keeps its base value";
    EXPECT_EQ(v[2].position, glm::vec3(8, 9, 10));
}

TEST(GltfSparseAccessors, WithoutABufferViewTheBaseIsZeros) {
    SparseFile sparse({1}, {3, 4, 5}, false);
    const Scene scene = loadScene(sparse.file.write());
    const std::vector<Vertex>& v = scene.meshes.at(0).vertices;
    EXPECT_EQ(v[0].position, glm::vec3(0.0f));
    EXPECT_EQ(v[1].position, glm::vec3(3, 4, 5));
    EXPECT_EQ(v[2].position, glm::vec3(0.0f));
}

TEST(GltfSparseAccessors, BadIndicesAreClearErrors) {
    {
        SparseFile sparse({0, 3}, {1, 1, 1, 2, 2, 2});
        const std::string message = sceneErrorOf([&] { loadScene(sparse.file.write()); });
        EXPECT_NE(message.find("sparse index 3 (entry 1), outside the accessor's 3 elements"), std::string::npos) << message;
    }
    {
        SparseFile sparse({2, 1}, {1, 1, 1, 2, 2, 2});
        const std::string message = sceneErrorOf([&] { loadScene(sparse.file.write()); });
        EXPECT_NE(message.find("not strictly increasing (1 after 2"), std::string::npos) << message;
    }
    {
        SparseFile sparse({1, 1}, {1, 1, 1, 2, 2, 2});
        const std::string message = sceneErrorOf([&] { loadScene(sparse.file.write()); });
        EXPECT_NE(message.find("not strictly increasing"), std::string::npos) << message;
    }
    {
        SparseFile sparse({0, 1}, {1, 1, 1, 2, 2, 2});
        sparse.file.gltf["accessors"][0]["sparse"]["count"] = 4;   // more than the accessor's 3
        const std::string message = sceneErrorOf([&] { loadScene(sparse.file.write()); });
        EXPECT_NE(message.find("sparse with count 4; it must be in [1, 3]"), std::string::npos) << message;
    }
    {
        SparseFile sparse({0, 1}, {1, 1, 1});   // values for one substitution, two announced
        const std::string message = sceneErrorOf([&] { loadScene(sparse.file.write()); });
        EXPECT_NE(message.find("sparse values reads past the end of its buffer"), std::string::npos) << message;
    }
    {
        SparseFile sparse({0, 1}, {1, 1, 1, 2, 2, 2});
        sparse.file.gltf["accessors"][0]["sparse"]["indices"]["componentType"] = 5126;   // FLOAT
        const std::string message = sceneErrorOf([&] { loadScene(sparse.file.write()); });
        EXPECT_NE(message.find("sparse indices of component type FLOAT"), std::string::npos) << message;
    }
}

// --- vertex colours -----------------------------------------------------------------------------

TEST(GltfVertexColors, Vec3FloatAndNormalizedIntegersAreRead) {
    {
        TinyGltf file;
        const float colors[9] = {1, 0, 0, 0, 0.5f, 0, 0, 0, 0.25f};
        file.gltf["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] =
            file.addAccessor(colors, sizeof(colors), {{"componentType", 5126}, {"count", 3}, {"type", "VEC3"}});
        const Scene scene = loadScene(file.write());
        EXPECT_EQ(scene.meshes[0].vertices[1].color, glm::vec4(0, 0.5f, 0, 1)) << "VEC3 colours are opaque";
    }
    {
        TinyGltf file;
        const uint8_t colors[12] = {255, 0, 0, 255, 0, 51, 0, 102, 0, 0, 255, 0};
        file.gltf["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = file.addAccessor(
            colors, sizeof(colors), {{"componentType", 5121}, {"normalized", true}, {"count", 3}, {"type", "VEC4"}});
        const Scene scene = loadScene(file.write());
        EXPECT_EQ(scene.meshes[0].vertices[1].color, glm::vec4(0, 0.2f, 0, 0.4f));
        EXPECT_EQ(scene.meshes[0].vertices[2].color.a, 0.0f);
    }
    {
        TinyGltf file;
        const uint16_t colors[12] = {65535, 0, 0, 65535, 0, 65535, 0, 65535, 0, 0, 13107, 65535};
        file.gltf["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = file.addAccessor(
            colors, sizeof(colors), {{"componentType", 5123}, {"normalized", true}, {"count", 3}, {"type", "VEC4"}});
        const Scene scene = loadScene(file.write());
        EXPECT_EQ(scene.meshes[0].vertices[2].color, glm::vec4(0, 0, 0.2f, 1));
    }
    TinyGltf plain;
    EXPECT_EQ(loadScene(plain.write()).meshes[0].vertices[0].color, glm::vec4(1.0f)) << "without COLOR_0 vertices are white";
}

TEST(GltfVertexColors, WrongTypesAreClearErrors) {
    {
        TinyGltf file;
        const uint8_t colors[12] = {};
        file.gltf["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] =
            file.addAccessor(colors, sizeof(colors), {{"componentType", 5121}, {"count", 3}, {"type", "VEC4"}});   // not normalized
        const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
        EXPECT_NE(message.find("COLOR_0 accessor"), std::string::npos) << message;
        EXPECT_NE(message.find("FLOAT, or normalized UNSIGNED_BYTE or UNSIGNED_SHORT"), std::string::npos) << message;
    }
    {
        TinyGltf file;
        const float colors[6] = {};
        file.gltf["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] =
            file.addAccessor(colors, sizeof(colors), {{"componentType", 5126}, {"count", 3}, {"type", "VEC2"}});
        const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
        EXPECT_NE(message.find("glTF vertex colours are VEC3 or VEC4"), std::string::npos) << message;
    }
    {
        TinyGltf file;
        const float colors[9] = {1, 1, 1, -0.5f, 1, 1, 1, 1, 1};
        file.gltf["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] =
            file.addAccessor(colors, sizeof(colors), {{"componentType", 5126}, {"count", 3}, {"type", "VEC3"}});
        const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
        EXPECT_NE(message.find("vertex colour (-0.5, 1, 1, 1) outside [0, 65504]"), std::string::npos) << message;
    }
}

// --- material extensions ------------------------------------------------------------------------

TEST(GltfMaterialExtensions, AreReadIntoTheMaterial) {
    TinyGltf file;
    file.gltf["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_materials_unlit", "KHR_materials_ior", "KHR_materials_specular"};
    json& extensions = file.gltf["materials"][0]["extensions"];
    extensions["KHR_materials_emissive_strength"] = {{"emissiveStrength", 7.5}};
    extensions["KHR_materials_unlit"] = json::object();
    extensions["KHR_materials_ior"] = {{"ior", 2.0}};
    extensions["KHR_materials_specular"] = {{"specularFactor", 0.5}, {"specularColorFactor", {1.0, 0.5, 2.0}}};
    const Scene scene = loadScene(file.write());
    const Material& material = scene.materials.at(0);
    EXPECT_EQ(material.emissiveStrength, 7.5f);
    EXPECT_TRUE(material.unlit);
    EXPECT_EQ(material.ior, 2.0f);
    EXPECT_EQ(material.specularFactor, 0.5f);
    EXPECT_EQ(material.specularColorFactor, glm::vec3(1.0f, 0.5f, 2.0f));
    // F0 = ((2 - 1) / (2 + 1))^2 = 1/9, times the colour, times the factor; F90 = the factor.
    EXPECT_NEAR(material.dielectricF0().r, 0.5 / 9.0, 1e-7);
    EXPECT_NEAR(material.dielectricF0().g, 0.25 / 9.0, 1e-7);
    EXPECT_NEAR(material.dielectricF0().b, 1.0 / 9.0, 1e-7);
    EXPECT_EQ(material.dielectricF90(), 0.5f);
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
}

TEST(GltfMaterialExtensions, DefaultsGiveTheCoreModelsF0) {
    const Material material;
    EXPECT_EQ(material.dielectricF0(), glm::vec3(0.04f)) << "ior 1.5 must give exactly the float 0.04 the shaders used before";
    EXPECT_EQ(material.dielectricF90(), 1.0f);
    Material infinite;
    infinite.ior = 0.0f;   // KHR_materials_ior: 0 is the limit of an infinite index, F0 = 1
    EXPECT_EQ(infinite.dielectricF0(), glm::vec3(1.0f));
}

TEST(GltfMaterialExtensions, BadValuesAreClearErrors) {
    auto messageFor = [](const char* extension, json value) {
        TinyGltf file;
        file.gltf["materials"][0]["extensions"][extension] = value;
        return sceneErrorOf([&] { loadScene(file.write()); });
    };
    std::string message = messageFor("KHR_materials_emissive_strength", {{"emissiveStrength", -1}});
    EXPECT_NE(message.find("material 'plain' has emissive strength -1"), std::string::npos) << message;
    message = messageFor("KHR_materials_ior", {{"ior", 0.5}});
    EXPECT_NE(message.find("has ior 0.5; it must be 0 or a finite value >= 1"), std::string::npos) << message;
    message = messageFor("KHR_materials_specular", {{"specularFactor", 1.5}});
    EXPECT_NE(message.find("specularFactor 1.5 outside [0, 1]"), std::string::npos) << message;
    message = messageFor("KHR_materials_specular", {{"specularColorFactor", {1, 1}}});
    EXPECT_NE(message.find("specularColorFactor must be an array of three numbers"), std::string::npos) << message;
    message = messageFor("KHR_materials_ior", {{"ior", "glass"}});
    EXPECT_NE(message.find("KHR_materials_ior ior is not a finite number"), std::string::npos) << message;
}

TEST(GltfMaterialExtensions, IgnoredPartsAreWarnedAboutOncePerFile) {
    TinyGltf file;
    file.gltf["extensionsUsed"] = {"KHR_materials_specular", "KHR_materials_clearcoat"};
    file.gltf["materials"][0]["extensions"]["KHR_materials_specular"] = {{"specularTexture", {{"index", 0}}}};
    file.gltf["materials"][0]["extensions"]["KHR_materials_clearcoat"] = {{"clearcoatFactor", 1}};
    file.gltf["materials"].push_back(file.gltf["materials"][0]);   // a second material: the extension is still named once
    testing::internal::CaptureStderr();
    const Scene scene = loadScene(file.write());
    const std::string err = testing::internal::GetCapturedStderr();
    ASSERT_EQ(scene.warnings.size(), 2u) << err;
    EXPECT_NE(scene.warnings[0].find("ignoring glTF extension 'KHR_materials_clearcoat'"), std::string::npos) << scene.warnings[0];
    EXPECT_NE(scene.warnings[1].find("material 'plain': ignoring KHR_materials_specular specularTexture"), std::string::npos)
        << scene.warnings[1];
    for (const std::string& warning : scene.warnings)
        EXPECT_NE(err.find("janus: warning: " + warning), std::string::npos) << "not printed: " << warning << "\n" << err;
}

// --- scenes and cameras -------------------------------------------------------------------------

// Two scenes: scene 0 holds the triangle and an orthographic camera (camera 0), scene 1 the
// triangle moved to x = 5 and two perspective cameras (1 at z = 3, 2 at z = 7).
TinyGltf twoScenesFile() {
    TinyGltf file;
    file.gltf["nodes"] = json::array({{{"name", "triangle node"}, {"mesh", 0}},
                                      {{"name", "ortho"}, {"camera", 0}, {"translation", {0, 0, 2}}},
                                      {{"name", "moved"}, {"mesh", 0}, {"translation", {5, 0, 0}}},
                                      {{"name", "near"}, {"camera", 1}, {"translation", {0, 0, 3}}},
                                      {{"name", "far"}, {"camera", 2}, {"translation", {0, 0, 7}}}});
    file.gltf["scenes"] = json::array({{{"nodes", {0, 1}}}, {{"nodes", {2, 3, 4}}}});
    file.gltf["scene"] = 0;
    const json perspective = {{"yfov", 0.5}, {"znear", 0.1}, {"zfar", 50}};
    file.gltf["cameras"] = json::array({{{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}},
                                        {{"type", "perspective"}, {"name", "near camera"}, {"perspective", perspective}},
                                        {{"type", "perspective"}, {"name", "far camera"}, {"perspective", perspective}}});
    return file;
}

TEST(GltfScenesAndCameras, TheSceneAndCameraCanBeChosen) {
    TinyGltf file = twoScenesFile();
    const std::filesystem::path path = file.write();
    const Scene byDefault = loadScene(path);
    ASSERT_EQ(byDefault.instances.size(), 1u);
    EXPECT_EQ(byDefault.instances[0].nodeName, "triangle node");
    // The first camera met in scene 0 is the orthographic one: ymag, znear and zfar as given.
    EXPECT_EQ(byDefault.camera.projection, CameraProjection::Orthographic);
    EXPECT_EQ(byDefault.camera.orthographicHalfHeight, 1.0f);
    EXPECT_EQ(byDefault.camera.nearPlane, 0.1f);
    EXPECT_EQ(byDefault.camera.farPlane, 10.0f);
    EXPECT_EQ(byDefault.camera.position, glm::vec3(0, 0, 2));
    EXPECT_EQ(byDefault.camera.node, 1);
    SceneLoadOptions options;
    options.scene = 1;
    const Scene second = loadScene(path, options);
    ASSERT_EQ(second.instances.size(), 1u);
    EXPECT_EQ(second.instances[0].nodeName, "moved");
    EXPECT_EQ(second.camera.position, glm::vec3(0, 0, 3)) << "the first camera of scene 1";
    EXPECT_EQ(second.camera.projection, CameraProjection::Perspective);
    EXPECT_EQ(second.camera.fovYRadians, 0.5f);
    options.camera = 2;
    EXPECT_EQ(loadScene(path, options).camera.position, glm::vec3(0, 0, 7));
    options = {};
    options.camera = 0;
    EXPECT_EQ(loadScene(path, options).camera.projection, CameraProjection::Orthographic);
}

// glTF: xmag and ymag must not be 0 (negative ones would mirror the view: refused too), zfar is
// required and > znear >= 0.
TEST(GltfScenesAndCameras, BadOrthographicCamerasAreClearErrors) {
    struct Case {
        json orthographic;
        const char* message;
    };
    const Case cases[] = {
        {{{"xmag", 1}, {"ymag", 0}, {"znear", 0.1}, {"zfar", 10}}, "camera 0 ('') is orthographic with xmag 1 and ymag 0; both must be finite and > 0"},
        {{{"xmag", -1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}, "with xmag -1 and ymag 1; both must be finite and > 0"},
        {{{"xmag", 1}, {"ymag", 1}, {"znear", 2}, {"zfar", 2}}, "with znear 2 and zfar 2; it needs 0 <= znear < zfar"},
        {{{"xmag", 1}, {"ymag", 1}, {"znear", -1}, {"zfar", 2}}, "with znear -1 and zfar 2; it needs 0 <= znear < zfar"},
    };
    for (const Case& c : cases) {
        TinyGltf file = twoScenesFile();
        file.gltf["cameras"][0]["orthographic"] = c.orthographic;
        const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
        EXPECT_NE(message.find(c.message), std::string::npos) << c.orthographic.dump() << ": " << message;
    }
    // znear 0 is allowed for orthographic cameras (not for perspective ones).
    TinyGltf file = twoScenesFile();
    file.gltf["cameras"][0]["orthographic"]["znear"] = 0;
    EXPECT_EQ(loadScene(file.write()).camera.nearPlane, 0.0f);
}

TEST(GltfScenesAndCameras, BadChoicesAreClearErrors) {
    TinyGltf file = twoScenesFile();
    const std::filesystem::path path = file.write();
    SceneLoadOptions options;
    options.scene = 2;
    std::string message = sceneErrorOf([&] { loadScene(path, options); });
    EXPECT_NE(message.find("scene 2 does not exist: the file has 2 scene(s) (0 to 1)"), std::string::npos) << message;
    options = {};
    options.camera = 1;   // in scene 1 only
    message = sceneErrorOf([&] { loadScene(path, options); });
    EXPECT_NE(message.find("camera 1 ('near camera') is used by no node of the loaded scene"), std::string::npos) << message;
    options.camera = 9;
    message = sceneErrorOf([&] { loadScene(path, options); });
    EXPECT_NE(message.find("camera 9 does not exist: the file has 3 camera(s)"), std::string::npos) << message;
}

}  // namespace
}  // namespace janus::renderer
