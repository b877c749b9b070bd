// GLB assembly for the fuzz targets, their seeds and the tests that replay findings
// (tests/renderer/fuzz_findings_test.cpp). glbWithImage: a GLB whose only image is `image` (in the
// BIN chunk), a material's base colour: how the image target feeds textures to the loader.
// Header-only: the fuzz build and the test build both include it.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace janus::fuzz {

inline void appendU32(std::string& out, uint32_t v) {
    for (int shift = 0; shift < 32; shift += 8) out.push_back(char((v >> shift) & 0xFF));
}

// A binary glTF of `json` and `bin`, each chunk padded to 4 bytes (JSON with spaces, BIN with zeros).
inline std::string makeGlb(std::string json, std::string bin) {
    json.resize((json.size() + 3) & ~size_t(3), ' ');
    bin.resize((bin.size() + 3) & ~size_t(3), '\0');
    std::string glb = "glTF";
    appendU32(glb, 2);
    appendU32(glb, uint32_t(12 + 8 + json.size() + 8 + bin.size()));
    appendU32(glb, uint32_t(json.size()));
    appendU32(glb, 0x4E4F534Au);   // JSON
    glb += json;
    appendU32(glb, uint32_t(bin.size()));
    appendU32(glb, 0x004E4942u);   // BIN
    glb += bin;
    return glb;
}

inline std::string glbWithImage(std::string_view image) {
    const nlohmann::json gltf = {
        {"asset", {{"version", "2.0"}}},
        {"buffers", {{{"byteLength", image.size()}}}},
        {"bufferViews", {{{"buffer", 0}, {"byteLength", image.size()}}}},
        {"images", {{{"bufferView", 0}, {"mimeType", "image/png"}}}},
        {"textures", {{{"source", 0}}}},
        {"materials", {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}}},
    };
    return makeGlb(gltf.dump(), std::string(image));
}

}  // namespace janus::fuzz
