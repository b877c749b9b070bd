// L2 spherical-harmonic irradiance (docs/IBL.md, "Spherical harmonics (L2)"): the CPU projection
// against closed forms, and ShIrradiance on every configuration (validation on) against the CPU
// double-precision reference, for analytic cubes, the shared HDR environment and hard cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>
#include <glm/gtc/packing.hpp>
#include <stb/stb_image.h>

#include "renderer_test_support.h"
// Internal to the renderer.
#include "core/pass_graph.h"
#include "ibl/sh_irradiance.h"
#include "ibl/spherical_harmonics.h"

namespace janus::renderer {
namespace {

using test_support::Config;

constexpr uint32_t kFace = 32;   // small cubes: the GPU paths run on llvmpipe / lavapipe

// L(w) = f(w) for every texel centre of a size^2 cube.
template <class F>
CubeImage cubeFrom(uint32_t size, F&& f) {
    CubeImage cube = CubeImage::filled(size, glm::vec4(0.0f));
    for (uint32_t face = 0; face < 6; ++face)
        for (uint32_t y = 0; y < size; ++y)
            for (uint32_t x = 0; x < size; ++x) cube.at(face, x, y) = glm::vec4(glm::vec3(f(cubeTexelDirection(face, x, y, size))), 1.0f);
    return cube;
}

// Fibonacci sphere: n roughly uniform unit directions.
std::vector<glm::dvec3> sphereDirections(uint32_t n) {
    std::vector<glm::dvec3> dirs;
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    for (uint32_t i = 0; i < n; ++i) {
        const double y = 1.0 - 2.0 * (i + 0.5) / n;
        const double r = std::sqrt(1.0 - y * y);
        dirs.emplace_back(r * std::cos(golden * i), y, r * std::sin(golden * i));
    }
    return dirs;
}

double maxAbsDifference(const ShRgb& a, const ShRgb& b) {
    double d = 0.0;
    for (uint32_t i = 0; i < 9; ++i)
        for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(a[i][c] - b[i][c]));
    return d;
}

void expectShNear(const ShRgb& expected, const ShRgb& actual, double tolerance, const std::string& label) {
    for (uint32_t i = 0; i < 9; ++i)
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(actual[i][c], expected[i][c], tolerance) << label << ": coefficient " << i << " channel " << c;
}

// --- CPU --------------------------------------------------------------------------------------

TEST(ShCpu, SolidAnglesCoverTheSphere) {
    for (uint32_t size : {1u, 2u, 7u, 32u}) {
        double sum = 0.0;
        for (uint32_t y = 0; y < size; ++y)
            for (uint32_t x = 0; x < size; ++x) sum += 6.0 * cubeTexelSolidAngle(x, y, size);
        EXPECT_NEAR(sum, 4.0 * std::numbers::pi, 1e-12) << size;
    }
    // One texel of a 1x1 face is a sixth of the sphere.
    EXPECT_NEAR(cubeTexelSolidAngle(0, 0, 1), 4.0 * std::numbers::pi / 6.0, 1e-14);
}

TEST(ShCpu, TexelDirectionsFollowTheFaceTable) {
    // Face centres look along the face axis; row 0 shows cubeFaceUp (scene_view.h).
    const glm::dvec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const glm::dvec3 ups[6] = {{0, 1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};
    for (uint32_t face = 0; face < 6; ++face) {
        EXPECT_NEAR(glm::distance(glm::normalize(cubeFacePointDirection(face, 0, 0)), axes[face]), 0.0, 1e-15) << face;
        EXPECT_NEAR(glm::distance(cubeFacePointDirection(face, 0, -1) - axes[face], ups[face]), 0.0, 1e-15) << face;
        // Column 0 shows the right of a camera looking along the axis with that up (mirrored face).
        const glm::dvec3 right = glm::cross(axes[face], ups[face]);
        EXPECT_NEAR(glm::distance(cubeFacePointDirection(face, -1, 0) - axes[face], right), 0.0, 1e-15) << face;
    }
}

TEST(ShCpu, BasisIsOrthonormalOnTheSampledSphere) {
    // Projecting the basis functions themselves: exact solid angles make this tight.
    const uint32_t size = 64;
    std::array<std::array<double, 9>, 9> gram{};
    for (uint32_t face = 0; face < 6; ++face)
        for (uint32_t y = 0; y < size; ++y)
            for (uint32_t x = 0; x < size; ++x) {
                const auto b = shBasis(cubeTexelDirection(face, x, y, size));
                const double w = cubeTexelSolidAngle(x, y, size);
                for (int i = 0; i < 9; ++i)
                    for (int j = 0; j < 9; ++j) gram[i][j] += b[i] * b[j] * w;
            }
    for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 9; ++j) EXPECT_NEAR(gram[i][j], i == j ? 1.0 : 0.0, 2e-3) << i << "," << j;
}

TEST(ShCpu, ConstantProjectsOntoL0Only) {
    const glm::dvec3 color(0.25, 1.0, 3.0);
    const CubeImage cube = CubeImage::filled(kFace, glm::vec4(glm::vec3(color), 1.0f));
    // Exact solid angles sum to 4 pi and the cube's symmetry cancels every other term.
    expectShNear(shConstantRadiance(color), shProjectRadiance(cube), 1e-12, "constant");
    // Irradiance / pi of a constant radiance c is c in every direction.
    const ShRgb irradiance = shProjectIrradiance(cube);
    for (const glm::dvec3& n : sphereDirections(64)) EXPECT_NEAR(glm::distance(shEvaluate(irradiance, n), color), 0.0, 1e-12);
}

TEST(ShCpu, LinearGradientProjectsOntoTheMatchingL1TermOnly) {
    const glm::dvec3 color(1.0, 0.5, 2.0);
    for (uint32_t axis = 0; axis < 3; ++axis) {
        const CubeImage cube = cubeFrom(kFace, [&](const glm::dvec3& w) { return color * w[axis]; });
        // Exact by symmetry (sum of w x^2 = 4 pi / 3); the texels hold floats (~6e-8 relative).
        expectShNear(shLinearGradientRadiance(axis, color), shProjectRadiance(cube), 1e-6, fmt::format("gradient axis {}", axis));
        // Irradiance / pi = (2/3) n[axis] color.
        const ShRgb irradiance = shProjectIrradiance(cube);
        for (const glm::dvec3& n : sphereDirections(32))
            EXPECT_NEAR(glm::distance(shEvaluate(irradiance, n), color * (2.0 / 3.0 * n[axis])), 0.0, 1e-6);
    }
}

TEST(ShCpu, ClampedCosineLobeMatchesTheClosedForm) {
    const glm::dvec3 color(2.0, 1.0, 0.5);
    const std::vector<glm::dvec3> axes = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1},
                                          glm::normalize(glm::dvec3(1, 2, -3))};
    for (const glm::dvec3& axis : axes) {
        const CubeImage cube = cubeFrom(kFace, [&](const glm::dvec3& w) { return color * std::max(0.0, glm::dot(axis, w)); });
        // The kink of max(0, cos) along the great circle is sampled at texel centres: the error is
        // quadrature, measured 2.5e-4 .. 8.9e-4 at 32^2 faces, i.e. at most 5e-4 of L00
        // (= pi * Y00 * 2 = 1.77 for red). Bound: 1e-3 of L00.
        const ShRgb projected = shProjectRadiance(cube);
        const double error = maxAbsDifference(shClampedCosineRadiance(axis, color), projected);
        std::printf("[ cosine lobe axis (%.2f, %.2f, %.2f) ] max |projected - closed form| = %.3g\n", axis.x, axis.y, axis.z, error);
        EXPECT_LT(error, 1e-3 * std::numbers::pi * kShY00 * 2.0) << "axis " << axis.x << "," << axis.y << "," << axis.z;
    }
}

TEST(ShCpu, ReconstructionRingsBelowZeroAndIsClamped) {
    // L2 truncation of a clamped-cosine lobe's irradiance: unclamped irradiance / pi at the
    // antipode is (1/4)(1 - 4/3 + 5/16) = -1/192 of the colour. shEvaluateIrradiance clamps it.
    const glm::dvec3 axis(0, 0, 1);
    const ShRgb irradiance = shConvolveIrradiance(shClampedCosineRadiance(axis, glm::dvec3(1.0)));
    EXPECT_NEAR(shEvaluate(irradiance, -axis).x, -1.0 / 192.0, 1e-12);
    EXPECT_EQ(shEvaluateIrradiance(irradiance, -axis).x, 0.0);
    // Facing the lobe: (1/4)(1 + 4/3 + 5/16 * 1) = 0.6614..., against the true 2/3.
    EXPECT_NEAR(shEvaluate(irradiance, axis).x, 0.25 * (1.0 + 4.0 / 3.0 + 5.0 / 16.0), 1e-12);
    for (const glm::dvec3& n : sphereDirections(256)) EXPECT_GE(shEvaluateIrradiance(irradiance, n).x, 0.0);
}

// --- Irradiance above a surface (shading normal bent from the surface's plane) ----------------

// A radiance SH with every coefficient set (deterministic, mixed signs), and its irradiance / pi.
ShRgb someRadiance() {
    ShRgb radiance{};
    for (uint32_t i = 0; i < 9; ++i)
        radiance[i] = glm::dvec3(std::sin(1.7 * i + 0.3), std::cos(2.3 * i + 1.1), std::sin(0.9 * i + 2.0)) * (i == 0 ? 4.0 : 1.0);
    return radiance;
}

// (1/pi) * integral of L(w) max(0, n.w) over the directions above the plane of g, by quadrature.
glm::dvec3 clippedLobeByQuadrature(const ShRgb& radiance, const glm::dvec3& n, const glm::dvec3& g, const std::vector<glm::dvec3>& directions) {
    glm::dvec3 sum(0.0);
    for (const glm::dvec3& w : directions) {
        const double cosine = glm::dot(n, w);
        if (cosine <= 0.0 || glm::dot(g, w) <= 0.0) continue;
        sum += shEvaluate(radiance, w) * cosine;
    }
    return sum * (4.0 * std::numbers::pi / double(directions.size())) / std::numbers::pi;
}

// n leaning `degrees` away from g, about a fixed skew axis.
glm::dvec3 leaning(const glm::dvec3& g, double degrees) {
    const glm::dvec3 tangent = glm::normalize(glm::cross(g, glm::normalize(glm::dvec3(0.3, -0.5, 0.8))));
    const double radians = degrees * std::numbers::pi / 180.0;
    return std::cos(radians) * g + std::sin(radians) * tangent;
}

TEST(ShCpu, AboveSurfaceIsThePlainEvaluationWhenTheNormalsAgree) {
    // dot(n, n) of a unit vector in double is 1 within 1e-16, so acos sees an angle near 1e-8:
    // the clipped sliver that leaves is of that size. Bound: 1e-7.
    const ShRgb irradiance = shConvolveIrradiance(someRadiance());
    for (const glm::dvec3& n : sphereDirections(64)) {
        const glm::dvec3 plain = shEvaluate(irradiance, n), above = shEvaluateAboveSurface(irradiance, n, n);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(above[c], plain[c], 1e-7) << "normal " << n.x << "," << n.y << "," << n.z;
    }
}

TEST(ShCpu, AboveSurfaceMatchesTheClippedLobeByQuadrature) {
    // The closed form against the integral it stands for. The integrand jumps where the surface's
    // plane cuts the lobe; 2^20 Fibonacci directions put the quadrature within 1e-4 of the
    // largest values here (measured below 3e-5). Bound: 2e-4.
    const ShRgb radiance = someRadiance();
    const ShRgb irradiance = shConvolveIrradiance(radiance);
    const std::vector<glm::dvec3> directions = sphereDirections(1u << 20);
    double worst = 0.0;
    for (const glm::dvec3& g : {glm::dvec3(0, 1, 0), glm::normalize(glm::dvec3(-2, 1, 3))})
        for (double degrees : {0.0, 5.0, 30.0, 45.0, 60.0, 89.0, 120.0, 175.0}) {
            const glm::dvec3 n = leaning(g, degrees);
            const glm::dvec3 expected = clippedLobeByQuadrature(radiance, n, g, directions), actual = shEvaluateAboveSurface(irradiance, n, g);
            for (int c = 0; c < 3; ++c) {
                worst = std::max(worst, std::abs(actual[c] - expected[c]));
                EXPECT_NEAR(actual[c], expected[c], 2e-4) << degrees << " degrees from (" << g.x << "," << g.y << "," << g.z << "), channel " << c;
            }
        }
    std::printf("[ above surface ] max |closed form - quadrature| = %.3g\n", worst);
}

TEST(ShCpu, AboveSurfaceKeepsOnlyTheUpperPartOfAUniformSky) {
    // Uniform radiance: the clipped lobe's solid-angle weight, pi (1 + cos theta) / 2, exactly.
    const glm::dvec3 color(1.0, 0.5, 0.25);
    const ShRgb irradiance = shConvolveIrradiance(shConstantRadiance(color));
    const glm::dvec3 g(0, 0, 1);
    for (double degrees : {0.0, 30.0, 45.0, 90.0, 135.0, 180.0}) {
        const double expected = 0.5 * (1.0 + std::cos(degrees * std::numbers::pi / 180.0));
        const glm::dvec3 actual = shEvaluateAboveSurface(irradiance, leaning(g, degrees), g);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(actual[c], expected * color[c], 1e-12) << degrees << " degrees";
    }
}

TEST(ShCpu, AboveSurfaceIsContinuousAsTheNormalsMeet) {
    // The tangent is undefined when the normals agree; any choice gives the clamped cosine's
    // moments there, so nearly equal normals give nearly the plain evaluation: the sliver the
    // surface hides grows with the angle (measured 0.12 x the angle in radians for this radiance;
    // bound: the angle in radians, + 1e-7 as above).
    const ShRgb irradiance = shConvolveIrradiance(someRadiance());
    const glm::dvec3 g = glm::normalize(glm::dvec3(1, -2, 0.5));
    const glm::dvec3 plain = shEvaluate(irradiance, g);
    for (double degrees : {1e-9, 1e-6, 1e-3}) {
        const glm::dvec3 above = shEvaluateAboveSurface(irradiance, leaning(g, degrees), g);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(above[c], plain[c], degrees * std::numbers::pi / 180.0 + 1e-7) << degrees << " degrees";
    }
}

// --- The shared HDR environment, resampled to a small cube on the CPU ----------------------

// Nearest texel of the equirectangular image along w (u from atan2(x, -z), v from the polar angle).
std::optional<CubeImage> hdrEnvironmentCube(uint32_t size) {
    const std::string path = std::string(JANUS_SHARED_SCENES_DIR) + "/env/chinese_garden_1k.hdr";
    int width = 0, height = 0, channels = 0;
    float* pixels = stbi_loadf(path.c_str(), &width, &height, &channels, 3);
    if (!pixels) return std::nullopt;
    const CubeImage cube = cubeFrom(size, [&](const glm::dvec3& w) {
        const double u = std::atan2(w.x, -w.z) / (2.0 * std::numbers::pi) + 0.5;
        const double v = std::acos(std::clamp(w.y, -1.0, 1.0)) / std::numbers::pi;
        const int px = std::clamp(int(u * width), 0, width - 1), py = std::clamp(int(v * height), 0, height - 1);
        const float* p = pixels + (size_t(py) * width + px) * 3;
        return glm::dvec3(p[0], p[1], p[2]);
    });
    stbi_image_free(pixels);
    return cube;
}

TEST(ShCpu, HdrEnvironmentIrradianceStaysPositive) {
    const std::optional<CubeImage> cube = hdrEnvironmentCube(kFace);
    ASSERT_TRUE(cube) << "the shared HDR environment is missing: the suite runs with ../shared beside the repository";
    const ShRgb irradiance = shProjectIrradiance(*cube);
    // Unclamped: a real sky is smooth enough that L2 never rings below zero; and the SH stays
    // close to the brute-force irradiance (within 10% of the mean irradiance).
    const double mean = irradiance[0].y * kShY00;
    for (const glm::dvec3& n : sphereDirections(64)) {
        const glm::dvec3 sh = shEvaluate(irradiance, n);
        EXPECT_GE(std::min({sh.x, sh.y, sh.z}), 0.0);
        const glm::dvec3 reference = cubeIrradianceOverPi(*cube, n);
        EXPECT_LT(glm::length(sh - reference), 0.1 * mean * std::sqrt(3.0));
    }
}

// --- GPU --------------------------------------------------------------------------------------

class ShIrradianceGpu : public ::testing::TestWithParam<Config> {
protected:
    void SetUp() override {
        m_device = &test_support::deviceFor(GetParam().backend);
        m_device->takeDebugMessages();
    }
    void TearDown() override {
        const std::vector<rhi::DebugMessage> messages = m_device->takeDebugMessages();
        EXPECT_TRUE(messages.empty()) << GetParam().name() << " produced validation / debug messages:" << test_support::joinMessages(messages);
    }

    // Uploads `cube` as RGBA32F, or RGBA16F (then `cube` is rounded to what was stored).
    rhi::TextureHandle upload(CubeImage& cube, bool half, uint32_t mipLevels = 1) {
        rhi::TextureHandle texture = m_device->createTexture(rhi::TextureDesc{}
                                                                 .setDimension(rhi::TextureDimension::TextureCube)
                                                                 .setFormat(half ? rhi::Format::RGBA16_FLOAT : rhi::Format::RGBA32_FLOAT)
                                                                 .setSize(cube.size, cube.size)
                                                                 .setMipLevels(mipLevels)
                                                                 .setUsage(rhi::TextureUsage::Sampled)
                                                                 .setDebugName("sh test cube"));
        writeMip(texture, cube, half, 0);
        return texture;
    }
    void writeMip(const rhi::TextureHandle& texture, CubeImage& cube, bool half, uint32_t mip) {
        for (uint32_t face = 0; face < 6; ++face) {
            if (half) {
                std::vector<uint16_t> texels;
                for (glm::vec4& t : cube.faces[face]) {
                    for (int c = 0; c < 4; ++c) {
                        const uint16_t h = glm::packHalf1x16(t[c]);
                        t[c] = glm::unpackHalf1x16(h);
                        texels.push_back(h);
                    }
                }
                m_device->writeTexture(texture, {mip, face}, texels.data(), texels.size() * sizeof(uint16_t));
            } else {
                m_device->writeTexture(texture, {mip, face}, cube.faces[face].data(), cube.faces[face].size() * sizeof(glm::vec4));
            }
        }
    }

    ShRgb gpuIrradiance(const rhi::TextureHandle& texture, uint32_t mip = 0) {
        ShIrradiance sh(*m_device, GetParam().path);
        sh.run(texture, mip);
        const std::array<glm::vec3, 9> coefficients = sh.readCoefficients();
        ShRgb out;
        for (uint32_t i = 0; i < 9; ++i) out[i] = glm::dvec3(coefficients[i]);
        return out;
    }

    // Both paths sum in float (basis, solid angles and products rounded to float; sums of up to
    // 6 x size^2 terms, tree-shaped on compute, row-then-column on fallback). The error bound is
    // relative to the "mass" M = sum |L| * solid angle of the brightest channel (|Y| <= 1.1):
    // measured <= 1e-7 M on every configuration (compute ~1e-8 M, fallback ~7e-8 M at 32^2 faces),
    // so 1e-6 M leaves a factor 10; the errors are printed.
    void expectMatchesCpu(const CubeImage& cube, const ShRgb& gpu, const std::string& label) {
        const ShRgb cpu = shProjectIrradiance(cube);
        double mass = 0.0;
        for (uint32_t face = 0; face < 6; ++face)
            for (uint32_t y = 0; y < cube.size; ++y)
                for (uint32_t x = 0; x < cube.size; ++x) {
                    const glm::vec4& t = cube.at(face, x, y);
                    mass += std::max({std::abs(t.r), std::abs(t.g), std::abs(t.b)}) * cubeTexelSolidAngle(x, y, cube.size);
                }
        for (uint32_t i = 0; i < 9; ++i)
            for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(gpu[i][c])) << label << " coefficient " << i;
        const double error = maxAbsDifference(cpu, gpu);
        std::printf("[ %s %s ] max |gpu - cpu| = %.3g (%.3g of mass %.4g)\n", GetParam().name().c_str(), label.c_str(), error,
                    mass > 0 ? error / mass : 0.0, mass);
        expectShNear(cpu, gpu, 1e-6 * mass + 1e-30, label);
    }

    bool supported() const {
        const Config& config = GetParam();
        if (config.path == FeaturePath::Compute && !m_device->capabilities().has(rhi::Capability::Compute)) return false;
        return true;
    }

    rhi::IDevice* m_device = nullptr;
};

TEST_P(ShIrradianceGpu, AnalyticCubesMatchTheCpuReference) {
    if (!supported()) GTEST_SKIP() << "no compute";
    const glm::dvec3 color(2.0, 1.0, 0.5);
    std::vector<std::pair<std::string, CubeImage>> cubes;
    cubes.emplace_back("constant", CubeImage::filled(kFace, glm::vec4(glm::vec3(color), 1.0f)));
    for (uint32_t axis = 0; axis < 3; ++axis)
        cubes.emplace_back(fmt::format("gradient {}", "xyz"[axis]), cubeFrom(kFace, [&](const glm::dvec3& w) { return color * w[axis]; }));
    const glm::dvec3 lobeAxis = glm::normalize(glm::dvec3(1, 2, -3));
    cubes.emplace_back("cosine lobe", cubeFrom(kFace, [&](const glm::dvec3& w) { return color * std::max(0.0, glm::dot(lobeAxis, w)); }));
    cubes.emplace_back("odd size", cubeFrom(13, [&](const glm::dvec3& w) { return color * (1.5 + w.x - 0.5 * w.y * w.z); }));
    for (auto& [label, cube] : cubes) {
        const ShRgb gpu = gpuIrradiance(upload(cube, false));
        expectMatchesCpu(cube, gpu, label);
    }
    // And against the closed forms directly (constant and gradient: no quadrature error).
    expectShNear(shConvolveIrradiance(shConstantRadiance(color)), gpuIrradiance(upload(cubes[0].second, false)), 1e-5, "constant closed form");
    expectShNear(shConvolveIrradiance(shLinearGradientRadiance(1, color)), gpuIrradiance(upload(cubes[2].second, false)), 1e-5,
                 "gradient closed form");
}

TEST_P(ShIrradianceGpu, HdrEnvironmentMatchesTheCpuReference) {
    if (!supported()) GTEST_SKIP() << "no compute";
    std::optional<CubeImage> cube = hdrEnvironmentCube(kFace);
    ASSERT_TRUE(cube) << "the shared HDR environment is missing: the suite runs with ../shared beside the repository";
    const rhi::TextureHandle texture = upload(*cube, true);   // RGBA16F, the usual environment format
    const ShRgb gpu = gpuIrradiance(texture);
    expectMatchesCpu(*cube, gpu, "chinese_garden_1k");
    for (const glm::dvec3& n : sphereDirections(256)) {
        const glm::dvec3 e = shEvaluate(gpu, n);
        EXPECT_GE(std::min({e.x, e.y, e.z}), 0.0) << "unclamped irradiance along " << n.x << "," << n.y << "," << n.z;
    }
}

TEST_P(ShIrradianceGpu, HardCasesStayFinite) {
    if (!supported()) GTEST_SKIP() << "no compute";
    CubeImage black = CubeImage::filled(kFace, glm::vec4(0.0f));
    const ShRgb blackSh = gpuIrradiance(upload(black, true));
    for (const glm::dvec3& c : blackSh) EXPECT_EQ(c, glm::dvec3(0.0));

    CubeImage halfMax = CubeImage::filled(kFace, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    halfMax.at(2, 5, 7) = glm::vec4(65504.0f, 65504.0f, 65504.0f, 1.0f);
    expectMatchesCpu(halfMax, gpuIrradiance(upload(halfMax, true)), "one texel at 65504");

    // A 3x3-texel sun 1e5 times brighter than a uniform sky: L2 rings below zero opposite the
    // sun, and shading's clamp (shEvaluateIrradiance, max(0, .)) removes it.
    CubeImage sun = CubeImage::filled(kFace, glm::vec4(0.5f, 0.6f, 0.7f, 1.0f));
    for (uint32_t y = 10; y < 13; ++y)
        for (uint32_t x = 20; x < 23; ++x) sun.at(4, x, y) = glm::vec4(50000.0f, 60000.0f, 65000.0f, 1.0f);
    const ShRgb sunSh = gpuIrradiance(upload(sun, true));
    expectMatchesCpu(sun, sunSh, "sun 1e5");
    const glm::dvec3 sunDir = cubeTexelDirection(4, 21, 11, kFace);
    double minimum = 0.0;
    for (const glm::dvec3& n : sphereDirections(512)) {
        minimum = std::min(minimum, shEvaluate(sunSh, n).x);
        const glm::dvec3 clamped = shEvaluateIrradiance(sunSh, n);
        EXPECT_GE(std::min({clamped.x, clamped.y, clamped.z}), 0.0);
    }
    EXPECT_LT(minimum, 0.0) << "expected L2 ringing opposite a point-like sun";
    EXPECT_GT(shEvaluate(sunSh, sunDir).x, 0.0);
}

TEST_P(ShIrradianceGpu, ProjectsTheChosenMip) {
    if (!supported()) GTEST_SKIP() << "no compute";
    CubeImage mip0 = CubeImage::filled(16, glm::vec4(9.0f, 9.0f, 9.0f, 1.0f));
    CubeImage mip1 = cubeFrom(8, [](const glm::dvec3& w) { return glm::dvec3(1.0 + 0.5 * w.z, 2.0, 1.0 - 0.25 * w.x); });
    const rhi::TextureHandle texture = upload(mip0, false, 2);
    writeMip(texture, mip1, false, 1);
    expectMatchesCpu(mip1, gpuIrradiance(texture, 1), "mip 1");
}

TEST_P(ShIrradianceGpu, PassDeclaresItsReadsAndWrites) {
    if (!supported()) GTEST_SKIP() << "no compute";
    CubeImage cube = cubeFrom(kFace, [](const glm::dvec3& w) { return glm::dvec3(1.0 + w.y, 0.5, 0.25); });
    const rhi::TextureHandle texture = upload(cube, false);
    ShIrradiance sh(*m_device, GetParam().path);
    PassGraph graph;
    const PassGraph::ResourceId environment = graph.importResource("environment");
    const PassGraph::ResourceId coefficients = graph.addResource("sh-irradiance");
    sh.addPass(graph, environment, texture, 0, coefficients);
    graph.markOutput(coefficients);
    graph.compile(*m_device);
    ASSERT_TRUE(graph.isKept(ShIrradiance::passName(GetParam().path)));
    const std::vector<PassReport> reports = graph.execute(*m_device, m_device->createCommandList());
    ASSERT_EQ(reports.size(), 1u);
    EXPECT_EQ(reports[0].dispatches + reports[0].draws, 2u);
    const std::array<glm::vec3, 9> read = sh.readCoefficients();
    ShRgb gpu;
    for (uint32_t i = 0; i < 9; ++i) gpu[i] = glm::dvec3(read[i]);
    expectMatchesCpu(cube, gpu, "pass graph");
    EXPECT_TRUE(GetParam().path == FeaturePath::Compute ? bool(sh.coefficientBuffer()) : bool(sh.coefficientTexture()));
}

INSTANTIATE_TEST_SUITE_P(AllConfigs, ShIrradianceGpu, ::testing::ValuesIn(test_support::allConfigs()),
                         [](const ::testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
