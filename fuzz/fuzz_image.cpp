// The image decoders, chosen by the input's magic as a file would be: Radiance HDR ("#?", the
// environment map reader), OpenEXR (environment maps), PFM (the HDR output reader); anything else
// is a glTF texture: wrapped as the only image of a GLB and loaded through loadSceneFromMemory,
// which decodes it as the loader does (stb_image behind the size checks, then RGBA8 conversion).
// Readers must throw ImageIOError (SceneError for the texture) and nothing else.
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "fuzz_common.h"
#include "janus/renderer/image.h"
#include "janus/renderer/scene.h"

namespace {

void appendU32(std::string& out, uint32_t v) {
    for (int shift = 0; shift < 32; shift += 8) out.push_back(char((v >> shift) & 0xFF));
}

// A GLB whose BIN chunk is `image` and whose material samples it as base colour.
std::string glbWithImage(std::string_view image) {
    const nlohmann::json gltf = {
        {"asset", {{"version", "2.0"}}},
        {"buffers", {{{"byteLength", image.size()}}}},
        {"bufferViews", {{{"buffer", 0}, {"byteLength", image.size()}}}},
        {"images", {{{"bufferView", 0}, {"mimeType", "image/png"}}}},
        {"textures", {{{"source", 0}}}},
        {"materials", {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}}},
    };
    std::string json = gltf.dump();
    json.resize((json.size() + 3) & ~size_t(3), ' ');
    std::string bin(image);
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

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace janus::renderer;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    auto startsWith = [&](std::string_view magic) { return bytes.substr(0, magic.size()) == magic; };
    try {
        if (startsWith("#?")) decodeRadianceHDR(bytes, "fuzz.hdr");
        else if (startsWith("\x76\x2f\x31\x01")) decodeEXR(bytes, "fuzz.exr");
        else if (startsWith("PF") || startsWith("Pf")) decodePFM(bytes, "fuzz.pfm");
        else if (size > 0) loadSceneFromMemory(glbWithImage(bytes), janus::fuzz::assetsDir() / "fuzz-image.glb");
    } catch (const ImageIOError&) {
    } catch (const SceneError&) {
    }
    return 0;
}
