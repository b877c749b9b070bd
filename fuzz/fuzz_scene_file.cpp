// JSON scene files (docs/SCENES.md) through loadSceneFromMemory: camera, environment, lights,
// layers, markers, reflection probes, quality, and the glTF they name, which resolves in
// fuzz/assets (triangle.gltf, textured.gltf). Any input loads or throws SceneError.
#include <cstdint>
#include <string_view>

#include "fuzz_common.h"
#include "janus/renderer/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace janus;
    try {
        renderer::loadSceneFromMemory(std::string_view(reinterpret_cast<const char*>(data), size), fuzz::assetsDir() / "fuzz.json");
    } catch (const renderer::SceneError&) {
    }
    return 0;
}
