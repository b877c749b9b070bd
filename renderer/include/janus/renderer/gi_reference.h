// The probe GI's CPU reference (docs/GI.md, "Reference"): a path tracer on Embree that computes,
// for the scene and lights the renderer shades, what the irradiance volume approximates:
//   - the incident radiance at a probe's position projected to SH9, and the irradiance / pi it
//     gives (what IrradianceProbe::sh holds), and
//   - the indirect diffuse irradiance / pi at every pixel of a camera's view (what `--debug gi`
//     shows: the volume's light alone).
// Light transport, with the same "bounces" as IrradianceVolume::bounces: a surface reached by a
// ray sends its emission plus albedo / pi times the direct irradiance of every light whose rendering
// layers share a bit with its instance's (directional, point and spot, with the renderer's
// attenuation and cone, each shadowed by a ray to the light) and,
// while bounces remain, albedo times the irradiance / pi it receives in turn (cosine-sampled paths);
// a ray that hits nothing brings the sky (the environment map, else the ambient colour). Back faces
// of single-sided materials send nothing (as the bake's back-face samples). Diffuse albedo is base
// colour x (1 - metallic), textures sampled bilinearly at mip 0. Opaque meshes take part, and
// alpha-masked ones where their alpha test keeps them (every ray passes where base colour factor x
// vertex colour x texture alpha is below the cutoff, as the bake, the shadow map and shading
// discard there); blended ones do not, as in the bake.
// Results are deterministic for a given seed, whatever the number of threads.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "janus/renderer/image.h"
#include "janus/renderer/renderer.h"
#include "janus/renderer/scene.h"

namespace janus::renderer {

// Longest path a converged reference follows (Russian roulette ends nearly all paths long before).
inline constexpr uint32_t kGiReferenceMaxBounces = 64;

struct GiReferenceSettings {
    // Light bounces as IrradianceVolume::bounces counts them (1: direct light reflected once);
    // 0: converged (every bounce; Russian roulette from the eighth, at most kGiReferenceMaxBounces).
    uint32_t bounces = 0;
    uint32_t directionsPerProbe = 4096;   // spherical-Fibonacci directions, one path each
    uint32_t samplesPerPixel = 256;       // cosine-distributed paths per pixel
    uint64_t seed = 1;
    uint32_t threads = 0;                 // 0: one per hardware thread

    GiReferenceSettings& setBounces(uint32_t value) { bounces = value; return *this; }
    GiReferenceSettings& setDirectionsPerProbe(uint32_t value) { directionsPerProbe = value; return *this; }
    GiReferenceSettings& setSamplesPerPixel(uint32_t value) { samplesPerPixel = value; return *this; }
    GiReferenceSettings& setSeed(uint64_t value) { seed = value; return *this; }
    GiReferenceSettings& setThreads(uint32_t value) { threads = value; return *this; }
};

// The reference's view of one probe: SH9 of the incident radiance (projected, not convolved) and
// of irradiance / pi (convolved with the clamped cosine: IrradianceProbe::sh's meaning).
struct GiReferenceProbe {
    glm::vec3 position{0.0f};
    std::array<glm::dvec3, 9> radianceSh{};
    std::array<glm::dvec3, 9> irradianceSh{};
};

class GiReference {
public:
    // Builds the ray tracing scene from `scene` (copies what it needs; `scene` may go away). Throws
    // RendererError when Embree fails or the environment map cannot be read.
    explicit GiReference(const Scene& scene);
    ~GiReference();
    GiReference(const GiReference&) = delete;
    GiReference& operator=(const GiReference&) = delete;

    // Incident radiance at each position (e.g. the volume's probes), projected to SH9. Throws
    // RendererError for 0 directions or more than kGiReferenceMaxBounces bounces.
    std::vector<GiReferenceProbe> probes(std::span<const glm::vec3> positions, const GiReferenceSettings& settings) const;
    // Indirect diffuse irradiance / pi per pixel of `camera`'s view (the renderer's projection;
    // row 0 on top): rgb where the pixel's ray meets a front face (or a double-sided one), alpha 1
    // there and 0 (rgb 0) where it meets nothing or a back face. Throws RendererError for a size of
    // 0 or 0 samples.
    ImageRGBAF indirectIrradiance(const Camera& camera, uint32_t width, uint32_t height, const GiReferenceSettings& settings) const;
    // Radiance arriving at `origin` from `direction` (unit), one path, `bounces` as above.
    glm::dvec3 incidentRadiance(const glm::vec3& origin, const glm::vec3& direction, uint32_t bounces, uint64_t seed) const;

    // The shadow map's reference (docs/SHADOWS.md, "Accuracy vs time"): per pixel of `camera`'s view
    // (row 0 on top), whether light travelling along `lightDirection` (a directional light; need not be
    // unit length) reaches the surface the pixel's centre sees: rgb 1 lit, 0 shadowed, by one ray
    // towards the light, which the shadow map's casters block as the map does (opaque meshes, and
    // masked ones where their alpha test keeps them; single-sided ones only where the light meets their front face;
    // blended ones not). Alpha 1 where the pixel sees a front face (or a double-sided one) that
    // faces the light; 0 (rgb 0) where it sees nothing, a back face, or a surface facing away from
    // the light, which the light does not reach whatever its shadow. Throws RendererError for a
    // size of 0 or a zero or non-finite direction.
    ImageRGBAF lightVisibility(const Camera& camera, uint32_t width, uint32_t height, const glm::vec3& lightDirection,
                               uint32_t threads = 0) const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

// How far the renderer is from the reference.
struct GiError {
    double relativeRmse = 0.0;   // RMS |renderer - reference| / mean |reference| (RGB vector lengths)
    // Signed: sum of (renderer - reference) / sum of reference, over every channel of every value
    // compared. Which way the error leans (too dark < 0 < too bright), which the RMSE does not say.
    double relativeBias = 0.0;
    double maxAbsolute = 0.0;    // largest |renderer - reference|
    uint64_t compared = 0;       // values compared (probe x normal, or pixels)
};
// Irradiance / pi of the renderer's probes against the reference's, both evaluated (clamped at 0,
// as shading does) at `normals` unit directions spread over the sphere (spherical Fibonacci), over
// the probes the renderer holds valid. Throws RendererError when the lists differ in length.
GiError compareProbeIrradiance(std::span<const IrradianceProbe> probes, std::span<const GiReferenceProbe> reference,
                               uint32_t normals = 64);
// The image's indirect term: `rendered` (the HDR image of a `--debug gi` frame) against the
// reference's indirectIrradiance, over the pixels where the reference's alpha is 1. Throws
// RendererError when the sizes differ.
GiError compareIndirectImage(const ImageRGBAF& rendered, const ImageRGBAF& reference);

// How far a shadow map's visibility (the red channel of a `--debug shadow` frame's HDR image) is
// from GiReference::lightVisibility, over the pixels whose reference alpha is 1.
struct VisibilityError {
    double meanAbsolute = 0.0;   // mean |rendered - reference|: the share of the light's contribution that is wrong
    double rmse = 0.0;
    double wrongFraction = 0.0;  // pixels on the wrong side of one half: lit where shadowed or shadowed where lit
    double leakFraction = 0.0;   // of those, lit (> 0.5) where the reference is shadowed: light leaks, peter-panning
    double falseShadowFraction = 0.0;   // shadowed (< 0.5) where the reference is lit: acne, shadows grown past their casters
    uint64_t compared = 0;
};
// Throws RendererError when the sizes differ.
VisibilityError compareVisibility(const ImageRGBAF& rendered, const ImageRGBAF& reference);

}  // namespace janus::renderer
