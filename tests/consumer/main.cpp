// Proves an installed Janus is usable: headers resolve, libraries link, a device can be probed,
// and janus_embed_shaders() embeds two variants of one shader side by side.
#include <cstdio>
#include <cstring>
#include <span>

#include "janus/renderer/renderer.h"
#include "janus/rhi/rhi.h"
#include "red_shaders.h"
#include "white_shaders.h"

int main() {
    janus::renderer::Scene scene = janus::renderer::defaultScene();
    std::printf("default scene: %zu meshes\n", scene.meshes.size());
    for (const auto& probe : janus::rhi::probeBackends())
        std::printf("%s: %s\n", janus::rhi::toString(probe.backend), probe.available ? "available" : probe.reason.c_str());
    const std::span<const uint32_t> white = white::tint_frag, red = red::tint_frag;
    const bool variantsDiffer = white.size() != red.size() || std::memcmp(white.data(), red.data(), white.size_bytes()) != 0;
    std::printf("tint.frag: %zu words, with RED %zu words%s\n", white.size(), red.size(), variantsDiffer ? "" : " (the same!)");
    return scene.meshes.empty() || !variantsDiffer || white[0] != 0x07230203u ? 1 : 0;
}
