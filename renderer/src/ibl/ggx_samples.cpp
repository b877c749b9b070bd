#include "ibl/ggx_samples.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace janus::renderer {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

float ggxRoughnessForMip(uint32_t mip, uint32_t mipCount) {
    if (mipCount <= 1) return 0.0f;
    return std::min(1.0f, float(mip) / float(mipCount - 1));
}

uint32_t ggxSamplesForMip(const std::vector<uint32_t>& samplesPerMip, uint32_t mip) {
    if (samplesPerMip.empty()) throw std::invalid_argument("GGX samples per mip: the list is empty");
    const size_t index = std::min<size_t>(mip == 0 ? 0 : mip - 1, samplesPerMip.size() - 1);
    return samplesPerMip[index];
}

double ggxDistribution(double nDotH, double alpha) {
    const double a2 = alpha * alpha;
    const double d = nDotH * nDotH * (a2 - 1.0) + 1.0;
    return a2 / (kPi * d * d);
}

double ggxLobeNormalization(double alpha) {
    if (!(alpha >= 1e-6)) return 0.0;
    const double a2 = alpha * alpha;
    // cos^2 theta_h(u) = (1 - u) / (1 + (a2 - 1) u); n.l = 2 cos^2 - 1 = (1 - (1 + a2) u) / (1 + (a2 - 1) u),
    // > 0 for u < u0 = 1 / (1 + a2). Its integral over [0, u0] in closed form, 1 / (1 - a2) +
    // 2 a2 / (1 - a2)^2 ln(2 a2 / (1 + a2)), cancels as a2 -> 1; there the integrand is smooth: Simpson.
    if (a2 < 0.5) return 4.0 * (1.0 / (1.0 - a2) + 2.0 * a2 / ((1.0 - a2) * (1.0 - a2)) * std::log(2.0 * a2 / (1.0 + a2)));
    const double u0 = 1.0 / (1.0 + a2);
    auto f = [&](double u) { return std::max(0.0, (1.0 - (1.0 + a2) * u) / (1.0 + (a2 - 1.0) * u)); };
    constexpr int kIntervals = 4096;   // even
    const double step = u0 / kIntervals;
    double sum = f(0.0) + f(u0);
    for (int i = 1; i < kIntervals; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(i * step);
    return 4.0 * sum * step / 3.0;
}

double radicalInverse(uint32_t bits) {
    bits = (bits << 16u) | (bits >> 16u);
    bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
    bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
    bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
    bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
    return double(bits) * 2.3283064365386963e-10;   // / 2^32
}

GgxSampleSet makeGgxSampleSet(float roughness, uint32_t count, uint32_t sourceFaceSize, uint32_t sourceMipCount, float lodBias) {
    if (!(roughness >= 0.0f && roughness <= 1.0f))
        throw std::invalid_argument("GGX sample set: roughness " + std::to_string(roughness) + " is outside [0, 1]");
    if (count == 0 || count > kMaxGgxSamples)
        throw std::invalid_argument("GGX sample set: " + std::to_string(count) + " samples is outside 1.." +
                                    std::to_string(kMaxGgxSamples));
    if (sourceFaceSize == 0 || sourceMipCount == 0) throw std::invalid_argument("GGX sample set: empty source cube");
    if (!std::isfinite(lodBias)) throw std::invalid_argument("GGX sample set: the lod bias is not finite");
    GgxSampleSet set;
    set.roughness = roughness;
    set.requested = count;
    const double alpha = double(roughness) * double(roughness);
    set.normalization = ggxLobeNormalization(alpha);
    const double maxLod = double(sourceMipCount - 1);
    // Below this alpha D is a spike narrower than float can sample: the mirror direction itself.
    if (alpha < 1e-6) {
        set.samples.push_back(GgxSample{glm::vec3(0, 0, 1), 0.0f});
        return set;
    }
    const double texelSolidAngle = 4.0 * kPi / (6.0 * double(sourceFaceSize) * double(sourceFaceSize));
    for (uint32_t i = 0; i < count; ++i) {
        const double u = double(i) / double(count);
        const double phi = 2.0 * kPi * radicalInverse(i);
        // Inverse CDF of D(H) NdotH: cos^2 theta = (1 - u) / (1 + (alpha^2 - 1) u); the
        // denominator is >= alpha^2 > 0.
        const double cos2 = (1.0 - u) / (1.0 + (alpha * alpha - 1.0) * u);
        const double cosTheta = std::sqrt(std::clamp(cos2, 0.0, 1.0));
        const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
        const glm::dvec3 h(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
        const glm::dvec3 l = 2.0 * h.z * h - glm::dvec3(0, 0, 1);   // reflect V = N = +Z about H
        if (!(l.z > 0.0)) continue;
        // pdf(L) = D(H) NdotH / (4 VdotH) = D / 4 because N = V.
        const double pdf = ggxDistribution(cosTheta, alpha) / 4.0;
        double lod = maxLod;
        if (pdf > 0.0 && std::isfinite(pdf)) {
            const double sampleSolidAngle = 1.0 / (double(count) * pdf);
            lod = 0.5 * std::log2(sampleSolidAngle / texelSolidAngle) + double(lodBias);
            if (!std::isfinite(lod)) lod = lod > 0 ? maxLod : 0.0;
        }
        set.samples.push_back(GgxSample{glm::vec3(glm::normalize(l)), float(std::clamp(lod, 0.0, maxLod))});
    }
    // Every set has at least the sample at u = 0 (H = N, L = N), so the weight sum is never 0.
    return set;
}

}  // namespace janus::renderer
