#include "ibl/dfg_lut.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>
#include <glm/gtc/packing.hpp>

#include "ibl/ggx_samples.h"
#include "janus/renderer/settings.h"

namespace janus::renderer {
namespace {

// forward.frag's visibilitySmithGGXCorrelated in double precision.
double visibility(double NoV, double NoL, double alpha) {
    const double a2 = alpha * alpha;
    const double ggxV = NoL * std::sqrt(NoV * NoV * (1.0 - a2) + a2);
    const double ggxL = NoV * std::sqrt(NoL * NoL * (1.0 - a2) + a2);
    const double sum = ggxV + ggxL;
    return sum > 0.0 ? 0.5 / sum : 0.0;
}

}  // namespace

glm::dvec2 integrateDfg(double NoV, double perceptualRoughness, uint32_t samples) {
    NoV = std::clamp(std::isfinite(NoV) ? NoV : 1.0, 1e-4, 1.0);
    const double r = std::clamp(std::isfinite(perceptualRoughness) ? perceptualRoughness : 1.0, 0.0, 1.0);
    const double alpha = r * r;
    const glm::dvec3 V(std::sqrt(1.0 - NoV * NoV), 0.0, NoV);   // N = +Z
    glm::dvec2 sum(0.0);
    for (uint32_t i = 0; i < samples; ++i) {
        const double u = (double(i) + 0.5) / double(samples), v = radicalInverse(i);
        // GGX: cos^2(theta_h) = (1 - v) / (1 + (alpha^2 - 1) v), H sampled with pdf D(H) NoH.
        const double cosThetaH = std::sqrt((1.0 - v) / (1.0 + (alpha * alpha - 1.0) * v));
        const double sinThetaH = std::sqrt(std::max(0.0, 1.0 - cosThetaH * cosThetaH));
        const double phi = 2.0 * std::numbers::pi * u;
        const glm::dvec3 H(sinThetaH * std::cos(phi), sinThetaH * std::sin(phi), cosThetaH);
        const double VoH = glm::dot(V, H);
        const glm::dvec3 L = 2.0 * VoH * H - V;
        const double NoL = L.z, NoH = H.z;
        if (NoL <= 0.0 || VoH <= 0.0 || NoH <= 0.0) continue;
        const double weight = 4.0 * visibility(NoV, NoL, alpha) * NoL * VoH / NoH;
        const double fc = std::pow(1.0 - VoH, 5.0);
        sum += glm::dvec2((1.0 - fc) * weight, fc * weight);
    }
    return samples > 0 ? sum / double(samples) : glm::dvec2(0.0);
}

DfgTable computeDfgTable(uint32_t size, uint32_t samples) {
    if (size == 0 || samples == 0)
        throw RendererError(fmt::format("DFG table: size {} and samples {} must both be at least 1", size, samples));
    DfgTable table;
    table.size = size;
    table.values.resize(size_t(size) * size);
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x)
            table.values[size_t(y) * size + x] =
                glm::vec2(integrateDfg((x + 0.5) / double(size), (y + 0.5) / double(size), samples));
    return table;
}

rhi::TextureHandle uploadDfgTable(rhi::IDevice& device, const DfgTable& table) {
    std::vector<uint16_t> texels(size_t(table.size) * table.size * 4, 0);
    for (size_t i = 0; i < table.values.size(); ++i) {
        texels[i * 4 + 0] = glm::packHalf1x16(table.values[i].x);
        texels[i * 4 + 1] = glm::packHalf1x16(table.values[i].y);
    }
    rhi::TextureHandle texture = device.createTexture(rhi::TextureDesc{}
                                                          .setFormat(rhi::Format::RGBA16_FLOAT)
                                                          .setSize(table.size, table.size)
                                                          .setUsage(rhi::TextureUsage::Sampled)
                                                          .setDebugName("DFG table"));
    device.writeTexture(texture, {}, texels.data(), texels.size() * sizeof(uint16_t));
    return texture;
}

}  // namespace janus::renderer
