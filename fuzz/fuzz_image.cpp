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
#include "glb_with_image.h"
#include "janus/renderer/image.h"
#include "janus/renderer/scene.h"

namespace {


}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace janus::renderer;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    auto startsWith = [&](std::string_view magic) { return bytes.substr(0, magic.size()) == magic; };
    try {
        if (startsWith("#?")) decodeRadianceHDR(bytes, "fuzz.hdr");
        else if (startsWith("\x76\x2f\x31\x01")) decodeEXR(bytes, "fuzz.exr");
        else if (startsWith("PF") || startsWith("Pf")) decodePFM(bytes, "fuzz.pfm");
        else if (size > 0) loadSceneFromMemory(janus::fuzz::glbWithImage(bytes), janus::fuzz::assetsDir() / "fuzz-image.glb");
    } catch (const ImageIOError&) {
    } catch (const SceneError&) {
    }
    return 0;
}
