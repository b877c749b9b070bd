// The split-sum DFG table (renderer/src/ibl/dfg_lut.h): its importance-sampled integrals against
// an independent quadrature of the same BRDF, its limits, finiteness and the uploaded texture.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>

#include <fmt/format.h>
#include <glm/gtc/packing.hpp>

#include "ibl/dfg_lut.h"
#include "renderer/renderer_test_support.h"

namespace janus::renderer {
namespace {

// The same (A, B) by midpoint quadrature over the hemisphere of L (uniform in cos(theta) and
// phi), with forward.frag's D and Vis written out independently.
glm::dvec2 quadratureDfg(double NoV, double roughness, int thetaSteps = 2048, int phiSteps = 1024) {
    const double alpha = roughness * roughness, a2 = alpha * alpha;
    const glm::dvec3 V(std::sqrt(1.0 - NoV * NoV), 0.0, NoV);
    glm::dvec2 sum(0.0);
    const double dCos = 1.0 / thetaSteps, dPhi = 2.0 * std::numbers::pi / phiSteps;
    for (int t = 0; t < thetaSteps; ++t) {
        const double cosT = (t + 0.5) * dCos, sinT = std::sqrt(1.0 - cosT * cosT);
        for (int p = 0; p < phiSteps; ++p) {
            const double phi = (p + 0.5) * dPhi;
            const glm::dvec3 L(sinT * std::cos(phi), sinT * std::sin(phi), cosT);
            const glm::dvec3 H = glm::normalize(L + V);
            const double NoH = H.z, VoH = glm::dot(V, H), NoL = cosT;
            const double f = (NoH * a2 - NoH) * NoH + 1.0;
            const double D = a2 / (std::numbers::pi * f * f);
            const double vis = 0.5 / (NoL * std::sqrt(NoV * NoV * (1.0 - a2) + a2) + NoV * std::sqrt(NoL * NoL * (1.0 - a2) + a2));
            const double fc = std::pow(1.0 - VoH, 5.0);
            const double value = D * vis * NoL * dCos * dPhi;
            sum += glm::dvec2((1.0 - fc) * value, fc * value);
        }
    }
    return sum;
}

TEST(DfgTableTest, ImportanceSamplingAgreesWithQuadratureOfTheSameBrdf) {
    // 4096 Hammersley samples against a 2048 x 1024 quadrature: both converge to the same
    // integral; 1% of (A + B) covers the sampling noise at the roughest and most grazing point.
    for (double roughness : {0.35, 0.6, 1.0}) {
        for (double NoV : {0.1, 0.5, 0.95}) {
            const glm::dvec2 sampled = integrateDfg(NoV, roughness, 4096);
            const glm::dvec2 reference = quadratureDfg(NoV, roughness);
            const double tolerance = 0.01 * (reference.x + reference.y);
            EXPECT_NEAR(sampled.x, reference.x, tolerance) << fmt::format("A at NoV {} roughness {}", NoV, roughness);
            EXPECT_NEAR(sampled.y, reference.y, tolerance) << fmt::format("B at NoV {} roughness {}", NoV, roughness);
        }
    }
}

TEST(DfgTableTest, AMirrorSeenHeadOnReflectsEverythingWithoutFresnelGain) {
    const glm::dvec2 mirror = integrateDfg(1.0, 0.0, 64);
    EXPECT_NEAR(mirror.x, 1.0, 1e-9);
    EXPECT_NEAR(mirror.y, 0.0, 1e-9);
}

TEST(DfgTableTest, TableIsFiniteBoundedAndLosesEnergyWithRoughness) {
    const DfgTable table = computeDfgTable(16, 256);
    ASSERT_EQ(table.values.size(), 16u * 16u);
    for (uint32_t y = 0; y < table.size; ++y) {
        for (uint32_t x = 0; x < table.size; ++x) {
            const glm::vec2 v = table.at(x, y);
            ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y)) << x << "," << y;
            EXPECT_GE(v.x, 0.0f);
            EXPECT_GE(v.y, 0.0f);
            // A single-scattering microfacet BRDF never reflects more than arrives.
            EXPECT_LE(v.x + v.y, 1.0f + 1e-3f) << x << "," << y;
        }
    }
    // Head-on, rougher surfaces lose more energy to masking (no multiple scattering).
    for (uint32_t y = 1; y < table.size; ++y)
        EXPECT_LE(table.at(table.size - 1, y).x + table.at(table.size - 1, y).y,
                  table.at(table.size - 1, y - 1).x + table.at(table.size - 1, y - 1).y + 1e-4f);
    for (double bad : {-1.0, 0.0, 2.0, double(NAN), double(INFINITY)}) {
        const glm::dvec2 v = integrateDfg(bad, bad, 32);
        EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y)) << bad;
    }
    EXPECT_THROW(computeDfgTable(0, 16), RendererError);
    EXPECT_THROW(computeDfgTable(16, 0), RendererError);
}

TEST(DfgTableTest, UploadsAsHalfFloatsOnEveryBackend) {
    const DfgTable table = computeDfgTable(8, 64);
    for (rhi::Backend backend : {rhi::Backend::Vulkan, rhi::Backend::GL, rhi::Backend::GLES}) {
        rhi::IDevice& device = test_support::deviceFor(backend);
        device.takeDebugMessages();
        const rhi::TextureHandle texture = uploadDfgTable(device, table);
        const std::vector<std::byte> bytes = device.readTexture(texture, {});
        ASSERT_EQ(bytes.size(), 8u * 8u * 8u) << rhi::toString(backend);
        for (size_t i = 0; i < table.values.size(); ++i) {
            uint16_t a, b;
            std::memcpy(&a, bytes.data() + i * 8, 2);
            std::memcpy(&b, bytes.data() + i * 8 + 2, 2);
            EXPECT_EQ(a, glm::packHalf1x16(table.values[i].x)) << rhi::toString(backend) << " texel " << i;
            EXPECT_EQ(b, glm::packHalf1x16(table.values[i].y)) << rhi::toString(backend) << " texel " << i;
        }
        const std::vector<rhi::DebugMessage> messages = device.takeDebugMessages();
        EXPECT_TRUE(messages.empty()) << test_support::joinMessages(messages);
    }
}

}  // namespace
}  // namespace janus::renderer
