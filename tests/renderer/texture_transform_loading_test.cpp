// glTF texCoord and KHR_texture_transform in the loader: every material texture keeps its UV set
// and transform, TEXCOORD_1 is read like TEXCOORD_0 (KHR_mesh_quantization types included), and a
// UV set Janus cannot serve is a SceneError that names the material, the texture and the mesh.
// The renderer's side is tests/renderer/texture_transform_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>

#include <glm/gtc/constants.hpp>
#include <nlohmann/json.hpp>

#include "janus/renderer/image.h"
#include "janus/renderer/scene.h"
#include "renderer/gltf_test_file.h"

namespace janus::renderer {
namespace {

using nlohmann::json;
using test_support::sceneErrorOf;
using test_support::TinyGltf;

// The triangle's second UV set: u runs along +Y, v along +X (TEXCOORD_0 of addUvsAndNormalMap has
// u along +X), so which set a texture or the tangents follow shows in the numbers.
int addUv1(TinyGltf& file) {
    const float uvs[6] = {0, 0, 0, 1, 1, 0};
    const int accessor = file.addAccessor(uvs, sizeof(uvs), {{"componentType", 5126}, {"count", 3}, {"type", "VEC2"}});
    file.gltf["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] = accessor;
    return accessor;
}

// A 1x1 texture (image and texture index 1) for the base colour, after addUvsAndNormalMap's normal map.
void addBaseColorTexture(TinyGltf& file, json textureInfo) {
    writePNG(file.dir() / "base.png", ImageRGBA8{1, 1, {200, 100, 50, 255}});
    file.gltf["images"].push_back({{"uri", "base.png"}});
    file.gltf["textures"].push_back({{"source", 1}});
    textureInfo["index"] = 1;
    file.gltf["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = textureInfo;
}

// Scale, then rotation, then offset. A quarter turn takes u = (1, 0) (right on the image) to
// (0, -1) (up on the image, v growing downwards): counter-clockwise as seen, the image turning
// clockwise, as the extension says and its TextureTransformTest model checks.
TEST(TextureTransformMatrix, ScalesThenRotatesCounterClockwiseOnTheImageThenOffsets) {
    TextureTransform transform;
    transform.offset = {0.5f, 0.25f};
    transform.rotation = glm::half_pi<float>();
    transform.scale = {2.0f, 3.0f};
    // (1, 0) -> scale (2, 0) -> turn (0, -2) -> offset (0.5, -1.75).
    const glm::vec2 u = transform.apply({1.0f, 0.0f});
    EXPECT_NEAR(u.x, 0.5f, 1e-6f);
    EXPECT_NEAR(u.y, -1.75f, 1e-6f);
    // (0, 1) -> (0, 3) -> (3, 0) -> (3.5, 0.25).
    const glm::vec2 v = transform.apply({0.0f, 1.0f});
    EXPECT_NEAR(v.x, 3.5f, 1e-6f);
    EXPECT_NEAR(v.y, 0.25f, 1e-6f);
    EXPECT_EQ(TextureTransform{}.apply({0.3f, 0.7f}), glm::vec2(0.3f, 0.7f));
}

TEST(TextureTransformLoading, OffsetRotationScaleAndTexCoordOverrideAreRead) {
    TinyGltf file;
    file.addUvsAndNormalMap();
    addUv1(file);
    addBaseColorTexture(file, {{"texCoord", 0},
                               {"extensions",
                                {{"KHR_texture_transform",
                                  {{"offset", {0.25, -0.5}}, {"rotation", 0.75}, {"scale", {2.0, 3.0}}, {"texCoord", 1}}}}}});
    file.gltf["materials"][0]["normalTexture"]["extensions"] = {{"KHR_texture_transform", {{"offset", {0.125, 0.0}}}}};
    file.gltf["extensionsUsed"] = {"KHR_texture_transform"};
    file.gltf["extensionsRequired"] = {"KHR_texture_transform"};
    testing::internal::CaptureStderr();
    const Scene scene = loadScene(file.write());
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(err.find("KHR_texture_transform"), std::string::npos) << "a supported extension was warned about: " << err;
    const Material& material = scene.materials.at(0);
    EXPECT_EQ(material.baseColorTransform.offset, glm::vec2(0.25f, -0.5f));
    EXPECT_EQ(material.baseColorTransform.rotation, 0.75f);
    EXPECT_EQ(material.baseColorTransform.scale, glm::vec2(2.0f, 3.0f));
    EXPECT_EQ(material.baseColorTransform.texCoord, 1u) << "the extension's texCoord replaces the texture reference's";
    EXPECT_EQ(material.normalTransform.offset, glm::vec2(0.125f, 0.0f));
    EXPECT_EQ(material.normalTransform.rotation, 0.0f);
    EXPECT_EQ(material.normalTransform.scale, glm::vec2(1.0f));
    EXPECT_EQ(material.normalTransform.texCoord, 0u);
    EXPECT_EQ(material.emissiveTransform, TextureTransform{}) << "a texture without the extension keeps the identity";
}

TEST(TextureTransformLoading, TexCoordOneOnTheTextureReferenceIsRead) {
    TinyGltf file;
    file.addUvsAndNormalMap();
    addUv1(file);
    addBaseColorTexture(file, {{"texCoord", 1}});
    const Scene scene = loadScene(file.write());
    EXPECT_EQ(scene.materials.at(0).baseColorTransform.texCoord, 1u);
    EXPECT_EQ(scene.materials.at(0).baseColorTransform.offset, glm::vec2(0.0f));
}

TEST(TextureTransformLoading, Texcoord1IsReadAsFloatAndAsNormalizedIntegers) {
    TinyGltf file;
    addUv1(file);
    const Scene floats = loadScene(file.write());
    const std::vector<Vertex>& v = floats.meshes.at(0).vertices;
    EXPECT_EQ(v.at(0).uv1, glm::vec2(0, 0));
    EXPECT_EQ(v.at(1).uv1, glm::vec2(0, 1));
    EXPECT_EQ(v.at(2).uv1, glm::vec2(1, 0));

    // KHR_mesh_quantization: normalized UNSIGNED_SHORT (c / 65535) and plain UNSIGNED_BYTE, as TEXCOORD_0 may be.
    TinyGltf quantized;
    const uint16_t shorts[6] = {0, 65535, 32768, 0, 65535, 16384};
    quantized.gltf["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] =
        quantized.addAccessor(shorts, sizeof(shorts), {{"componentType", 5123}, {"normalized", true}, {"count", 3}, {"type", "VEC2"}});
    quantized.gltf["extensionsUsed"] = {"KHR_mesh_quantization"};
    quantized.gltf["extensionsRequired"] = {"KHR_mesh_quantization"};
    const Scene normalized = loadScene(quantized.write());
    const std::vector<Vertex>& q = normalized.meshes.at(0).vertices;
    EXPECT_EQ(q.at(0).uv1, glm::vec2(0.0f, 1.0f));
    EXPECT_EQ(q.at(1).uv1, glm::vec2(32768.0f / 65535.0f, 0.0f));
    EXPECT_EQ(q.at(2).uv1, glm::vec2(1.0f, 16384.0f / 65535.0f));

    TinyGltf bytes;
    const uint8_t raw[12] = {3, 4, 0, 0, 5, 6, 0, 0, 7, 8, 0, 0};   // stride 4: vertex attributes are 4-byte aligned
    bytes.gltf["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] =
        bytes.addAccessor(raw, sizeof(raw), {{"componentType", 5121}, {"count", 3}, {"type", "VEC2"}}, 4);
    const Scene unnormalized = loadScene(bytes.write());
    EXPECT_EQ(unnormalized.meshes.at(0).vertices.at(0).uv1, glm::vec2(3.0f, 4.0f));
}

TEST(TextureTransformLoading, TexcoordOneIsRefusedWithTheSameComponentRulesAsTexcoordZero) {
    TinyGltf file;
    const int32_t ints[6] = {0, 0, 0, 1, 1, 0};
    file.gltf["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] =
        file.addAccessor(ints, sizeof(ints), {{"componentType", 5125}, {"count", 3}, {"type", "VEC2"}});
    const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
    EXPECT_NE(message.find("TEXCOORD_1 accessor"), std::string::npos) << message;
    EXPECT_NE(message.find("UNSIGNED_INT"), std::string::npos) << message;
}

TEST(TextureTransformLoading, TangentsAreGeneratedFromTheUvSetOfTheNormalTexture) {
    TinyGltf file;
    file.addUvsAndNormalMap();
    addUv1(file);
    file.gltf["materials"][0]["normalTexture"]["texCoord"] = 1;
    const Scene scene = loadScene(file.write());
    // TEXCOORD_1's u runs along +Y and its v along +X; image up (decreasing v) is -X = cross(+Z, +Y),
    // so w = +1. From TEXCOORD_0 the tangent would be +X.
    for (const Vertex& v : scene.meshes.at(0).vertices) EXPECT_EQ(v.tangent, glm::vec4(0, 1, 0, 1));
}

TEST(TextureTransformErrors, TexCoordTwoNamesTheMaterialAndTheTexture) {
    TinyGltf file;
    file.addUvsAndNormalMap();
    file.gltf["materials"][0]["normalTexture"]["texCoord"] = 2;
    const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
    EXPECT_NE(message.find("material 'plain' normalTexture uses texCoord 2"), std::string::npos) << message;
    EXPECT_NE(message.find("TEXCOORD_0 and TEXCOORD_1 only"), std::string::npos) << message;
}

TEST(TextureTransformErrors, TexCoordTwoFromTheExtensionIsRefusedToo) {
    TinyGltf file;
    file.addUvsAndNormalMap();
    addUv1(file);
    addBaseColorTexture(file, {{"extensions", {{"KHR_texture_transform", {{"texCoord", 2}}}}}});
    const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
    EXPECT_NE(message.find("material 'plain' baseColorTexture uses texCoord 2"), std::string::npos) << message;
}

TEST(TextureTransformErrors, TexCoordOneOnAMeshWithoutTexcoord1NamesMeshMaterialAndTexture) {
    TinyGltf file;
    file.addUvsAndNormalMap();
    addBaseColorTexture(file, {{"texCoord", 1}});
    const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
    EXPECT_NE(message.find("mesh 'triangle' primitive 0"), std::string::npos) << message;
    EXPECT_NE(message.find("material 'plain', whose baseColorTexture reads texCoord 1"), std::string::npos) << message;
    EXPECT_NE(message.find("no TEXCOORD_1"), std::string::npos) << message;
}

TEST(TextureTransformErrors, MalformedTransformNamesTheField) {
    TinyGltf file;
    file.addUvsAndNormalMap();
    file.gltf["materials"][0]["normalTexture"]["extensions"] = {{"KHR_texture_transform", {{"scale", {1.0}}}}};
    const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
    EXPECT_NE(message.find("material 'plain' normalTexture: KHR_texture_transform scale must be an array of two numbers"),
              std::string::npos)
        << message;
}

TEST(TextureTransformErrors, ValidateSceneRefusesTexCoordAboveOneAndNonFiniteTransforms) {
    Scene scene;
    Material material;
    material.name = "built in code";
    material.emissiveTransform.texCoord = 2;
    scene.materials.push_back(material);
    std::string message = sceneErrorOf([&] { validateScene(scene); });
    EXPECT_NE(message.find("'built in code' emissiveTexture uses texCoord 2"), std::string::npos) << message;
    scene.materials[0].emissiveTransform = TextureTransform{};
    scene.materials[0].occlusionTransform.rotation = std::nanf("");
    message = sceneErrorOf([&] { validateScene(scene); });
    EXPECT_NE(message.find("occlusionTexture has a NaN or infinite texture transform"), std::string::npos) << message;
}

}  // namespace
}  // namespace janus::renderer
