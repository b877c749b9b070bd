// Absolute correctness, not only parity: parity compares configurations with each other, so a bug
// they share passes everywhere. Here chosen pixels of simple scenes must hold the radiance that
// the BRDF gives when it is evaluated on the CPU in double precision from the known geometry:
// the ray through the pixel's centre hits the same triangles the rasteriser covers, the normal
// is interpolated from the same vertex normals, and the material, lights and ambient colour are
// the scene's. Scenes: a sphere on a floor under one directional light (lit pixels, and pixels in
// the sphere's shadow with the shadow map on and off), and a floor under one point and one spot
// light. On every configuration.
//
// What the reference writes down is the renderer's documented model (docs/LIGHTING.md): GGX
// distribution, height-correlated Smith visibility, Schlick Fresnel, Lambert diffuse times
// (1 - F); local lights fall off as 1/d^2 times a window (1 - (d/range)^4)^2 and spot lights
// times the squared cone ramp; the uniform ambient colour lights diffuse + f0.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "janus/renderer/light_grid.h"
#include "janus/renderer/renderer.h"
#include "renderer/renderer_test_support.h"
#include "scene/scene_internal.h"

namespace janus::renderer {
namespace {

using test_support::Config;
using dvec3 = glm::dvec3;

constexpr double kPi = 3.14159265358979323846;
// The bound: every checked channel's shading within 1e-3 of the reference, relative, on
// top of the RGBA16F target's own rounding (one half unit in the last place: up to 2^-10, about
// 1e-3 relative by itself at the bottom of a binade, where a truncating driver would use up the
// whole bound before any shading error).
constexpr double kRelativeTolerance = 1e-3;

// What storing `value` in the RGBA16F HDR target and the GPU's arithmetic may change it by, in
// units in the last place of a half (10 fraction bits). Drivers may round towards zero (lavapipe
// and llvmpipe do: every value read back is the reference or the half just below it), so one
// unit is storage alone. NVIDIA (H200, driver 580, all five configurations) was up to 1.1 units
// off on a few lit pixels: its fp32 transcendentals (pow, exp2, inversesqrt) are approximations
// within GLSL's ULP bounds, which put the value a little past one half step. Two units leave
// room for that; kRelativeTolerance, the bound, still applies to every value.
constexpr double kHalfUnitsInTheLastPlace = 2.0;
double halfUnitInTheLastPlace(double value) {
    const double magnitude = std::max(std::abs(value), std::ldexp(1.0, -14));   // halves are subnormal below
    return std::ldexp(1.0, std::ilogb(magnitude) - 10);
}
double hdrTolerance(double value) { return kHalfUnitsInTheLastPlace * halfUnitInTheLastPlace(value) + 1e-5 * std::abs(value); }

struct Hit {
    double t = 0.0;
    dvec3 position{0.0};
    dvec3 normal{0.0};   // interpolated, normalised, world space
    uint32_t instance = 0;
};

// Möller-Trumbore over every triangle of every instance, in double precision.
std::optional<Hit> intersect(const Scene& scene, const dvec3& origin, const dvec3& direction) {
    std::optional<Hit> best;
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& instance = scene.instances[i];
        const glm::dmat4 world(instance.world);
        const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(world)));
        const Mesh& mesh = scene.meshes[instance.mesh];
        for (size_t k = 0; k + 2 < mesh.indices.size(); k += 3) {
            const Vertex* v[3] = {&mesh.vertices[mesh.indices[k]], &mesh.vertices[mesh.indices[k + 1]],
                                  &mesh.vertices[mesh.indices[k + 2]]};
            dvec3 p[3];
            for (int c = 0; c < 3; ++c) p[c] = dvec3(world * glm::dvec4(dvec3(v[c]->position), 1.0));
            const dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
            const dvec3 q = glm::cross(direction, e2);
            const double det = glm::dot(e1, q);
            if (std::abs(det) < 1e-14) continue;
            const dvec3 s = origin - p[0];
            const double b1 = glm::dot(s, q) / det;
            const dvec3 r = glm::cross(s, e1);
            const double b2 = glm::dot(direction, r) / det;
            const double t = glm::dot(e2, r) / det;
            if (b1 < 0.0 || b2 < 0.0 || b1 + b2 > 1.0 || t <= 1e-9 || (best && t >= best->t)) continue;
            const double b0 = 1.0 - b1 - b2;
            const dvec3 n = normalMatrix * (b0 * dvec3(v[0]->normal) + b1 * dvec3(v[1]->normal) + b2 * dvec3(v[2]->normal));
            best = Hit{t, origin + t * direction, glm::normalize(n), i};
        }
    }
    return best;
}

// The ray through the centre of pixel (x, y), row 0 on top (NDC y = -1 there: docs/ARCHITECTURE.md).
struct Ray {
    dvec3 origin;
    dvec3 direction;
};
Ray pixelRay(const Camera& camera, uint32_t width, uint32_t height, uint32_t x, uint32_t y) {
    const glm::dmat4 inverseViewProjection =
        glm::inverse(glm::dmat4(makeProjection(camera, width, height)) * glm::dmat4(makeView(camera)));
    const double ndcX = (x + 0.5) / width * 2.0 - 1.0;
    const double ndcY = (y + 0.5) / height * 2.0 - 1.0;
    auto unproject = [&](double depth) {
        const glm::dvec4 p = inverseViewProjection * glm::dvec4(ndcX, ndcY, depth, 1.0);
        return dvec3(p) / p.w;
    };
    const dvec3 nearPoint = unproject(0.0), farPoint = unproject(1.0);
    return {dvec3(camera.position), glm::normalize(farPoint - nearPoint)};
}

struct SurfaceD {
    dvec3 normal, view, diffuseColor, f0;
    double alpha;
};

SurfaceD surfaceAt(const Scene& scene, const Hit& hit) {
    const Mesh& mesh = scene.meshes[scene.instances[hit.instance].mesh];
    const Material& material = scene.materials.at(size_t(mesh.material));
    const dvec3 base(material.baseColorFactor);
    const double metallic = std::clamp(double(material.metallicFactor), 0.0, 1.0);
    const double roughness = std::clamp(double(material.roughnessFactor), 0.045, 1.0);
    SurfaceD s;
    s.normal = hit.normal;
    s.view = glm::normalize(dvec3(scene.camera.position) - hit.position);
    s.diffuseColor = base * (1.0 - metallic);
    s.f0 = glm::mix(dvec3(0.04), base, metallic);
    s.alpha = roughness * roughness;
    return s;
}

// Outgoing radiance for irradiance `irradiance` (at normal incidence) arriving from `toLight`.
dvec3 brdfTimesCosine(const SurfaceD& s, const dvec3& toLight, const dvec3& irradiance) {
    const double NoL = std::clamp(glm::dot(s.normal, toLight), 0.0, 1.0);
    if (NoL <= 0.0) return dvec3(0.0);
    const dvec3 h = glm::normalize(toLight + s.view);
    const double NoV = std::clamp(std::abs(glm::dot(s.normal, s.view)), 1e-4, 1.0);
    const double NoH = std::clamp(glm::dot(s.normal, h), 0.0, 1.0);
    const double VoH = std::clamp(glm::dot(s.view, h), 0.0, 1.0);
    const double a2 = s.alpha * s.alpha;
    const double f = NoH * NoH * (a2 - 1.0) + 1.0;
    const double D = a2 / (kPi * f * f);
    const double V = 0.5 / (NoL * std::sqrt(NoV * NoV * (1.0 - a2) + a2) + NoV * std::sqrt(NoL * NoL * (1.0 - a2) + a2));
    const dvec3 F = s.f0 + (dvec3(1.0) - s.f0) * std::pow(1.0 - VoH, 5.0);
    const dvec3 diffuse = (dvec3(1.0) - F) * s.diffuseColor / kPi;
    return (diffuse + F * (D * V)) * irradiance * NoL;
}

// Irradiance at normal incidence from a point or spot light at `position` (glTF units).
dvec3 localLightIrradiance(const Light& light, const dvec3& position, dvec3& toLight) {
    const dvec3 d = dvec3(light.position) - position;
    const double distanceSq = glm::dot(d, d);
    toLight = d / std::sqrt(distanceSq);
    const double range = light.range.value();
    const double ratio4 = (distanceSq / (range * range)) * (distanceSq / (range * range));
    const double window = std::clamp(1.0 - ratio4, 0.0, 1.0);
    double attenuation = window * window / distanceSq;
    if (light.type == LightType::Spot) {
        const double cosOuter = std::cos(double(light.outerConeAngle));
        const double cosInner = std::cos(double(std::min(light.innerConeAngle, light.outerConeAngle)));
        const double cd = glm::dot(glm::normalize(dvec3(light.direction)), -toLight);
        const double cone = std::clamp((cd - cosOuter) / (cosInner - cosOuter), 0.0, 1.0);
        attenuation *= cone * cone;
    }
    return dvec3(light.color) * double(light.intensity) * attenuation;
}

// What the renderer should write at `hit`; `shadowed`: the directional light is blocked there.
dvec3 expectedRadiance(const Scene& scene, const Hit& hit, bool shadowed) {
    const SurfaceD s = surfaceAt(scene, hit);
    dvec3 radiance = dvec3(scene.environment.ambientColor) * (s.diffuseColor + s.f0);
    for (const Light& light : scene.lights) {
        if (light.type == LightType::Directional) {
            if (!shadowed)
                radiance += brdfTimesCosine(s, -glm::normalize(dvec3(light.direction)), dvec3(light.color) * double(light.intensity));
        } else {
            dvec3 toLight;
            const dvec3 irradiance = localLightIrradiance(light, hit.position, toLight);
            radiance += brdfTimesCosine(s, toLight, irradiance);
        }
    }
    return radiance;
}

enum class ShadowState { Lit, Shadowed, Either };

struct PixelCheck {
    uint32_t x, y;
    dvec3 expected;
};

// How the comparison went over all the chosen pixels.
struct Comparison {
    size_t checked = 0;
    size_t failed = 0;
    double worst = 0.0;
    std::string firstFailure;
};

Comparison compare(const ImageRGBAF& hdr, const std::vector<PixelCheck>& checks) {
    Comparison result;
    for (const PixelCheck& check : checks) {
        const size_t at = (size_t(check.y) * hdr.width + check.x) * 4;
        ++result.checked;
        for (int c = 0; c < 3; ++c) {
            const double actual = hdr.pixels[at + c];
            const double expected = check.expected[c];
            const double difference = std::abs(actual - expected);
            const double error = std::max(difference - halfUnitInTheLastPlace(expected), 0.0) / std::max(std::abs(expected), 1e-6);
            result.worst = std::max(result.worst, error);
            if (!(difference <= hdrTolerance(expected)) || !(error <= kRelativeTolerance)) {
                if (result.failed == 0)
                    result.firstFailure = fmt::format("pixel ({}, {}) channel {}: {} instead of {} (relative error {:.2e}, "
                                                      "{:.2e} beyond the half's rounding, {:.1f} half units in the last place)",
                                                      check.x, check.y, c, actual, expected, difference / std::max(std::abs(expected), 1e-6),
                                                      error, difference / halfUnitInTheLastPlace(expected));
                ++result.failed;
                break;
            }
        }
    }
    return result;
}

// Every fourth pixel whose ray, and the rays of its 4 neighbours, hit the same instance (no
// silhouettes), where the surface faces the directional light by at least `minNoL` (away from
// the terminator, where the shadow map's bias decides) and `wantShadow` holds for the shadow
// ray: `isShadowed` says whether the directional light is blocked with a margin either way
// (nullopt: too close to the shadow's edge to say).
template <class ShadowTest>
std::vector<PixelCheck> choosePixels(const Scene& scene, uint32_t size, ShadowState want, bool shadowsOn,
                                     ShadowTest isShadowed, double minNoL = 0.3) {
    std::vector<PixelCheck> checks;
    std::optional<dvec3> toSun;
    for (const Light& light : scene.lights)
        if (light.type == LightType::Directional) toSun = -glm::normalize(dvec3(light.direction));
    for (uint32_t y = 2; y + 2 < size; y += 4) {
        for (uint32_t x = 2; x + 2 < size; x += 4) {
            const Ray ray = pixelRay(scene.camera, size, size, x, y);
            const std::optional<Hit> hit = intersect(scene, ray.origin, ray.direction);
            if (!hit) continue;
            bool interior = true;
            for (auto [dx, dy] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
                const Ray n = pixelRay(scene.camera, size, size, x + dx, y + dy);
                const std::optional<Hit> h = intersect(scene, n.origin, n.direction);
                interior = interior && h && h->instance == hit->instance;
            }
            if (!interior) continue;
            bool shadowed = false;
            if (toSun) {
                if (glm::dot(hit->normal, *toSun) < minNoL) continue;
                const std::optional<bool> blocked = isShadowed(hit->position, *toSun);
                if (!blocked) continue;
                if (want == ShadowState::Lit && *blocked) continue;
                if (want == ShadowState::Shadowed && !*blocked) continue;
                shadowed = *blocked && shadowsOn;
            }
            checks.push_back({x, y, expectedRadiance(scene, *hit, shadowed)});
        }
    }
    return checks;
}

// --- scenes ----------------------------------------------------------------------------------

Camera cameraAt(glm::vec3 position, glm::vec3 target) {
    Camera camera;
    camera.position = position;
    camera.target = target;
    camera.nearPlane = 0.1f;
    camera.farPlane = 30.0f;
    return camera;
}

constexpr dvec3 kSphereCentre{0.0, 0.0, 0.0};
constexpr double kSphereRadius = 1.0;

Scene sphereOnFloor() {
    Scene scene;
    detail::addMaterial(scene, "sphere", {0.8f, 0.35f, 0.2f}, 0.3f, 0.45f);
    detail::addMaterial(scene, "floor", {0.5f, 0.55f, 0.6f}, 0.0f, 0.8f);
    // Fine enough that the silhouette is round at 128 px; the reference uses these very triangles.
    scene.meshes = {detail::makeSphere(0, 96, 48), detail::makeQuad(1)};
    scene.instances = {Instance{0, glm::translate(glm::mat4(1.0f), glm::vec3(kSphereCentre))},
                       Instance{1, test_support::quadFacing({0.0f, -1.0f, 0.0f}, {0, 1, 0}, 12.0f)}};
    Light sun;
    sun.direction = glm::normalize(glm::vec3(0.45f, -1.0f, 0.3f));
    sun.color = {1.0f, 0.9f, 0.8f};
    sun.intensity = 3.0f;
    scene.lights = {sun};
    scene.environment.ambientColor = glm::vec3(0.05f, 0.06f, 0.08f);
    scene.camera = cameraAt({0.3f, 1.6f, 4.2f}, {0.4f, -0.6f, 0.0f});
    return scene;
}

// The sphere blocks the sun where the ray towards it passes within the radius of the centre;
// 0.08 m either side of the edge (a few shadow-map texels, the PCF kernel) is left unjudged.
std::optional<bool> sphereShadows(const dvec3& position, const dvec3& toSun) {
    const dvec3 toCentre = kSphereCentre - position;
    const double along = glm::dot(toCentre, toSun);
    if (along <= 0.0) return false;   // the sphere is behind the point, seen from the sun
    const double distance = glm::length(toCentre - along * toSun);
    if (distance > kSphereRadius + 0.08) return false;
    if (distance < kSphereRadius - 0.08) return true;
    return std::nullopt;
}

Scene floorUnderPointAndSpot() {
    Scene scene;
    detail::addMaterial(scene, "floor", {0.7f, 0.65f, 0.6f}, 0.2f, 0.5f);
    scene.meshes = {detail::makeQuad(0)};
    scene.instances = {Instance{0, test_support::quadFacing({0.0f, 0.0f, 0.0f}, {0, 1, 0}, 8.0f)}};
    scene.lights = {test_support::pointLight({-1.0f, 1.2f, 0.5f}, {1.0f, 0.8f, 0.6f}, 6.0f, 4.0f),
                    test_support::spotLight({1.1f, 1.6f, -0.4f}, glm::normalize(glm::vec3(-0.2f, -1.0f, 0.15f)),
                                            {0.5f, 0.7f, 1.0f}, 15.0f, 6.0f, 0.35f, 0.7f)};
    scene.environment.ambientColor = glm::vec3(0.02f);
    scene.camera = cameraAt({0.0f, 3.5f, 3.5f}, {0.0f, 0.0f, 0.0f});
    return scene;
}

// --- tests -----------------------------------------------------------------------------------

class AnalyticShadingTest : public test_support::ConfigTest {
protected:
    test_support::FrameOutput render(const Scene& scene, bool shadows) {
        RenderSettings settings = settingsOfSize(test_support::kSize, test_support::kSize);
        settings.lighting.shadows = shadows;
        return test_support::renderOneFrame(GetParam(), scene, settings);
    }
    void expectMatches(const ImageRGBAF& hdr, const std::vector<PixelCheck>& checks, size_t minimum, const std::string& what) {
        ASSERT_GE(checks.size(), minimum) << what << ": too few pixels could be judged; the scene or camera moved";
        const Comparison result = compare(hdr, checks);
        EXPECT_EQ(result.failed, 0u) << GetParam().name() << ", " << what << ": " << result.failed << " of "
                                     << result.checked << " pixels off by more than " << kHalfUnitsInTheLastPlace
                                     << " units in a half's last place (or " << kRelativeTolerance << " relative); first: " << result.firstFailure;
    }
};

TEST_P(AnalyticShadingTest, SphereAndFloorUnderADirectionalLight) {
    const Scene scene = sphereOnFloor();
    const test_support::FrameOutput frame = render(scene, true);
    ASSERT_TRUE(test_support::hasPassStartingWith(frame.report, "shadow-map")) << test_support::passNames(frame.report);
    expectMatches(frame.hdr, choosePixels(scene, test_support::kSize, ShadowState::Lit, true, sphereShadows), 200,
                  "lit pixels (sphere and floor)");
}

TEST_P(AnalyticShadingTest, FloorInTheSpheresShadowHasOnlyTheAmbientLight) {
    const Scene scene = sphereOnFloor();
    const test_support::FrameOutput frame = render(scene, true);
    expectMatches(frame.hdr, choosePixels(scene, test_support::kSize, ShadowState::Shadowed, true, sphereShadows), 20,
                  "shadowed floor pixels");
}

TEST_P(AnalyticShadingTest, WithoutTheShadowMapTheSameFloorIsLit) {
    const Scene scene = sphereOnFloor();
    const test_support::FrameOutput frame = render(scene, false);
    EXPECT_FALSE(test_support::hasPassStartingWith(frame.report, "shadow-map")) << test_support::passNames(frame.report);
    expectMatches(frame.hdr, choosePixels(scene, test_support::kSize, ShadowState::Shadowed, false, sphereShadows), 20,
                  "floor pixels the sphere would shadow");
    expectMatches(frame.hdr, choosePixels(scene, test_support::kSize, ShadowState::Lit, false, sphereShadows), 200,
                  "lit pixels (sphere and floor)");
}

TEST_P(AnalyticShadingTest, FloorUnderAPointAndASpotLight) {
    const Scene scene = floorUnderPointAndSpot();
    const test_support::FrameOutput frame = render(scene, true);
    auto noSun = [](const dvec3&, const dvec3&) { return std::optional<bool>(false); };
    const std::vector<PixelCheck> checks = choosePixels(scene, test_support::kSize, ShadowState::Either, true, noSun);
    expectMatches(frame.hdr, checks, 300, "floor pixels");
    // The scene must exercise both lights: some pixels inside the spot's cone, some only under
    // the point light (their expected radiance differs from ambient by each light's share).
    size_t inCone = 0;
    for (const PixelCheck& check : checks) {
        const Ray ray = pixelRay(scene.camera, test_support::kSize, test_support::kSize, check.x, check.y);
        const std::optional<Hit> hit = intersect(scene, ray.origin, ray.direction);
        dvec3 toLight;
        if (hit && localLightIrradiance(scene.lights[1], hit->position, toLight).b > 0.5) ++inCone;
    }
    EXPECT_GE(inCone, 20u) << "too few checked pixels are lit by the spot light";
}

INSTANTIATE_TEST_SUITE_P(Configs, AnalyticShadingTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
