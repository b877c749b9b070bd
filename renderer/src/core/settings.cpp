// Names of the settings' enumerations (settings.h), apart from the frame report so that the
// scene loader, which checks a scene file's "quality" keys, links without the GPU half.
#include "janus/renderer/settings.h"

namespace janus::renderer {

const char* toString(FeaturePath path) { return path == FeaturePath::Compute ? "compute" : "fallback"; }

std::optional<FeaturePath> parseFeaturePath(std::string_view name) {
    if (name == "compute") return FeaturePath::Compute;
    if (name == "fallback") return FeaturePath::Fallback;
    return std::nullopt;
}

const char* toString(LightCulling mode) {
    switch (mode) {
        case LightCulling::Auto: return "auto";
        case LightCulling::Naive: return "naive";
        case LightCulling::Tiles2D: return "tiles-2d";
        case LightCulling::TilesDepth: return "tiles-depth";
    }
    return "unknown";
}

std::optional<LightCulling> parseLightCulling(std::string_view name) {
    for (LightCulling mode : {LightCulling::Auto, LightCulling::Naive, LightCulling::Tiles2D, LightCulling::TilesDepth})
        if (name == toString(mode)) return mode;
    return std::nullopt;
}

const char* toString(DebugView view) {
    switch (view) {
        case DebugView::Tiles: return "tiles";
        case DebugView::Gi: return "gi";
        case DebugView::GiLight: return "gi-light";
        case DebugView::Shadow: return "shadow";
        case DebugView::None: break;
    }
    return "none";
}

std::optional<DebugView> parseDebugView(std::string_view name) {
    if (name == "none") return DebugView::None;
    if (name == "tiles") return DebugView::Tiles;
    if (name == "gi") return DebugView::Gi;
    if (name == "gi-light") return DebugView::GiLight;
    if (name == "shadow") return DebugView::Shadow;
    return std::nullopt;
}

}  // namespace janus::renderer
