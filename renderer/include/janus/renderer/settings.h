// janus::renderer settings: what a Renderer is asked to render, and the error it throws when it
// cannot. Lower than renderer.h so that feature code (light_grid.h, shadows) need not include it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string_view>

namespace janus::renderer {

enum class FeaturePath { Compute, Fallback };
const char* toString(FeaturePath path);          // "compute", "fallback"
std::optional<FeaturePath> parseFeaturePath(std::string_view name);

// How point and spot lights reach the pixels that they light (docs/LIGHTING.md).
enum class LightCulling {
    Auto,         // chosen per frame: Naive below LightingSettings::autoTiledThreshold local lights, else TilesDepth
    Naive,        // every pixel loops every local light (the reference)
    Tiles2D,      // screen tiles; a light is listed where its sphere meets the tile's frustum (near..far)
    TilesDepth,   // as Tiles2D, clipped to each tile's depth bounds from a depth prepass
};
const char* toString(LightCulling mode);          // "auto", "naive", "tiles-2d", "tiles-depth"
std::optional<LightCulling> parseLightCulling(std::string_view name);

enum class DebugView {
    None,
    Tiles,   // heat map of local lights per tile (blue = none, red = the cap or 256) over the image; tiles at a cap below the light count are hatched
    Gi,      // the irradiance volume's diffuse light (irradiance / pi x coverage) instead of the shaded image, and its probes (docs/GI.md)
    GiLight, // the same light without the probes: the image's indirect term alone (what `janus bench gi` compares)
    Shadow,  // the main directional light's visibility from its shadow map (0 shadowed .. 1 lit; 1 without a map) on every
             // surface, in the HDR image (what `janus bench shadows` compares; docs/SHADOWS.md)
};
const char* toString(DebugView view);             // "none", "tiles", "gi", "gi-light", "shadow"
std::optional<DebugView> parseDebugView(std::string_view name);

// LightingSettings::maxLightsPerTile: sized by the renderer from the scene's lights.
inline constexpr uint32_t kAutoMaxLightsPerTile = 0;

// The largest list cap (LightingSettings::maxLightsPerTile) a renderer accepts.
inline constexpr uint32_t kMaxLightsPerTileLimit = 1024;
// An automatic cap (kAutoMaxLightsPerTile, the default) keeps the tile lists within this many
// bytes, unless that leaves fewer than kAutoMaxLightsPerTileFloor entries a tile. 32 MiB is what
// the former fixed default of 256 took at 3840x2160: a cap of 1024 fits up to about 1920x1080 in
// 16 px tiles, 256 at 4K.
inline constexpr uint64_t kAutoTileListBudgetBytes = uint64_t(32) << 20;
inline constexpr uint32_t kAutoMaxLightsPerTileFloor = 256;
// The cap an automatic maxLightsPerTile takes for `localLights` point/spot lights over `tileCount`
// tiles: the light count (no tile meets more, so none drops one), at most kMaxLightsPerTileLimit,
// within the budget above (but not below its floor), and at most `deviceLimit` (the largest cap
// whose lists the device holds on the feature path). At least 1.
uint32_t autoMaxLightsPerTile(size_t localLights, size_t tileCount, uint32_t deviceLimit = kMaxLightsPerTileLimit);

// Lighting knobs. Unset fields take the scene file's "quality" value, then the default shown.
struct LightingSettings {
    std::optional<LightCulling> culling;          // default Auto
    std::optional<uint32_t> tileSize;             // pixels: 16, 32, 64, 128 or 256; default 16
    // 1..1024, or kAutoMaxLightsPerTile (the default): as many as the scene has point and spot lights,
    // so no tile can drop one, within autoMaxLightsPerTile's limits; the frame report says which cap
    // was chosen (docs/LIGHTING.md, "The cap").
    std::optional<uint32_t> maxLightsPerTile;
    // Lights without a glTF range are culled where their illuminance falls below this (lux);
    // default 0.01. 0 = never cull them: infinite range, only Naive can render that (the
    // reference that measures the cut-off's error).
    std::optional<float> intensityCutoff;
    std::optional<uint32_t> autoTiledThreshold;   // Auto: fewer local lights than this loop naively; default 8 (bench)
    std::optional<bool> shadows;                  // shadow map for the main directional light; default true
    std::optional<uint32_t> shadowMapSize;        // default 1024
};

struct Scene;
// The lighting knobs a renderer made with `given` uses for `scene`, every field set: the given
// value, else the scene file's "quality" value, else the default. Throws RendererError, naming the
// key, for what the renderer would refuse.
LightingSettings resolveLightingSettings(const LightingSettings& given, const Scene& scene);

struct RenderSettings {
    uint32_t width = 256;
    uint32_t height = 256;
    FeaturePath path = FeaturePath::Compute;
    LightingSettings lighting;
    DebugView debugView = DebugView::None;
    // Multisampling of the main view: 0 = the scene file's quality key "msaa", else 1 (off); or
    // 1, 2, 4, 8, 16 samples per pixel where the device
    // allows that count for RGBA16F and D32F render targets (rhi::FormatCapabilities::sampleCounts;
    // 4 is allowed everywhere). The scene is shaded per pixel and depth-tested per sample, and the
    // samples are averaged before the tonemap (docs/LIGHTING.md, "Anti-aliasing"). Tiled light
    // culling then uses screen tiles without depth bounds (Auto picks Tiles2D; TilesDepth, whose
    // bounds come from single-sampled depth, is a RendererError), and readDepth() is not possible.
    uint32_t msaaSamples = 0;
    // Alpha-masked materials (glTF alphaMode MASK) in a multisampled view: true gives each
    // fragment as many samples as its alpha says around the material's cut-off (alpha to
    // coverage, over about one pixel), so a cut-out's edge is anti-aliased like a triangle's;
    // false keeps the per-pixel cut-off. nullopt: the scene file's quality key
    // "alphaToCoverage", else true. Nothing changes with one sample (docs/LIGHTING.md,
    // "Anti-aliasing").
    std::optional<bool> alphaToCoverage;
    // Samples per pixel of every reflection probe's capture: 0 = each probe's own
    // (ReflectionProbe::msaaSamples, the scene file's "msaa" of the probe), else 1, 2, 4, 8 or 16
    // where the device allows the count, as msaaSamples (docs/PROBES.md, "Multisampled captures").
    uint32_t probeMsaaSamples = 0;
    // The scene's irradiance volume from a file `bakeIrradianceVolume` (janus bake) wrote; empty:
    // baked when the renderer is made (docs/GI.md). A file of another scene, version or volume is
    // a RendererError.
    std::filesystem::path giBakeFile;
};

// Point and spot lights that light something, at most: one 512-word bitmask per tile in
// light_cull.comp. validateScene refuses more (SceneError), so loading says so before any device.
inline constexpr uint32_t kMaxLocalLights = 16384;

class RendererError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// A GI bake file that cannot be used: missing, not a bake, another format version, truncated,
// damaged (checksum), or made for another scene or volume (docs/GI.md, "Bake files").
class GiBakeFileError : public RendererError {
public:
    using RendererError::RendererError;
};

}  // namespace janus::renderer
