// The GI reference path tracer (janus/renderer/gi_reference.h, docs/GI.md "Reference") against
// closed forms: a closed emissive box (every bounce count and converged), a lit plane (direct
// light, shadow rays, the point light's attenuation), the sky, back faces and mirrored instances;
// determinism; the error measures the benchmark reports. CPU only.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "ibl/spherical_harmonics.h"
#include "janus/renderer/gi_reference.h"
#include "renderer/renderer_test_support.h"
#include "scene/scene_internal.h"

namespace janus::renderer {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A quad of `size` x `size` metres centred at `center`, facing `normal`.
void addQuad(Scene& scene, int32_t material, const glm::vec3& center, const glm::vec3& normal, float size, bool mirrored = false) {
    const uint32_t mesh = detail::addMesh(scene, detail::makeQuad(material));
    scene.instances.push_back(Instance{mesh, test_support::quadFacing(center, normal, size, mirrored), 1u, fmt::format("quad {}", scene.instances.size())});
}

// A closed 2 m box around the origin whose inside walls emit `emission` and reflect `albedo`.
Scene emissiveBox(const glm::vec3& emission, float albedo) {
    Scene scene;
    scene.environment.ambientColor = glm::vec3(0.0f);
    test_support::addGlowingRoom(scene, {emission, emission, emission, emission, emission, emission}, albedo, false);
    scene.camera.position = glm::vec3(0.0f, 0.0f, 0.8f);
    scene.camera.target = glm::vec3(0.2f, -0.3f, -1.0f);
    return scene;
}

// Irradiance / pi of a reference probe at normal `n`, clamped at 0 as shading does.
glm::dvec3 irradianceOverPi(const GiReferenceProbe& probe, const glm::dvec3& n) {
    ShRgb sh{};
    for (size_t k = 0; k < 9; ++k) sh[k] = probe.irradianceSh[k];
    return shEvaluateIrradiance(sh, n);
}

TEST(GiReference, AClosedEmissiveBoxGivesTheGeometricSeriesOfItsAlbedo) {
    const glm::vec3 e(1.5f, 1.0f, 0.25f);
    const double a = 0.5;
    const GiReference reference(emissiveBox(e, float(a)));
    const std::vector<glm::vec3> positions = {glm::vec3(0.0f), glm::vec3(0.3f, -0.5f, 0.6f)};
    // Every path of n bounces collects e (1 + a + ... + a^(n-1)) exactly; converged: e / (1 - a).
    for (uint32_t bounces : {1u, 2u, 3u, 0u}) {
        const double expected = bounces == 0 ? 1.0 / (1.0 - a) : (1.0 - std::pow(a, bounces)) / (1.0 - a);
        const auto probes = reference.probes(positions, GiReferenceSettings{}.setBounces(bounces).setDirectionsPerProbe(2048));
        ASSERT_EQ(probes.size(), 2u);
        for (const GiReferenceProbe& probe : probes) {
            // Constant radiance L: irradiance / pi = L for every normal (only L0 is non-zero).
            const glm::dvec3 value = irradianceOverPi(probe, glm::dvec3(0, 1, 0));
            // Exact paths: float rounding of the sum over 2048 directions. Converged: Russian
            // roulette is unbiased but noisy: within 1 %.
            const double tolerance = bounces == 0 ? 0.01 : 1e-5;
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(value[c], e[c] * expected, tolerance * e[c] * expected) << "bounces " << bounces;
            for (size_t k = 1; k < 9; ++k)
                EXPECT_LT(glm::length(probe.irradianceSh[k]), (bounces == 0 ? 0.02 : 1e-4) * glm::length(glm::dvec3(e)) * expected);
        }
    }
}

TEST(GiReference, TheIndirectImageOfTheEmissiveBoxIsItsEmissionAtEveryPixel) {
    const glm::vec3 e(0.5f, 1.0f, 2.0f);
    const GiReference reference(emissiveBox(e, 0.25f));
    Camera camera = emissiveBox(e, 0.25f).camera;
    const ImageRGBAF image = reference.indirectIrradiance(camera, 16, 12, GiReferenceSettings{}.setBounces(2).setSamplesPerPixel(64));
    ASSERT_EQ(image.pixels.size(), 16u * 12u * 4u);
    // A wall's indirect light comes from the other walls, each sending e + 0.25 e after two bounces.
    for (size_t i = 0; i < image.pixels.size(); i += 4) {
        ASSERT_EQ(image.pixels[i + 3], 1.0f) << "pixel " << i / 4 << " sees nothing";
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(image.pixels[i + c], e[c] * 1.25, 1e-5 * e[c]);
    }
}

// A 200 m ground (albedo 0.5) under a 3 lux sun from straight above; no sky. Two black roofs:
// over x = 5 one facing down (the ground sees its front face), over x = -5 one facing up (the
// ground sees its back face).
Scene litGround(bool occluder) {
    Scene scene;
    scene.environment.ambientColor = glm::vec3(0.0f);
    addQuad(scene, detail::addMaterial(scene, "ground", glm::vec3(0.5f), 0.0f, 1.0f), glm::vec3(0.0f), glm::vec3(0, 1, 0), 200.0f);
    if (occluder) {
        const int32_t roof = detail::addMaterial(scene, "roof", glm::vec3(0.0f), 0.0f, 1.0f);
        addQuad(scene, roof, glm::vec3(5, 3, 0), glm::vec3(0, -1, 0), 2.0f);
        addQuad(scene, roof, glm::vec3(-5, 3, 0), glm::vec3(0, 1, 0), 2.0f);
    }
    Light sun;
    sun.type = LightType::Directional;
    sun.intensity = 3.0f;
    sun.direction = glm::vec3(0.0f, -1.0f, 0.0f);
    scene.lights.push_back(sun);
    return scene;
}

TEST(GiReference, ASunLitGroundSendsAlbedoTimesIrradianceOverPiAndShadowsFollowTheShadowMapsCulling) {
    const GiReference reference(litGround(true));
    const glm::dvec3 lit = reference.incidentRadiance(glm::vec3(0, 1, 0), glm::vec3(0, -1, 0), 1, 7);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(lit[c], 0.5 * 3.0 / kPi, 1e-6);
    // Under the roof facing up (the sun meets its front face): in its shadow, nothing.
    EXPECT_EQ(reference.incidentRadiance(glm::vec3(-5, 1, 0), glm::vec3(0, -1, 0), 1, 7), glm::dvec3(0.0));
    // Under the roof facing down (the sun meets its back face) the light passes, as the renderer's
    // shadow map culls single-sided back faces from the light's side: lit.
    const glm::dvec3 throughBackFace = reference.incidentRadiance(glm::vec3(5, 1, 0), glm::vec3(0, -1, 0), 1, 7);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(throughBackFace[c], 0.5 * 3.0 / kPi, 1e-6);
    // Looking up at the upward roof's underside, a back face of a single-sided material: it sends nothing.
    EXPECT_EQ(reference.incidentRadiance(glm::vec3(-5, 1, 0), glm::vec3(0, 1, 0), 1, 7), glm::dvec3(0.0));
    // A probe 1 m above the open ground: the lower hemisphere sends 0.5 * 3 / pi (nearly all of
    // it: the ground is 200 m wide), the upper nothing. Irradiance / pi facing down is that too;
    // L2 SH of a hemisphere step, evaluated at its pole, is within a few % of it.
    const auto probes = reference.probes(std::vector<glm::vec3>{glm::vec3(-20, 1, 0)}, GiReferenceSettings{}.setBounces(1));
    ASSERT_EQ(probes.size(), 1u);
    EXPECT_NEAR(irradianceOverPi(probes[0], glm::dvec3(0, -1, 0)).g, 0.5 * 3.0 / kPi, 0.05 * 0.5 * 3.0 / kPi);
    EXPECT_LT(irradianceOverPi(probes[0], glm::dvec3(0, 1, 0)).g, 0.05 * 0.5 * 3.0 / kPi);
}

TEST(GiReference, APointLightLightsWithTheRenderersAttenuationAndCone) {
    Scene scene;
    scene.environment.ambientColor = glm::vec3(0.0f);
    addQuad(scene, detail::addMaterial(scene, "ground", glm::vec3(1.0f), 0.0f, 1.0f), glm::vec3(0.0f), glm::vec3(0, 1, 0), 20.0f);
    Light point;
    point.type = LightType::Point;
    point.intensity = 8.0f;
    point.color = glm::vec3(1.0f, 0.5f, 0.25f);
    point.position = glm::vec3(0.0f, 2.0f, 0.0f);
    point.range = 4.0f;
    scene.lights.push_back(point);
    const GiReference reference(scene);
    // Seen from beside the light: the spot below it receives I / d^2 x window(d / range)^2.
    const glm::vec3 eye(0.0f, 1.0f, 0.0f);
    const glm::dvec3 value = reference.incidentRadiance(eye, glm::vec3(0, -1, 0), 1, 1);
    const double ratio = 2.0 / 4.0, window = 1.0 - std::pow(ratio, 4.0);
    const double irradiance = 8.0 / 4.0 * window * window;
    EXPECT_NEAR(value.r, irradiance / kPi, 1e-6);
    EXPECT_NEAR(value.g, 0.5 * irradiance / kPi, 1e-6);
    // Past the range: dark.
    EXPECT_EQ(reference.incidentRadiance(glm::vec3(5.0f, 1.0f, 0.0f), glm::vec3(0, -1, 0), 1, 1), glm::dvec3(0.0));
}

TEST(GiReference, RaysThatLeaveBringTheSkyOrTheAmbientColour) {
    Scene empty;
    empty.environment.ambientColor = glm::vec3(0.1f, 0.2f, 0.3f);
    const GiReference ambient(empty);
    EXPECT_EQ(ambient.incidentRadiance(glm::vec3(0.0f), glm::vec3(0, 0, 1), 0, 1), glm::dvec3(glm::vec3(0.1f, 0.2f, 0.3f)));
    // A sky whose upper half is 4 and lower half 1 (equirect rows: top = up), intensity 0.5.
    auto sky = std::make_shared<ImageRGBAF>(ImageRGBAF{16, 8, std::vector<float>(16 * 8 * 4, 1.0f)});
    for (uint32_t y = 0; y < 4; ++y)
        for (uint32_t x = 0; x < 16; ++x)
            for (int c = 0; c < 3; ++c) sky->pixels[(y * 16 + x) * 4 + c] = 4.0f;
    Scene skyScene;
    skyScene.environment.image = sky;
    skyScene.environment.intensity = 0.5f;
    const GiReference withSky(skyScene);
    EXPECT_NEAR(withSky.incidentRadiance(glm::vec3(0.0f), glm::vec3(0, 1, 0), 1, 1).g, 2.0, 1e-6);
    EXPECT_NEAR(withSky.incidentRadiance(glm::vec3(0.0f), glm::vec3(0, -1, 0), 1, 1).g, 0.5, 1e-6);
}

TEST(GiReference, BackFacesSendNothingAndMirroredInstancesKeepTheirFrontSide) {
    for (bool mirrored : {false, true}) {
        Scene scene;
        scene.environment.ambientColor = glm::vec3(0.0f);
        const int32_t glow = detail::addMaterial(scene, "glow", glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(2.0f));
        addQuad(scene, glow, glm::vec3(0, 0, -1), glm::vec3(0, 0, 1), 2.0f, mirrored);   // faces the origin
        addQuad(scene, glow, glm::vec3(0, 0, 1), glm::vec3(0, 0, 1), 2.0f, mirrored);    // its back to the origin
        const GiReference reference(scene);
        EXPECT_EQ(reference.incidentRadiance(glm::vec3(0.0f), glm::vec3(0, 0, -1), 1, 1), glm::dvec3(2.0)) << "mirrored " << mirrored;
        EXPECT_EQ(reference.incidentRadiance(glm::vec3(0.0f), glm::vec3(0, 0, 1), 1, 1), glm::dvec3(0.0)) << "mirrored " << mirrored;
    }
    // Double-sided: both sides glow.
    Scene scene;
    scene.environment.ambientColor = glm::vec3(0.0f);
    const int32_t glow = detail::addMaterial(scene, "glow", glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(2.0f));
    scene.materials[size_t(glow)].doubleSided = true;
    addQuad(scene, glow, glm::vec3(0, 0, 1), glm::vec3(0, 0, 1), 2.0f);
    EXPECT_EQ(GiReference(scene).incidentRadiance(glm::vec3(0.0f), glm::vec3(0, 0, 1), 1, 1), glm::dvec3(2.0));
}

TEST(GiReference, ResultsDependOnTheSeedNotOnTheThreads) {
    const Scene scene = emissiveBox(glm::vec3(1.0f), 0.7f);
    const GiReference reference(scene);
    const std::vector<glm::vec3> positions = {glm::vec3(0.1f), glm::vec3(-0.4f, 0.2f, 0.0f), glm::vec3(0.5f, -0.5f, 0.5f)};
    const GiReferenceSettings settings = GiReferenceSettings{}.setBounces(0).setDirectionsPerProbe(256);
    const auto one = reference.probes(positions, GiReferenceSettings(settings).setThreads(1));
    const auto two = reference.probes(positions, GiReferenceSettings(settings).setThreads(2));
    const auto other = reference.probes(positions, GiReferenceSettings(settings).setThreads(2).setSeed(2));
    bool seedMatters = false;
    for (size_t p = 0; p < positions.size(); ++p)
        for (size_t k = 0; k < 9; ++k) {
            EXPECT_EQ(one[p].radianceSh[k], two[p].radianceSh[k]);
            seedMatters = seedMatters || one[p].radianceSh[k] != other[p].radianceSh[k];
        }
    EXPECT_TRUE(seedMatters) << "converged paths use Russian roulette: another seed must change something";
}

TEST(GiReference, ErrorMeasuresAreRelativeAndSkipInvalidProbesAndEmptyPixels) {
    GiReferenceProbe ref;
    ref.irradianceSh[0] = glm::dvec3(1.0 / 0.28209479177387814);   // irradiance / pi = 1 everywhere
    IrradianceProbe same, brighter, invalid;
    same.valid = brighter.valid = true;
    same.sh[0] = glm::vec3(ref.irradianceSh[0]);
    brighter.sh[0] = glm::vec3(ref.irradianceSh[0] * 1.1);
    invalid.sh[0] = glm::vec3(1000.0f);
    EXPECT_NEAR(compareProbeIrradiance(std::vector<IrradianceProbe>{same}, std::vector<GiReferenceProbe>{ref}).relativeRmse, 0.0, 1e-6);
    const GiError error = compareProbeIrradiance(std::vector<IrradianceProbe>{brighter, invalid}, std::vector<GiReferenceProbe>{ref, ref}, 16);
    EXPECT_NEAR(error.relativeRmse, 0.1, 1e-5);   // the invalid probe is not compared
    EXPECT_NEAR(error.relativeBias, 0.1, 1e-5);
    EXPECT_EQ(error.compared, 16u);
    EXPECT_THROW(compareProbeIrradiance(std::vector<IrradianceProbe>{same}, std::vector<GiReferenceProbe>{}), RendererError);

    ImageRGBAF reference{2, 1, {1.0f, 1.0f, 1.0f, 1.0f, 5.0f, 5.0f, 5.0f, 0.0f}};
    ImageRGBAF rendered{2, 1, {0.5f, 0.5f, 0.5f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f}};
    const GiError image = compareIndirectImage(rendered, reference);
    EXPECT_EQ(image.compared, 1u);   // the second pixel sees nothing in the reference
    EXPECT_NEAR(image.relativeRmse, 0.5, 1e-6);
    EXPECT_NEAR(image.relativeBias, -0.5, 1e-6);
    EXPECT_THROW(compareIndirectImage(ImageRGBAF{1, 1, {0, 0, 0, 0}}, reference), RendererError);
}

TEST(GiReference, TheBiasSaysWhichWayTheErrorLeansWhereTheRmseCannot) {
    const ImageRGBAF reference{3, 1, {1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 2.0f, 2.0f, 2.0f, 1.0f}};
    // As bright as the reference overall (errors of both signs), and 20 % too dark in one channel.
    const GiError balanced = compareIndirectImage(ImageRGBAF{3, 1, {1.5f, 1.5f, 1.5f, 1.0f, 0.5f, 0.5f, 0.5f, 1.0f, 2.0f, 2.0f, 2.0f, 1.0f}},
                                                  reference);
    EXPECT_GT(balanced.relativeRmse, 0.2);
    EXPECT_NEAR(balanced.relativeBias, 0.0, 1e-6);
    const GiError darkRed = compareIndirectImage(ImageRGBAF{3, 1, {0.2f, 1.0f, 1.0f, 1.0f, 0.2f, 1.0f, 1.0f, 1.0f, 0.4f, 2.0f, 2.0f, 1.0f}},
                                                 reference);
    EXPECT_NEAR(darkRed.relativeBias, -0.8 / 3.0, 1e-6);
    // No light in the reference: any light at all is infinitely too bright, none is no bias.
    const ImageRGBAF black{1, 1, {0.0f, 0.0f, 0.0f, 1.0f}};
    EXPECT_EQ(compareIndirectImage(black, black).relativeBias, 0.0);
    EXPECT_EQ(compareIndirectImage(ImageRGBAF{1, 1, {0.1f, 0.0f, 0.0f, 1.0f}}, black).relativeBias, std::numeric_limits<double>::infinity());
}

// A directional light lights only the meshes whose rendering layers share a bit with its own, as
// in forward shading (it lit every mesh).
TEST(GiReference, ADirectionalLightLightsOnlyItsRenderingLayers) {
    for (const uint32_t lightLayers : {1u, 2u, 3u}) {
        Scene scene;
        scene.environment.ambientColor = glm::vec3(0.0f);
        const int32_t grey = detail::addMaterial(scene, "ground", glm::vec3(0.5f), 0.0f, 1.0f);
        scene.instances.push_back(Instance{detail::addMesh(scene, detail::makeQuad(grey)),
                                           glm::rotate(glm::scale(glm::mat4(1.0f), glm::vec3(10.0f)), -glm::half_pi<float>(), glm::vec3(1, 0, 0)),
                                           2u, "ground"});
        Light sun;
        sun.direction = glm::vec3(0.0f, -1.0f, 0.0f);
        sun.intensity = 2.0f;
        sun.renderingLayers = lightLayers;
        scene.lights.push_back(sun);
        const GiReference reference(scene);
        const glm::dvec3 seen = reference.incidentRadiance(glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0.0f, -1.0f, 0.0f), 1, 1);
        const double expected = (lightLayers & 2u) != 0 ? 0.5 / 3.14159265358979 * 2.0 : 0.0;
        EXPECT_NEAR(seen.g, expected, 1e-9) << "light layers " << lightLayers;
    }
}

TEST(GiReference, BadSettingsAreClearErrors) {
    const GiReference reference(emissiveBox(glm::vec3(1.0f), 0.5f));
    const std::vector<glm::vec3> one = {glm::vec3(0.0f)};
    EXPECT_THROW(reference.probes(one, GiReferenceSettings{}.setDirectionsPerProbe(0)), RendererError);
    EXPECT_THROW(reference.probes(one, GiReferenceSettings{}.setBounces(kGiReferenceMaxBounces + 1)), RendererError);
    EXPECT_THROW(reference.indirectIrradiance(Camera{}, 0, 4, GiReferenceSettings{}), RendererError);
    EXPECT_THROW(reference.indirectIrradiance(Camera{}, 4, 4, GiReferenceSettings{}.setSamplesPerPixel(0)), RendererError);
}

}  // namespace
}  // namespace janus::renderer
