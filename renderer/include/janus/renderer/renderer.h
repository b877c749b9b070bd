// janus::renderer: renders a Scene with a janus::rhi device.
//
// The frame is planned from the scene: a pass exists only if the scene needs it. Every feature
// has a compute path (needs Capability::Compute) and a fallback path (fragment shaders / CPU),
// and both run on every backend that can run them.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "janus/renderer/frame_report.h"
#include "janus/renderer/image.h"
#include "janus/renderer/scene.h"
#include "janus/renderer/scene_view.h"
#include "janus/renderer/settings.h"
#include "janus/rhi/rhi.h"

namespace janus::renderer {

// Renders the scene around a point into the six faces of one cube of a cube map (the capture
// reflection probes and G-buffer cubes are built on): six views (makeCubeFaceViews) with the
// reduced pass set below, straight into `target`. The result is linear radiance, as the HDR
// image of renderFrame() holds it.
struct CubeCaptureDesc {
    glm::vec3 position{0.0f};
    float nearPlane = 0.05f;
    float farPlane = 100.0f;
    // A TextureCube or TextureCubeArray with RenderTarget usage and a float colour format (e.g.
    // RGBA16F). The faces written are layers 6 * cube + 0..5 at `mipLevel`, whose size is the
    // faces' size (`cube` is 0 for a TextureCube).
    rhi::TextureHandle target;
    uint32_t cube = 0;
    uint32_t mipLevel = 0;
    bool shadows = true;                // the main light's shadow map (the pass is left out without)
    uint32_t shadowMapSize = 0;         // its size for the capture; 0 = the renderer's
    uint32_t renderingLayers = ~0u;     // meshes the capture sees
    uint32_t faces = 0x3f;              // bit f: render face f (+X, -X, +Y, -Y, +Z, -Z); at least one
    // Samples per pixel: each face is shaded into multisampled targets the renderer keeps and
    // resolved into the target's face (1, 2, 4, 8 or 16 where the device allows the count for the
    // target's format and D32F; alpha-masked materials then use the renderer's alphaToCoverage).
    uint32_t msaaSamples = 1;
    // Surfaces shade with the reflection probes shown now (ReflectionProbe::seesProbes) instead of
    // the sky alone. What the capture writes is never what shading reads: probes are shown from
    // copies made when an update completes.
    bool reflectionProbes = false;
    std::string viewPrefix = "cube";    // views are named "<prefix> +X" ... in reports
};

// The capture a reflection probe's updates make (docs/PROBES.md): its position, planes, passes,
// samples and whether it sees probes. `target`, `faces` and `viewPrefix` are the caller's.
CubeCaptureDesc cubeCaptureOf(const ReflectionProbe& probe);

// One probe of the scene's irradiance volume as the last relight left it (docs/GI.md).
struct IrradianceProbe {
    glm::vec3 position{0.0f};
    // SH9 of irradiance / pi (what Lambert multiplies albedo by), basis order of docs/IBL.md.
    std::array<glm::vec3, 9> sh{};
    bool valid = false;              // shading gives an invalid probe (inside geometry) no weight
    float backFaceFraction = 0.0f;   // of its bake samples
};

// What bakeIrradianceVolume made.
struct IrradianceBakeSummary {
    uint32_t probes = 0, validProbes = 0;
    uint32_t relocatedProbes = 0;   // moved out of geometry (IrradianceVolume::relocateProbes)
    uint64_t surfels = 0, bricks = 0, transfers = 0;
    double milliseconds = 0.0;
};
// Bakes the scene's irradiance volume (docs/GI.md) on `device` and writes it atomically to `path`
// for RenderSettings::giBakeFile. Throws RendererError when the scene has no volume or the file
// cannot be written.
IrradianceBakeSummary bakeIrradianceVolume(rhi::IDevice& device, const Scene& scene, const std::filesystem::path& path);

// The directional light the shadow map serves (docs/SHADOWS.md): the brightest (largest colour
// channel x intensity) of the first `shadedDirectionalLights` directional lights in scene order
// (the forward pass shades four), the first of equals. An index into scene.lights; nullopt when
// none gives any light.
std::optional<size_t> mainDirectionalLight(const Scene& scene, uint32_t shadedDirectionalLights = 4);

class Renderer {
public:
    // Uploads the scene. Throws RendererError for settings the device cannot honour (absurd
    // sizes; the compute path on a device without compute names the capability). The renderer
    // keeps a reference to `device`, which must outlive it: its destructor waits for the device's
    // work to finish. Should the device go first, the renderer's calls that use it throw
    // RendererError saying so, and its destructor only warns (RHI handles may outlive their device).
    Renderer(rhi::IDevice& device, const Scene& scene, const RenderSettings& settings);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // The main camera's frame: its report has one view, "main".
    FrameReport renderFrame();
    // Throws RendererError for a target that is not a cube, lacks RenderTarget usage or a float
    // format, or has no such mip. The report lists six views, "cube +X" ... "cube -Z".
    FrameReport renderCubeCapture(const CubeCaptureDesc& capture);
    // Starts an update of the named reflection probe (every probe when empty) at the next frame,
    // whatever its update mode (docs/PROBES.md). Throws RendererError for an unknown name.
    void requestProbeUpdate(std::string_view probeName = {});
    // True while a reflection probe has its first update due or under way: frames rendered now
    // lack its reflections (time slicing spreads an update over up to 8 frames). Render until it
    // is false for a complete image (what `janus render` does).
    bool probesPending() const;
    // True while the irradiance volume has relight work due (probesPerFrame spreads a relight over
    // frames): render until it is false for a settled image.
    bool irradiancePending() const;
    // The irradiance volume's probes (grid order x + X (y + Y z)); empty without a volume. Waits
    // for the GPU. A probe not yet relit reads as zero and invalid.
    std::vector<IrradianceProbe> readIrradianceProbes();
    // Replaces what the irradiance volume holds with `probes` (grid order and positions as
    // readIrradianceProbes gives them; `sh` and `valid` are stored, as half floats, and
    // backFaceFraction is ignored): light from another baker, or a reference's probes to measure
    // the volume's lookup alone (`janus bench gi`). Ends a relight in progress; the next relight
    // (markIrradianceDirty, a light changed by setLights) replaces them in turn. Throws
    // RendererError without a volume, for another probe count, a position off the grid or a
    // coefficient that is not finite or beyond half-float range.
    void writeIrradianceProbes(std::span<const IrradianceProbe> probes);
    // The scene's lights or sky changed: the irradiance volume relights (docs/GI.md).
    void markIrradianceDirty();
    // Replaces the scene's lights (Scene::lights) from the next frame on: forward shading, the
    // main directional light's shadow map (refitted to its direction), light culling, and the
    // irradiance volume, which relights from scratch (as a new Renderer would light it) only when
    // a light actually changed. Reflection probes keep their update mode: requestProbeUpdate()
    // recaptures them. The frame keeps its plan (docs/LIGHTING.md, "Moving lights"), so these
    // are RendererErrors that change nothing: a light with a NaN or infinite value, a negative
    // colour or intensity or a zero direction (naming it); more point/spot lights that light
    // something than the renderer was made with; a directional light that gives light where the
    // renderer was made without one (and shadows are on). Create a new Renderer for those.
    void setLights(std::span<const Light> lights);

    ImageRGBA8 readDisplayImage();   // tonemapped, sRGB-encoded: what PNGs and parity use
    ImageRGBAF readHdrImage();       // linear scene radiance before tonemapping: EXR / PFM
    // For tests and analysis (they wait for the GPU). readTileLists throws RendererError when the
    // last frame built no tiles; readDepth returns the D32F depth of the last frame, row 0 on top.
    TileLists readTileLists();
    std::vector<float> readDepth();

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

}  // namespace janus::renderer
