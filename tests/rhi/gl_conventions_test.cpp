// Conventions the GL backend has to work for (and Vulkan gets for free): Vulkan's fill rule on
// edges through pixel centres, [0, 1] clip depth where reported native, new resources reading as
// zero. Every test runs on every backend.
#include "backend_test.h"

#include <cmath>

namespace janus::rhi::test {
namespace {

class ConventionsTest : public BackendTest {
protected:
    TextureHandle color8x8() { return createTexture2D(Format::RGBA8_UNORM, 8, 8, TextureUsage::RenderTarget); }
};
JANUS_INSTANTIATE_BACKEND_TESTS(ConventionsTest);

const Color kWhite = {1, 1, 1, 1};

// Every edge of the square passes exactly through pixel centres (NDC +-0.375 is row/column 2.5
// and 5.5 of 8). Vulkan's top-left rule (row 0 on top) covers the top and left edges' pixels and
// not the bottom and right ones: rows and columns 2..4. (GL with an upper-left clip origin fails
// this on Mesa: rows 3..5.)
TEST_P(ConventionsTest, EdgesThroughPixelCentresFollowTheTopLeftRule) {
    TextureHandle color = color8x8();
    drawVertices(RenderPassDesc().addColor(Attachment::clear(color, {0, 0, 0, 1})),
                 colorPipeline(Format::RGBA8_UNORM), rectangle(-0.375f, -0.375f, 0.375f, 0.375f, kWhite));
    std::vector<Rgba8> expected(64, toRgba8({0, 0, 0, 1}));
    for (size_t i = 0; i < 64; ++i)
        if (i % 8 >= 2 && i % 8 <= 4 && i / 8 >= 2 && i / 8 <= 4) expected[i] = toRgba8(kWhite);
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(color), expected, 8)) << "rows and columns 2..4 covered";
}

// Where a backend reports [0, 1] clip depth as native, depth reaches the depth buffer unchanged.
// Emulation (z' = 2z - w, then back) would round this depth to 0: -1 + 2e-8 is -1 in float.
TEST_P(ConventionsTest, NativeClipDepthKeepsTinyDepths) {
    if (!caps().conventions.nativeClipDepthZeroToOne) GTEST_SKIP() << "clip depth is emulated on this device";
    TextureHandle color = color8x8();
    TextureHandle depth = createTexture2D(Format::D32_FLOAT, 8, 8, TextureUsage::RenderTarget);
    const float tiny = 1e-8f;
    drawVertices(RenderPassDesc().addColor(Attachment::clear(color, {0, 0, 0, 1})).setDepth(Attachment::clearDepthTo(depth, 1.0f)),
                 colorPipeline(Format::RGBA8_UNORM, Format::D32_FLOAT, {}, {true, true, CompareOp::Always}),
                 rectangle(-1, -1, 1, 1, kWhite, tiny));
    EXPECT_EQ(readTextureAs<float>(depth), std::vector<float>(64, tiny));
}

TEST_P(ConventionsTest, NewBuffersReadAsZero) {
    BufferHandle buffer = createBuffer(BufferUsage::Vertex | BufferUsage::Uniform, 4096);
    EXPECT_EQ(readBufferAs<uint32_t>(buffer), std::vector<uint32_t>(1024, 0u));
}

TEST_P(ConventionsTest, NewTexturesReadAsZeroInEverySubresource) {
    auto expectZero = [&](const TextureHandle& texture, TextureSubresource sub, const char* what) {
        const std::vector<std::byte> bytes = device().readTexture(texture, sub);
        ASSERT_FALSE(bytes.empty());
        size_t nonZero = 0;
        for (std::byte b : bytes) nonZero += b != std::byte{0};
        EXPECT_EQ(nonZero, 0u) << what << " mip " << sub.mipLevel << " layer " << sub.layer;
    };
    TextureHandle mips = device().createTexture(TextureDesc().setSize(16, 8).setFormat(Format::RGBA8_UNORM)
                                                    .setMipLevels(0).setUsage(TextureUsage::Sampled));
    for (uint32_t mip = 0; mip < mips->desc().mipLevels; ++mip) expectZero(mips, {mip, 0}, "rgba8 mip chain");
    TextureHandle cube = device().createTexture(TextureDesc().setSize(4, 4).setDimension(TextureDimension::TextureCube)
                                                    .setFormat(Format::RGBA16_FLOAT).setUsage(TextureUsage::Sampled));
    for (uint32_t face = 0; face < 6; ++face) expectZero(cube, {0, face}, "rgba16f cube");
    TextureHandle volume = device().createTexture(TextureDesc().setSize(4, 4, 3).setDimension(TextureDimension::Texture3D)
                                                      .setFormat(Format::R32_FLOAT).setUsage(TextureUsage::Sampled));
    for (uint32_t slice = 0; slice < 3; ++slice) expectZero(volume, {0, slice}, "r32f volume");
    expectZero(createTexture2D(Format::R32_UINT, 4, 4, TextureUsage::Sampled), {}, "r32ui");
    expectZero(createTexture2D(Format::D32_FLOAT, 4, 4, TextureUsage::RenderTarget), {}, "d32f");
}

}  // namespace
}  // namespace janus::rhi::test
