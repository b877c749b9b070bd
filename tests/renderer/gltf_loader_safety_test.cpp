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

#include "core/texture_fit.h"
#include "janus/renderer/image.h"
#include "janus/renderer/scene.h"
#include "renderer/gltf_test_file.h"

namespace janus::renderer {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test_support::sceneErrorOf;
using test_support::TinyGltf;

using test_support::contains;

SceneLoadOptions allowingOutsidePaths() {
    SceneLoadOptions options;
    options.allowPathsOutsideSceneFolder = true;
    return options;
}

std::string base64(const std::vector<uint8_t>& bytes) {
    static const char* const kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        const uint32_t b0 = bytes[i], b1 = i + 1 < bytes.size() ? bytes[i + 1] : 0, b2 = i + 2 < bytes.size() ? bytes[i + 2] : 0;
        const uint32_t triple = (b0 << 16) | (b1 << 8) | b2;
        out += kAlphabet[(triple >> 18) & 63];
        out += kAlphabet[(triple >> 12) & 63];
        out += i + 1 < bytes.size() ? kAlphabet[(triple >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? kAlphabet[triple & 63] : '=';
    }
    return out;
}

std::vector<uint8_t> fileBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// A PNG with only its signature, an IHDR claiming width x height (RGBA8) and IEND: enough for
// a header read, nothing to decode. stb does not check chunk CRCs.
std::vector<uint8_t> pngHeaderOnly(uint32_t width, uint32_t height) {
    std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    auto u32 = [&](uint32_t v) {
        for (int shift : {24, 16, 8, 0}) png.push_back(uint8_t(v >> shift));
    };
    u32(13);
    png.insert(png.end(), {'I', 'H', 'D', 'R'});
    u32(width);
    u32(height);
    png.insert(png.end(), {8, 6, 0, 0, 0});   // 8 bits, RGBA, deflate, no filter, no interlace
    u32(0);                                   // CRC (not checked)
    u32(0);
    png.insert(png.end(), {'I', 'E', 'N', 'D'});
    u32(0);
    return png;
}

// Points the material's base colour at image 0, whose "uri" is `uri`.
void useImage(TinyGltf& file, const std::string& uri) {
    file.gltf["images"] = json::array({{{"uri", uri}}});
    file.gltf["textures"] = json::array({{{"source", 0}}});
    file.gltf["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
}

// --- URIs: the glTF's folder and below, unless allowed ----------------------------------------

TEST(GltfUris, BufferUriLeavingTheFolderIsRefusedByNameUnlessAllowed) {
    TinyGltf file;
    file.gltf["buffers"][0]["uri"] = "../tri.bin";   // tri.bin is in dir(), the glTF one folder below
    const fs::path path = file.write("models/tri.gltf");
    const std::string message = sceneErrorOf([&] { loadScene(path); });
    EXPECT_TRUE(contains(message, path.string())) << message;
    EXPECT_TRUE(contains(message, "buffer 0")) << message;
    EXPECT_TRUE(contains(message, "'../tri.bin' leaves the glTF's folder")) << message;
    EXPECT_TRUE(contains(message, "--allow-outside-paths")) << "the message says how to allow it: " << message;

    const Scene scene = loadScene(path, allowingOutsidePaths());
    ASSERT_EQ(scene.meshes.size(), 1u);
    EXPECT_EQ(scene.meshes[0].vertices[1].position, glm::vec3(1, 0, 0));
}

TEST(GltfUris, ImageUriEscapingToEtcPasswdIsRefusedBeforeAnythingIsRead) {
    TinyGltf file;
    useImage(file, "../../../../../../../../../../etc/passwd");
    const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
    EXPECT_TRUE(contains(message, "image 0")) << message;
    EXPECT_TRUE(contains(message, "'../../../../../../../../../../etc/passwd' leaves the glTF's folder")) << message;
}

TEST(GltfUris, PercentEncodedDotsAreDecodedBeforeTheCheck) {
    TinyGltf file;
    file.gltf["buffers"][0]["uri"] = "%2E%2E/tri.bin";
    const std::string message = sceneErrorOf([&] { loadScene(file.write("models/tri.gltf")); });
    EXPECT_TRUE(contains(message, "leaves the glTF's folder")) << message;
}

TEST(GltfUris, DotDotThatStaysInsideTheFolderIsFine) {
    TinyGltf file;
    file.gltf["buffers"][0]["uri"] = "models/../tri.bin";
    EXPECT_EQ(loadScene(file.write()).meshes.size(), 1u);
}

TEST(GltfUris, AbsolutePathsAreRefusedUnlessAllowed) {
    TinyGltf file;
    const fs::path bin = fs::absolute(file.dir() / "tri.bin");
    file.gltf["buffers"][0]["uri"] = bin.string();   // even one that names a file inside the folder
    const fs::path path = file.write();
    const std::string message = sceneErrorOf([&] { loadScene(path); });
    EXPECT_TRUE(contains(message, fmt::format("'{}' is an absolute path", bin.string()))) << message;
    EXPECT_EQ(loadScene(path, allowingOutsidePaths()).meshes.size(), 1u);
}

TEST(GltfUris, OtherSchemesThanDataAreRefusedEvenWhenAllowed) {
    for (const std::string uri : {"file:///etc/passwd", "http://example.com/tri.bin"}) {
        TinyGltf file;
        file.gltf["buffers"][0]["uri"] = uri;
        const fs::path path = file.write();
        for (const SceneLoadOptions& options : {SceneLoadOptions{}, allowingOutsidePaths()}) {
            const std::string message = sceneErrorOf([&] { loadScene(path, options); });
            EXPECT_TRUE(contains(message, fmt::format("'{}' uses the '{}:' scheme", uri, uri.substr(0, uri.find(':'))))) << message;
        }
    }
}

// tinygltf also looks for a relative URI in the working directory when it is not next to the
// glTF; a file there must not be read in its place.
TEST(GltfUris, TheWorkingDirectoryIsNotSearched) {
    TinyGltf elsewhere;   // a folder holding tri.bin, made the working directory
    elsewhere.write();
    TinyGltf file;
    file.gltf["buffers"][0]["uri"] = "only-in-the-working-directory.bin";
    fs::copy_file(elsewhere.dir() / "tri.bin", elsewhere.dir() / "only-in-the-working-directory.bin");
    const fs::path path = file.write();
    const fs::path cwd = fs::current_path();
    fs::current_path(elsewhere.dir());
    const std::string message = sceneErrorOf([&] { loadScene(path); });
    fs::current_path(cwd);
    EXPECT_TRUE(contains(message, "only-in-the-working-directory.bin")) << message;
}

// A scene file is the user's own: its "gltf" (and environment map) may point anywhere, as the
// repository's tests/renderer/data/cornell.json does with ../../../../shared.
TEST(GltfUris, SceneFileReferencesAreNotSubjectToTheRule) {
    TinyGltf file;
    file.write();
    fs::create_directories(file.dir() / "scenes" / "deeper");
    const fs::path scene = file.writeText("scenes/deeper/scene.json", R"({"gltf": "../../tri.gltf"})");
    EXPECT_EQ(loadScene(scene).meshes.size(), 1u);
}

// --- data: URIs --------------------------------------------------------------------------------

TEST(GltfDataUris, Base64BufferIsDecoded) {
    TinyGltf file;
    file.gltf["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(file.bin());
    const fs::path path = file.write();
    fs::remove(file.dir() / "tri.bin");
    const Scene scene = loadScene(path);
    ASSERT_EQ(scene.meshes.size(), 1u);
    EXPECT_EQ(scene.meshes[0].vertices[2].position, glm::vec3(0, 1, 0));
    EXPECT_EQ(scene.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(GltfDataUris, Base64ImageIsDecoded) {
    TinyGltf file;
    writePNG(file.dir() / "red.png", ImageRGBA8{1, 1, {200, 10, 20, 255}});
    useImage(file, "data:image/png;base64," + base64(fileBytes(file.dir() / "red.png")));
    const Scene scene = loadScene(file.write());
    ASSERT_EQ(scene.textures.size(), 1u);
    EXPECT_EQ(scene.textures[0].rgba, (std::vector<uint8_t>{200, 10, 20, 255}));
}

TEST(GltfDataUris, MalformedDataUrisAreRefusedWithTheReason) {
    const std::string valid = base64(TinyGltf().bin());
    struct Case {
        std::string uri;
        std::string reason;
    };
    const Case cases[] = {
        {"data:application/octet-stream;base64," + valid.substr(0, 20) + "!" + valid.substr(21),
         "is not valid base64: character '!' at offset 20"},
        {"data:application/octet-stream;base64," + valid.substr(0, valid.size() - 1), "not a multiple of 4"},
        {"data:application/octet-stream;base64," + valid.substr(0, 16), "decodes to 12 bytes, but the buffer's byteLength is 44"},
        {"data:application/octet-stream;base64,", "holds no data"},
        {"data:application/octet-stream," + valid, "is not base64-encoded"},
        {"data:application/json;base64," + valid, "media type 'application/json'"},
        {"data:application/octet-stream;base64", "has no ','"},
    };
    for (const Case& c : cases) {
        TinyGltf file;
        file.gltf["buffers"][0]["uri"] = c.uri;
        const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
        EXPECT_TRUE(contains(message, "buffer 0: data: URI")) << c.uri << ": " << message;
        EXPECT_TRUE(contains(message, c.reason)) << c.uri << ": " << message;
        EXPECT_LT(message.size(), 400u) << "a long data: URI is shortened in the message: " << message;
    }
}

// tinygltf hands the loader an embedded image's bytes without checking its buffer view against
// the buffer (a read past the end of the buffer).
TEST(GltfDataUris, ImageBufferViewOutsideItsBufferIsRefused) {
    TinyGltf file;
    file.gltf["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 40}, {"byteLength", 4000}});
    file.gltf["images"] = json::array({{{"bufferView", 2}, {"mimeType", "image/png"}}});
    file.gltf["textures"] = json::array({{{"source", 0}}});
    file.gltf["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    const std::string message = sceneErrorOf([&] { loadScene(file.writeGlb()); });
    EXPECT_TRUE(contains(message, "image 0: its buffer view 2")) << message;
    EXPECT_TRUE(contains(message, "does not lie inside its buffer")) << message;
}

// --- image sizes -------------------------------------------------------------------------------

TEST(GltfImages, ImageWiderThanTheLimitIsRefusedNamingItsSize) {
    TinyGltf file;
    writePNG(file.dir() / "wide.png", ImageRGBA8{16385, 1, std::vector<uint8_t>(16385 * 4, 255)});
    useImage(file, "wide.png");
    const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
    EXPECT_TRUE(contains(message, "image 0 ('wide.png') is 16385x1 pixels")) << message;
    EXPECT_TRUE(contains(message, "at most 16384 on a side")) << message;
}

TEST(GltfImages, ImageBeyondThePixelBudgetIsRefusedFromItsHeaderAlone) {
    TinyGltf file;
    const std::vector<uint8_t> header = pngHeaderOnly(8193, 8193);   // 256 MiB RGBA8 if decoded: over 64 Mi pixels
    std::ofstream(file.dir() / "huge.png", std::ios::binary).write(reinterpret_cast<const char*>(header.data()), std::streamsize(header.size()));
    useImage(file, "huge.png");
    const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
    EXPECT_TRUE(contains(message, "image 0 ('huge.png') is 8193x8193 pixels")) << message;
    EXPECT_TRUE(contains(message, "64 Mi pixels in all")) << message;
}

TEST(GltfImages, ImageAtTheSideLimitIsRead) {
    TinyGltf file;
    writePNG(file.dir() / "edge.png", ImageRGBA8{16384, 1, std::vector<uint8_t>(16384 * 4, 255)});
    useImage(file, "edge.png");
    const Scene scene = loadScene(file.write());
    ASSERT_EQ(scene.textures.size(), 1u);
    EXPECT_EQ(scene.textures[0].width, 16384u);
}

// Images decode side by side once the file is parsed: each lands in its own texture, and of two
// broken ones the lower image is the error, as when they decoded one at a time.
TEST(GltfImages, ImagesDecodeSideBySideEachIntoItsOwnTexture) {
    TinyGltf file;
    const char* names[] = {"a.png", "b.png", "c.png", "d.png"};
    json images = json::array(), textures = json::array();
    for (int i = 0; i < 4; ++i) {
        writePNG(file.dir() / names[i], ImageRGBA8{2, 1, std::vector<uint8_t>{uint8_t(10 * i), 1, 2, 255, uint8_t(10 * i + 5), 3, 4, 255}});
        images.push_back({{"uri", names[i]}});
        textures.push_back({{"source", i}});
    }
    file.gltf["images"] = images;
    file.gltf["textures"] = textures;
    json& material = file.gltf["materials"][0];
    material["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    material["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 1}};
    material["normalTexture"] = {{"index", 2}};
    material["emissiveTexture"] = {{"index", 3}};
    const Scene scene = loadScene(file.write());
    ASSERT_EQ(scene.textures.size(), 4u);
    for (const TextureImage& texture : scene.textures) {
        const int i = int(std::find(std::begin(names), std::end(names), texture.name) - std::begin(names));
        ASSERT_LT(i, 4) << texture.name;
        EXPECT_EQ(texture.rgba, (std::vector<uint8_t>{uint8_t(10 * i), 1, 2, 255, uint8_t(10 * i + 5), 3, 4, 255})) << texture.name;
    }

    // Images 1 and 3 have a header and nothing to decode.
    for (const char* broken : {"b.png", "d.png"}) {
        const std::vector<uint8_t> header = pngHeaderOnly(2, 1);
        std::ofstream(file.dir() / broken, std::ios::binary).write(reinterpret_cast<const char*>(header.data()), std::streamsize(header.size()));
    }
    const std::string message = sceneErrorOf([&] { loadScene(file.write()); });
    EXPECT_TRUE(contains(message, "image 1 ('b.png') could not be decoded")) << message;
    EXPECT_FALSE(contains(message, "image 3")) << message;
}

// What GpuScene does with a texture larger than the device's largest 2D texture (the GPU side
// is TextureLimitTest in texture_limit_test.cpp).
TEST(TextureFit, LargerTexturesAreDownscaledKeepingTheirAspect) {
    TextureImage image;
    image.name = "big";
    image.width = 16;
    image.height = 4;
    image.srgb = true;
    for (uint32_t i = 0; i < image.width * image.height; ++i) image.rgba.insert(image.rgba.end(), {30, 120, 240, 255});
    const TextureImage fitted = fitTextureToSize(image, 8);
    EXPECT_EQ(fitted.width, 8u);
    EXPECT_EQ(fitted.height, 2u);
    EXPECT_EQ(fitted.name, "big");
    EXPECT_TRUE(fitted.srgb);
    ASSERT_EQ(fitted.rgba.size(), 8u * 2u * 4u);
    for (size_t i = 0; i < fitted.rgba.size(); ++i)
        EXPECT_NEAR(int(fitted.rgba[i]), int(image.rgba[i % 4]), 1) << "a uniform texture keeps its colour, byte " << i;

    image.width = 5;
    image.height = 1;
    image.rgba.resize(5 * 4);
    const TextureImage thin = fitTextureToSize(image, 4);
    EXPECT_EQ(thin.width, 4u);
    EXPECT_EQ(thin.height, 1u);   // never below one texel

    const TextureImage same = fitTextureToSize(image, 5);
    EXPECT_EQ(same.width, 5u);
    EXPECT_EQ(same.rgba, image.rgba);
}

// --- node hierarchies --------------------------------------------------------------------------

TEST(GltfNodes, HundredThousandNestedNodesDoNotOverflowTheStack) {
    TinyGltf file;
    constexpr int kDepth = 100000;
    file.makeNodeChain(kDepth);
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
    // The two dark lights are named with their file, glTF light index and node.
    std::vector<std::string> dark;
    for (const std::string& warning : scene.warnings)
        if (contains(warning, "lights nothing")) dark.push_back(warning);
    ASSERT_EQ(dark.size(), 2u);
    EXPECT_TRUE(contains(dark[0], ".gltf: KHR_lights_punctual light 0 on node 'lamp 0' lights nothing (its range is <= 0)")) << dark[0];
    EXPECT_TRUE(contains(dark[1], "KHR_lights_punctual light 1 on node 'lamp 1' lights nothing")) << dark[1];
}

}  // namespace
}  // namespace janus::renderer
