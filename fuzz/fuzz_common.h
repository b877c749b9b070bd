// Shared by the fuzz targets: where inputs "live" (so relative URIs and a scene file's "gltf"
// resolve to the small files in fuzz/assets), and the one exception type a loader may throw.
#pragma once

#include <cstdlib>
#include <filesystem>

namespace janus::fuzz {

// JANUS_FUZZ_ASSETS overrides the folder, e.g. to fuzz against other referenced files.
inline const std::filesystem::path& assetsDir() {
    static const std::filesystem::path dir = [] {
        const char* env = std::getenv("JANUS_FUZZ_ASSETS");
        return std::filesystem::path(env && *env ? env : JANUS_FUZZ_ASSETS_DIR);
    }();
    return dir;
}

}  // namespace janus::fuzz
