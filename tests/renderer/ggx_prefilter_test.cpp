// GGX prefiltering (renderer/src/ibl/ggx_samples.*, ggx_prefilter.*): the sample sets and the
// double-precision CPU reference on the CPU, and on every configuration (validation on) mip 0 =
// source, prefiltered mips vs the reference, draws / dispatches per update, and hard cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <optional>
#include <iostream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>
#include <glm/gtc/packing.hpp>

#include "janus/renderer/image.h"
#include "renderer_test_support.h"
// Internal to the renderer.
#include "../../renderer/src/ibl/environment_map.h"
#include "../../renderer/src/ibl/ggx_prefilter.h"
#include "../../renderer/src/ibl/ggx_samples.h"

namespace janus::renderer {
namespace {

using test_support::Config;

constexpr uint32_t kFace = 32;   // 6 mips: small, llvmpipe/lavapipe run on two cores
constexpr uint32_t kMips = 6;

TEST(GgxSamples, EverySetIsFiniteWithAPositiveWeightSum) {
    for (float roughness : {0.0f, 1e-4f, 0.01f, 0.2f, 0.5f, 0.8f, 1.0f})
        for (uint32_t count : {1u, 21u, 34u, 89u, kMaxGgxSamples}) {
            const GgxSampleSet set = makeGgxSampleSet(roughness, count, kFace, kMips);
            ASSERT_FALSE(set.samples.empty());
            double weight = 0.0;
            for (const GgxSample& s : set.samples) {
                ASSERT_TRUE(std::isfinite(s.direction.x) && std::isfinite(s.direction.y) && std::isfinite(s.direction.z));
                ASSERT_TRUE(std::isfinite(s.lod));
                EXPECT_GE(s.lod, 0.0f);
                EXPECT_LE(s.lod, float(kMips - 1));
                EXPECT_GT(s.direction.z, 0.0f);
                EXPECT_NEAR(glm::length(s.direction), 1.0f, 1e-5f);
                weight += s.direction.z;
            }
            EXPECT_GT(weight, 0.0) << "roughness " << roughness << ", " << count << " samples";
        }
    // Wider lobes read coarser mips.
    const GgxSampleSet narrow = makeGgxSampleSet(0.2f, 34, kFace, kMips), wide = makeGgxSampleSet(1.0f, 34, kFace, kMips);
    EXPECT_LT(narrow.samples[1].lod, wide.samples[1].lod);
    EXPECT_EQ(ggxRoughnessForMip(0, 6), 0.0f);
    EXPECT_EQ(ggxRoughnessForMip(5, 6), 1.0f);
    EXPECT_EQ(ggxSamplesForMip(defaultGgxSamplesPerMip(), 1), 21u);
    EXPECT_EQ(ggxSamplesForMip(defaultGgxSamplesPerMip(), 9), 89u);
    EXPECT_THROW(makeGgxSampleSet(1.5f, 34, kFace, kMips), std::invalid_argument);
    EXPECT_THROW(makeGgxSampleSet(0.5f, 0, kFace, kMips), std::invalid_argument);
    // The lod bias shifts every lod (r = 1: every unbiased lod is above 0); a non-finite bias is refused.
    const GgxSampleSet unbiased = makeGgxSampleSet(1.0f, 34, kFace, kMips, 0.0f), biased = makeGgxSampleSet(1.0f, 34, kFace, kMips, 0.5f);
    ASSERT_EQ(unbiased.samples.size(), biased.samples.size());
    for (size_t i = 0; i < unbiased.samples.size(); ++i)
        EXPECT_FLOAT_EQ(biased.samples[i].lod, std::min(float(kMips - 1), std::max(0.0f, unbiased.samples[i].lod + 0.5f)))
            << "sample " << i;
    EXPECT_THROW(makeGgxSampleSet(0.5f, 34, kFace, kMips, std::nanf("")), std::invalid_argument);
}

using Radiance = std::function<glm::dvec3(const glm::dvec3&, uint32_t face, uint32_t x, uint32_t y)>;

CubeImage makeCube(uint32_t size, const Radiance& radiance) {
    CubeImage cube;
    cube.size = size;
    for (uint32_t face = 0; face < 6; ++face) {
        cube.faces[face].resize(size_t(size) * size * 4);
        for (uint32_t y = 0; y < size; ++y)
            for (uint32_t x = 0; x < size; ++x) {
                const glm::dvec3 c = radiance(cubeTexelDirection(face, x, y, size), face, x, y);
                float* p = cube.faces[face].data() + (size_t(y) * size + x) * 4;
                p[0] = float(c.x), p[1] = float(c.y), p[2] = float(c.z), p[3] = 1.0f;
            }
    }
    return cube;
}

TEST(GgxReference, HardCasesAreFinite) {
    const CubeImage black = makeCube(8, [](const glm::dvec3&, uint32_t, uint32_t, uint32_t) { return glm::dvec3(0.0); });
    const CubeImage hot = makeCube(8, [](const glm::dvec3&, uint32_t face, uint32_t x, uint32_t y) {
        return face == 4 && x == 3 && y == 4 ? glm::dvec3(65504.0) : glm::dvec3(0.25);
    });
    for (const CubeImage* cube : {&black, &hot}) {
        const GgxReference reference(*cube);
        for (double roughness : {0.0, 1e-5, 0.3, 1.0})
            for (const glm::dvec3& n : {glm::dvec3(0, 0, 1), glm::dvec3(1, 1, 1), glm::dvec3(0, -1, 0)}) {
                const glm::dvec3 r = reference.radiance(n, roughness);
                EXPECT_TRUE(std::isfinite(r.x) && std::isfinite(r.y) && std::isfinite(r.z));
                if (cube == &black) {
                    EXPECT_EQ(r, glm::dvec3(0.0));
                }
            }
    }
    // Roughness 0 is the mirror: the texel along n.
    EXPECT_EQ(GgxReference(hot).radiance(cubeTexelDirection(4, 3, 4, 8), 0.0), glm::dvec3(65504.0));
}

// The reference for every texel of mips 1..mipCount-1 (roughness m / (mipCount - 1)) of a cube of
// `source.size`, index [mip][(face * size + y) * size + x].
using ReferenceMips = std::vector<std::vector<glm::dvec3>>;
ReferenceMips referenceMips(const CubeImage& source, uint32_t mipCount) {
    const GgxReference reference(source);
    ReferenceMips mips(mipCount);
    for (uint32_t mip = 1; mip < mipCount; ++mip) {
        const uint32_t size = std::max(1u, source.size >> mip);
        for (uint32_t face = 0; face < 6; ++face)
            for (uint32_t y = 0; y < size; ++y)
                for (uint32_t x = 0; x < size; ++x)
                    mips[mip].push_back(reference.radiance(cubeTexelDirection(face, x, y, size), ggxRoughnessForMip(mip, mipCount)));
    }
    return mips;
}

// Relative RMSE over a mip (RMS of |gpu - ref| / mean |ref|) and the largest relative error of one
// texel (|gpu - ref| / |ref|).
struct MipError {
    double rmse = 0.0, maxRelative = 0.0;
};

std::vector<MipError> measureErrors(rhi::IDevice& device, const GgxPrefilter& prefilter, const ReferenceMips& reference) {
    std::vector<MipError> errors(prefilter.mipCount());
    for (uint32_t mip = 1; mip < prefilter.mipCount(); ++mip) {
        const CubeImage got = readCube(device, prefilter.prefiltered(), mip);
        double squared = 0.0, magnitude = 0.0, maxRelative = 0.0;
        size_t i = 0;
        for (uint32_t face = 0; face < 6; ++face)
            for (uint32_t y = 0; y < got.size; ++y)
                for (uint32_t x = 0; x < got.size; ++x, ++i) {
                    const glm::dvec3& expected = reference[mip][i];
                    const glm::dvec3 error = got.texel(face, x, y) - expected;
                    squared += glm::dot(error, error);
                    magnitude += glm::length(expected);
                    maxRelative = std::max(maxRelative, glm::length(error) / glm::length(expected));
                }
        errors[mip] = {std::sqrt(squared / double(i)) / (magnitude / double(i)), maxRelative};
    }
    return errors;
}

// The shared sky (1024 x 512 equirect) box-filtered into a small cube on the CPU: the mean of
// 8 x 8 nearest equirect texels per cube texel.
std::optional<CubeImage> sharedSkyCube(uint32_t size) {
    const std::filesystem::path path = std::filesystem::path(JANUS_SHARED_SCENES_DIR) / "env" / "chinese_garden_1k.hdr";
    if (!std::filesystem::exists(path)) return std::nullopt;
    const ImageRGBAF sky = readRadianceHDR(path);
    constexpr int kSub = 8;
    return makeCube(size, [&](const glm::dvec3&, uint32_t face, uint32_t x, uint32_t y) {
        glm::dvec3 sum(0.0);
        for (int j = 0; j < kSub; ++j)
            for (int i = 0; i < kSub; ++i) {
                const glm::dvec3 d = glm::normalize(cubeDirection(face, (x + (i + 0.5) / kSub) / size, (y + (j + 0.5) / kSub) / size));
                const glm::dvec2 uv = equirectUv(d);
                const uint32_t px = std::min(sky.width - 1, uint32_t(uv.x * sky.width));
                const uint32_t py = std::min(sky.height - 1, uint32_t(uv.y * sky.height));
                const float* p = sky.pixels.data() + (size_t(py) * sky.width + px) * 4;
                sum += glm::dvec3(p[0], p[1], p[2]);
            }
        return sum / double(kSub * kSub);
    });
}

class GgxPrefilterTest : public testing::TestWithParam<Config> {
protected:
    rhi::IDevice& device() { return test_support::deviceFor(GetParam().backend); }
    bool compute() const { return GetParam().path == FeaturePath::Compute; }
    void expectNoMessages() {
        const std::vector<rhi::DebugMessage> messages = device().takeDebugMessages();
        EXPECT_TRUE(messages.empty()) << GetParam().name() << ":" << test_support::joinMessages(messages);
    }
    // An RGBA16F source cube, full chain, mip 0 = `image` (values rounded to half).
    rhi::TextureHandle upload(const CubeImage& image) {
        const rhi::TextureHandle cube = device().createTexture(rhi::TextureDesc{}
                                                                   .setDimension(rhi::TextureDimension::TextureCube)
                                                                   .setFormat(rhi::Format::RGBA16_FLOAT)
                                                                   .setSize(image.size, image.size)
                                                                   .setMipLevels(0)
                                                                   .setUsage(rhi::TextureUsage::Sampled | rhi::TextureUsage::RenderTarget)
                                                                   .setDebugName("prefilter test source"));
        for (uint32_t face = 0; face < 6; ++face) {
            std::vector<uint16_t> halves(image.faces[face].size());
            for (size_t i = 0; i < halves.size(); ++i) halves[i] = glm::packHalf1x16(image.faces[face][i]);
            device().writeTexture(cube, {0, face}, halves.data(), halves.size() * 2);
        }
        return cube;
    }
    void expectCounts(const PassReport& report, uint32_t mipCount) {
        if (compute()) {
            EXPECT_EQ(report.name, "ggx-prefilter-compute");
            EXPECT_EQ(report.dispatches, mipCount - 1);   // one per prefiltered mip, all faces
            EXPECT_EQ(report.draws, 0u);
        } else {
            EXPECT_EQ(report.name, "ggx-prefilter-fallback");
            EXPECT_EQ(report.draws, 6 * (mipCount - 1));   // one per face per prefiltered mip: 30 for 6 mips
            EXPECT_EQ(report.dispatches, 0u);
        }
    }
    // Every value of every mip finite and >= 0; returns the largest.
    float expectFinite(const GgxPrefilter& prefilter, const std::string& label) {
        float largest = 0.0f;
        for (uint32_t mip = 0; mip < prefilter.mipCount(); ++mip) {
            const CubeImage image = readCube(device(), prefilter.prefiltered(), mip);
            for (uint32_t face = 0; face < 6; ++face)
                for (size_t i = 0; i < image.faces[face].size(); ++i) {
                    if (i % 4 == 3) continue;   // alpha
                    const float v = image.faces[face][i];
                    EXPECT_TRUE(std::isfinite(v) && v >= 0.0f) << label << ": mip " << mip << " face " << face << " has " << v;
                    if (!std::isfinite(v)) return v;
                    largest = std::max(largest, v);
                }
        }
        return largest;
    }
};

// A smooth sky with a soft bright lobe: what the prefilter is compared with the reference on.
glm::dvec3 testSky(const glm::dvec3& d) {
    const glm::dvec3 sun = glm::normalize(glm::dvec3(0.4, 0.7, -0.6));
    const double lobe = std::pow(std::max(0.0, glm::dot(d, sun)), 8.0);
    return glm::dvec3(0.2 + 0.3 * (0.5 + 0.5 * d.x), 0.2 + 0.3 * (0.5 + 0.5 * d.y), 0.2 + 0.3 * (0.5 + 0.5 * d.z)) +
           glm::dvec3(4.0, 3.0, 2.0) * lobe;
}

TEST_P(GgxPrefilterTest, MatchesTheCpuReferenceAndMip0IsTheSource) {
    device().takeDebugMessages();
    const rhi::TextureHandle source = upload(makeCube(kFace, [](const glm::dvec3& d, uint32_t, uint32_t, uint32_t) { return testSky(d); }));
    GgxPrefilter prefilter(device(), GetParam().path);
    const PassReport report = prefilter.run(source);
    ASSERT_EQ(prefilter.mipCount(), kMips);
    expectCounts(report, kMips);

    // Mip 0 is a copy: bit for bit what the source holds.
    const CubeImage source0 = readCube(device(), source, 0);
    const CubeImage mip0 = readCube(device(), prefilter.prefiltered(), 0);
    for (uint32_t face = 0; face < 6; ++face) ASSERT_EQ(mip0.faces[face], source0.faces[face]) << "face " << face;

    // Each prefiltered texel against the brute-force reference over the source's mip 0 (as stored,
    // in half).
    const std::vector<MipError> errors = measureErrors(device(), prefilter, referenceMips(source0, kMips));
    for (uint32_t mip = 1; mip < kMips; ++mip) {
        const MipError& e = errors[mip];
        std::cout << fmt::format("{} mip {} (roughness {:.2f}, {} samples): relative RMSE {:.4f}, max relative {:.4f}\n",
                                 GetParam().name(), mip, prefilter.roughnessForMip(mip), prefilter.sampleSets()[mip].samples.size(),
                                 e.rmse, e.maxRelative);
        // Tolerances: filtered importance sampling reads box-filtered source mips (lod from each
        // sample's solid angle, bias 0) instead of every texel, with 21..89 samples: noisy, and
        // slightly blurred by the bilinear taps. Measured on every configuration (identical):
        // relative RMSE 1.1..1.8 %, max relative 3.0..6.9 % (mip 1, r = 0.2, is the worst; table
        // in docs/IBL.md). The bounds leave ~35 % headroom over the worst mip; Karis' +1 bias
        // (4.2..6.9 % RMSE, 11..15 % max) fails them on every mip.
        EXPECT_LT(e.rmse, 0.025) << GetParam().name() << " mip " << mip;
        EXPECT_LT(e.maxRelative, 0.095) << GetParam().name() << " mip " << mip;
    }
    expectNoMessages();
}

// The accuracy-vs-samples table of docs/IBL.md ("GGX prefiltering"): samples per mip 8..128 at
// 32^2 faces, relative RMSE / max relative per mip against the reference and the pass's GPU time
// (the second of two runs). Disabled: run with --gtest_also_run_disabled_tests. GGX_TABLE_BIASES
// (comma-separated lod biases) and GGX_TABLE_SAMPLES ("default" or counts) override the rows.
TEST_P(GgxPrefilterTest, DISABLED_AccuracyTable) {
    device().takeDebugMessages();
    std::vector<std::pair<std::string, CubeImage>> skies;
    skies.emplace_back("test sky", makeCube(kFace, [](const glm::dvec3& d, uint32_t, uint32_t, uint32_t) { return testSky(d); }));
    if (std::optional<CubeImage> garden = sharedSkyCube(kFace)) skies.emplace_back("chinese_garden_1k", std::move(*garden));
    std::vector<float> biases = {kDefaultGgxLodBias};
    if (const char* env = std::getenv("GGX_TABLE_BIASES")) {
        biases.clear();
        for (std::string rest = env; !rest.empty();) {
            const size_t comma = rest.find(',');
            biases.push_back(std::stof(rest.substr(0, comma)));
            rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
        }
    }
    std::vector<std::vector<uint32_t>> rows = {{8}, {16}, {34}, {64}, {128}, defaultGgxSamplesPerMip()};
    if (const char* env = std::getenv("GGX_TABLE_SAMPLES")) {
        rows.clear();
        for (std::string rest = env; !rest.empty();) {
            const size_t comma = rest.find(',');
            const std::string item = rest.substr(0, comma);
            rows.push_back(item == "default" ? defaultGgxSamplesPerMip() : std::vector<uint32_t>{uint32_t(std::stoul(item))});
            rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
        }
    }
    for (const auto& [skyName, image] : skies) {
        const rhi::TextureHandle source = upload(image);
        const CubeImage source0 = readCube(device(), source, 0);
        const ReferenceMips reference = referenceMips(source0, kMips);
        for (float bias : biases)
            for (const std::vector<uint32_t>& samples : rows) {
                GgxPrefilterSettings settings;
                settings.samplesPerMip = samples;
                settings.lodBias = bias;
                GgxPrefilter prefilter(device(), GetParam().path, settings);
                prefilter.run(source);
                const PassReport report = prefilter.run(source);
                const std::vector<MipError> errors = measureErrors(device(), prefilter, reference);
                std::string line = fmt::format("| {} | {} | bias {} | {} |", GetParam().name(), skyName, bias,
                                               samples.size() == 1 ? std::to_string(samples[0]) : std::string("default"));
                double worstRmse = 0, worstMax = 0;
                for (uint32_t mip = 1; mip < kMips; ++mip) {
                    line += fmt::format(" {:.1f} / {:.1f} |", 100.0 * errors[mip].rmse, 100.0 * errors[mip].maxRelative);
                    worstRmse = std::max(worstRmse, errors[mip].rmse);
                    worstMax = std::max(worstMax, errors[mip].maxRelative);
                }
                line += fmt::format(" worst {:.1f} / {:.1f} | {} ms |\n", 100.0 * worstRmse, 100.0 * worstMax,
                                    report.gpuMs ? fmt::format("{:.2f}", *report.gpuMs) : std::string("-"));
                std::cout << line;
            }
    }
    expectNoMessages();
}

struct HardCase {
    const char* name;
    Radiance radiance;
    std::vector<float> roughness;   // per-mip override (empty: m / (N - 1))
};

TEST_P(GgxPrefilterTest, HardCasesStayFinite) {
    device().takeDebugMessages();
    const std::vector<HardCase> cases = {
        {"roughness 0 and 1", [](const glm::dvec3& d, uint32_t, uint32_t, uint32_t) { return testSky(d); }, {0, 0, 1, 0, 1, 1}},
        {"all black", [](const glm::dvec3&, uint32_t, uint32_t, uint32_t) { return glm::dvec3(0.0); }, {}},
        {"one texel at 65504",
         [](const glm::dvec3&, uint32_t face, uint32_t x, uint32_t y) {
             return face == 2 && x == 7 && y == 20 ? glm::dvec3(65504.0) : glm::dvec3(0.1);
         },
         {}},
        // The rest at 0.5 and a sun of 4 texels 1e5 times brighter (5e4 fits a half).
        {"sun 1e5 times brighter",
         [](const glm::dvec3&, uint32_t face, uint32_t x, uint32_t y) {
             return face == 4 && x >= 10 && x < 12 && y >= 10 && y < 12 ? glm::dvec3(5e4) : glm::dvec3(0.5);
         },
         {}},
    };
    for (const HardCase& hard : cases) {
        SCOPED_TRACE(hard.name);
        const rhi::TextureHandle source = upload(makeCube(kFace, hard.radiance));
        GgxPrefilterSettings settings;
        settings.roughness = hard.roughness;
        GgxPrefilter prefilter(device(), GetParam().path, settings);
        expectCounts(prefilter.run(source), kMips);
        const float largest = expectFinite(prefilter, hard.name);
        if (std::string(hard.name) == "all black") {
            EXPECT_EQ(largest, 0.0f);
        } else {
            EXPECT_LE(largest, 65504.0f);
        }
    }
    expectNoMessages();
}

TEST_P(GgxPrefilterTest, SampleCountsAndMipCountAreSettings) {
    device().takeDebugMessages();
    const rhi::TextureHandle source = upload(makeCube(kFace, [](const glm::dvec3& d, uint32_t, uint32_t, uint32_t) { return testSky(d); }));
    GgxPrefilterSettings settings;
    settings.mipCount = 4;
    settings.samplesPerMip = {34};   // 34 everywhere
    GgxPrefilter prefilter(device(), GetParam().path, settings);
    expectCounts(prefilter.run(source), 4);
    EXPECT_EQ(prefilter.prefiltered()->desc().mipLevels, 4u);
    EXPECT_FLOAT_EQ(prefilter.roughnessForMip(3), 1.0f);
    for (uint32_t mip = 1; mip < 4; ++mip) EXPECT_EQ(prefilter.sampleSets()[mip].requested, 34u);
    expectFinite(prefilter, "34 everywhere");
    settings.samplesPerMip = {0};
    EXPECT_THROW(GgxPrefilter(device(), GetParam().path, settings), RendererError);
    expectNoMessages();
}

INSTANTIATE_TEST_SUITE_P(Configs, GgxPrefilterTest, testing::ValuesIn(test_support::allConfigs()),
                         [](const testing::TestParamInfo<Config>& info) { return info.param.name(); });

}  // namespace
}  // namespace janus::renderer
