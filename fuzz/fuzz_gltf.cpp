// glTF / GLB through loadSceneFromMemory, the in-memory twin of loadScene: the whole loader
// (tinygltf, our reference checks, accessors, images, nodes, validateScene). Input: a .gltf
// (JSON) or, when it starts with the GLB magic, a .glb. Relative URIs resolve in fuzz/assets.
//
// The contract under test: any input either loads or throws SceneError. Anything else (a crash,
// a sanitizer report, another exception escaping, a hang or an allocation beyond the limit) is a
// finding.
#include <cstdint>
#include <cstring>
#include <string_view>

#include "fuzz_common.h"
#include "janus/renderer/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace janus;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    try {
        renderer::loadSceneFromMemory(bytes, fuzz::assetsDir() / (glb ? "fuzz.glb" : "fuzz.gltf"));
    } catch (const renderer::SceneError&) {
    }
    return 0;
}
