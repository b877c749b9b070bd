// A one-triangle glTF written to a temporary folder, for scene-loader tests that craft files
// (tests/renderer/scene_test.cpp, gltf_loader_safety_test.cpp), and sceneErrorOf.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "janus/renderer/image.h"
#include "janus/renderer/scene.h"

namespace janus::renderer::test_support {

namespace gltf_test_file_detail {
namespace fs = std::filesystem;
using nlohmann::json;

// Runs `load` and returns the SceneError message; fails the test if nothing (or something
// else) was thrown.
template <typename Load>
std::string sceneErrorOf(Load&& load) {
    try {
        load();
    } catch (const SceneError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "expected SceneError, got another exception: " << e.what();
        return {};
    }
    ADD_FAILURE() << "expected SceneError, nothing was thrown";
    return {};
}

// A one-triangle glTF written to a fresh directory, with hooks to break it in specific ways.
class TinyGltf {
public:
    TinyGltf() {
        m_dir = fs::temp_directory_path() / fmt::format("janus-scene-test-{}-{}", ::getpid(), s_counter++);
        fs::create_directories(m_dir);
        // Three positions (36 bytes) then three uint16 indices (6 bytes, padded to 8).
        const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        const uint16_t indices[4] = {0, 1, 2, 0};
        m_bin.resize(44);
        std::memcpy(m_bin.data(), positions, 36);
        std::memcpy(m_bin.data() + 36, indices, 8);
        gltf = {
            {"asset", {{"version", "2.0"}}},
            {"scene", 0},
            {"scenes", json::array({{{"nodes", {0}}}})},
            {"nodes", json::array({{{"name", "triangle node"}, {"mesh", 0}}})},
            {"meshes", json::array({{{"name", "triangle"}, {"primitives", json::array({{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 0}}})}}})},
            {"materials", json::array({{{"name", "plain"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}}}}})},
            {"buffers", json::array({{{"uri", "tri.bin"}, {"byteLength", 44}}})},
            {"bufferViews", json::array({{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}},
                                         {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 6}}})},
            {"accessors", json::array({{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"},
                                        {"min", {0, 0, 0}}, {"max", {1, 1, 0}}},
                                       {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}}})},
        };
    }
    ~TinyGltf() {
        std::error_code ec;
        fs::remove_all(m_dir, ec);
    }

    // Adds TEXCOORD_0 (v grows downwards, as in glTF) and a 1x1 normal-map PNG to the material.
    void addUvsAndNormalMap() {
        const float uvs[6] = {0, 1, 1, 1, 0, 0};
        const size_t offset = m_bin.size();
        m_bin.resize(offset + sizeof(uvs));
        std::memcpy(m_bin.data() + offset, uvs, sizeof(uvs));
        gltf["buffers"][0]["byteLength"] = m_bin.size();
        gltf["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", sizeof(uvs)}});
        gltf["accessors"].push_back({{"bufferView", 2}, {"componentType", 5126}, {"count", 3}, {"type", "VEC2"}});
        gltf["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 2;
        writePNG(m_dir / "normal.png", ImageRGBA8{1, 1, {128, 128, 255, 255}});
        gltf["images"] = json::array({{{"uri", "normal.png"}}});
        gltf["textures"] = json::array({{{"source", 0}}});
        gltf["materials"][0]["normalTexture"] = {{"index", 0}};
    }

    // Replaces the nodes with a chain `depth` deep: node i is node i + 1's parent, each moves its
    // child by 0.5 along z, and the last holds mesh 0 (hierarchies that must not overflow a stack).
    void makeNodeChain(int depth) {
        json nodes = json::array();
        for (int i = 0; i < depth; ++i) {
            json node = {{"translation", {0.0, 0.0, 0.5}}};
            if (i + 1 < depth) node["children"] = {i + 1};
            else node["mesh"] = 0;
            nodes.push_back(std::move(node));
        }
        gltf["nodes"] = std::move(nodes);
    }

    void setIndex(size_t which, uint16_t value) { std::memcpy(m_bin.data() + 36 + which * 2, &value, 2); }
    const fs::path& dir() const { return m_dir; }
    const std::vector<uint8_t>& bin() const { return m_bin; }

    // Appends `bytes` to the buffer (4-byte aligned, as glTF wants for vertex data) as a new
    // buffer view (with `stride` when non-zero) and an accessor reading it; returns the accessor.
    int addAccessor(const void* data, size_t bytes, json accessor, size_t stride = 0) {
        while (m_bin.size() % 4) m_bin.push_back(0);
        const size_t offset = m_bin.size();
        m_bin.resize(offset + bytes);
        std::memcpy(m_bin.data() + offset, data, bytes);
        while (m_bin.size() % 4) m_bin.push_back(0);
        gltf["buffers"][0]["byteLength"] = m_bin.size();
        json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
        if (stride) view["byteStride"] = stride;
        gltf["bufferViews"].push_back(view);
        accessor["bufferView"] = gltf["bufferViews"].size() - 1;
        gltf["accessors"].push_back(accessor);
        return int(gltf["accessors"].size() - 1);
    }

    // `name` may lie in a subfolder of dir(); the buffer file stays dir()/tri.bin.
    fs::path write(const std::string& name = "tri.gltf") const {
        std::ofstream(m_dir / "tri.bin", std::ios::binary).write(reinterpret_cast<const char*>(m_bin.data()), std::streamsize(m_bin.size()));
        fs::create_directories((m_dir / name).parent_path());
        std::ofstream(m_dir / name) << gltf.dump(2);
        return m_dir / name;
    }
    // The same content as one binary .glb: header, JSON chunk, BIN chunk (both 4-byte aligned).
    fs::path writeGlb(const std::string& name = "tri.glb") const {
        json embedded = gltf;
        embedded["buffers"] = json::array({{{"byteLength", m_bin.size()}}});
        std::string text = embedded.dump();
        while (text.size() % 4) text += ' ';
        std::vector<uint8_t> bin = m_bin;
        while (bin.size() % 4) bin.push_back(0);
        const uint32_t total = uint32_t(12 + 8 + text.size() + 8 + bin.size());
        std::ofstream out(m_dir / name, std::ios::binary);
        auto u32 = [&](uint32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); };
        u32(0x46546C67);   // "glTF"
        u32(2);
        u32(total);
        u32(uint32_t(text.size()));
        u32(0x4E4F534A);   // "JSON"
        out.write(text.data(), std::streamsize(text.size()));
        u32(uint32_t(bin.size()));
        u32(0x004E4942);   // "BIN\0"
        out.write(reinterpret_cast<const char*>(bin.data()), std::streamsize(bin.size()));
        return m_dir / name;
    }
    fs::path writeText(const std::string& name, const std::string& text) const {
        std::ofstream(m_dir / name) << text;
        return m_dir / name;
    }

    json gltf;

private:
    fs::path m_dir;
    std::vector<uint8_t> m_bin;
    static inline int s_counter = 0;
};

}  // namespace gltf_test_file_detail

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A Khronos sample model of ../shared/scenes/khronos (its README says what each exercises).
inline std::filesystem::path khronosModel(const std::string& model) {
    return std::filesystem::path(JANUS_SHARED_SCENES_DIR) / "khronos" / model / "glTF" / (model + ".gltf");
}

using gltf_test_file_detail::sceneErrorOf;
using gltf_test_file_detail::TinyGltf;

}  // namespace janus::renderer::test_support
