// CPU tile builder and culling analysis (docs/LIGHTING.md).
#include "janus/renderer/light_grid.h"

namespace janus::renderer {

TileLists buildTileListsCpu(const TileGrid&, std::span<const PackedLight>, std::span<const float>, TileBuildStats*, unsigned) {
    throw RendererError("buildTileListsCpu: not implemented yet");
}

CullingEfficiency measureCullingEfficiency(const TileGrid&, std::span<const PackedLight>, const TileLists*, std::span<const float>) {
    throw RendererError("measureCullingEfficiency: not implemented yet");
}

std::vector<MissingLight> findMissingLights(const TileGrid&, std::span<const PackedLight>, const TileLists&, std::span<const float>, size_t) {
    throw RendererError("findMissingLights: not implemented yet");
}

}  // namespace janus::renderer
