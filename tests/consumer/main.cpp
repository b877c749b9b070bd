// Proves an installed Janus is usable: headers resolve, libraries link, a device can be probed.
#include <cstdio>

#include "janus/renderer/renderer.h"
#include "janus/rhi/rhi.h"

int main() {
    janus::renderer::Scene scene = janus::renderer::defaultScene();
    std::printf("default scene: %zu meshes\n", scene.meshes.size());
    for (const auto& probe : janus::rhi::probeBackends())
        std::printf("%s: %s\n", janus::rhi::toString(probe.backend), probe.available ? "available" : probe.reason.c_str());
    return scene.meshes.empty() ? 1 : 0;
}
