// Orientation: row 0 is NDC y = -1 and texture v = 0 on every backend, for rendering,
// sampling and readback (no backend flips), and the conventions each backend reports.
#include "backend_test.h"

namespace janus::rhi::test {
namespace {

class OrientationTest : public BackendTest {};
JANUS_INSTANTIATE_BACKEND_TESTS(OrientationTest);

// The pattern, spelled out for 8x8 so a reader can see the expected layout: R red triangle at
// the top-left, G green square top-right, B blue square bottom-left, . cleared black.
constexpr const char* kExpectedPattern8x8[] = {
    "RRR...GG",
    "RR....GG",
    "R.......",
    "........",
    "........",
    "........",
    "BB......",
    "BB......",
};

TEST_P(OrientationTest, PatternLandsAtTheExpectedRows) {
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 8, 8, TextureUsage::RenderTarget);
    drawVertices(RenderPassDesc().addColor(Attachment::clear(target, {0, 0, 0, 1})), colorPipeline(Format::RGBA8_UNORM),
                 orientationPattern());
    std::vector<Rgba8> expected;
    for (const char* row : kExpectedPattern8x8)
        for (const char* c = row; *c; ++c)
            expected.push_back(*c == 'R' ? Rgba8{255, 0, 0, 255} : *c == 'G' ? Rgba8{0, 255, 0, 255}
                               : *c == 'B' ? Rgba8{0, 0, 255, 255} : Rgba8{0, 0, 0, 255});
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(target), expected, 8)) << "row 0 must be NDC y = -1 (top)";
    // The CPU reference rasteriser agrees with the picture above (it checks the other sizes).
    std::vector<Rgba8> reference;
    for (const Color& c : rasterize(orientationPattern(), 8, 8, {0, 0, 0, 1})) reference.push_back(toRgba8(c));
    EXPECT_TRUE(imagesEqual(reference, expected, 8)) << "test bug: the reference rasteriser disagrees";
}

// Varyings are sampled at pixel centres on every backend: pixel (x, y) of a W x H target sees
// the full-screen triangle's vUv at ((x + 0.5) / W, (y + 0.5) / H), row 0 at v = 0, and window x
// x + 0.5. A half-pixel offset (as a y flip done one row off would give) moves every minified
// texture lookup; on NVIDIA gl and gles differ from vulkan along the edges of minified label
// textures (docs/TESTING.md, "On a GPU machine"), and this tells rasterisation apart.
TEST_P(OrientationTest, VaryingsAreSampledAtPixelCentres) {
    constexpr uint32_t kWidth = 16, kHeight = 8;   // not square: a transpose shows up too
    if (!device().formatCapabilities(Format::RGBA32_FLOAT).has(FormatCapability::RenderTarget))
        GTEST_SKIP() << "rgba32f is no render target here";
    TextureHandle target = createTexture2D(Format::RGBA32_FLOAT, kWidth, kHeight, TextureUsage::RenderTarget);
    drawFullscreen(RenderPassDesc().addColor(Attachment::clear(target)), fullscreenPipeline("rt_uv_frag", Format::RGBA32_FLOAT), {});
    const std::vector<Color> seen = readTextureAs<Color>(target);
    ASSERT_EQ(seen.size(), size_t(kWidth) * kHeight);
    for (uint32_t y = 0; y < kHeight; ++y)
        for (uint32_t x = 0; x < kWidth; ++x) {
            const Color& c = seen[size_t(y) * kWidth + x];
            // 1e-5: the interpolation's float rounding; half a pixel would be 0.03 or more here.
            EXPECT_NEAR(c[0], (x + 0.5f) / kWidth, 1e-5f) << "u at (" << x << ", " << y << ")";
            EXPECT_NEAR(c[1], (y + 0.5f) / kHeight, 1e-5f) << "v at (" << x << ", " << y << ")";
            EXPECT_EQ(c[2], x + 0.5f) << "gl_FragCoord.x at (" << x << ", " << y << ")";
        }
}

// A texture uploaded with texel (0, 0) distinct must show it at row 0, column 0 of a target
// that samples it: a Y flip on upload, in sampling or in readback shows up here.
TEST_P(OrientationTest, SampledTexelZeroReachesRowZero) {
    const uint32_t width = 4, height = 8;   // not square: a transpose shows up too
    std::vector<Rgba8> texels;
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) texels.push_back({uint8_t(60 * x), uint8_t(30 * y), uint8_t(x == 0 && y == 0 ? 255 : 0), 255});
    TextureHandle texture = createTexture2D(Format::RGBA8_UNORM, width, height);
    device().writeTexture(texture, {}, texels.data(), texels.size() * sizeof(Rgba8));
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, width, height, TextureUsage::RenderTarget);
    BindingSetHandle bindings =
        device().createBindingSet(BindingSetDesc().add(BindingItem::sampledTexture(0, texture, nearestClampSampler())));
    drawFullscreen(RenderPassDesc().addColor(Attachment::clear(target)), fullscreenPipeline("rt_sample_2d_frag", Format::RGBA8_UNORM),
                   {bindings});
    std::vector<Rgba8> result = readTextureAs<Rgba8>(target);
    ASSERT_FALSE(result.empty());
    EXPECT_EQ(result[0], (Rgba8{0, 0, 255, 255})) << "texel (0, 0) must reach row 0, column 0";
    EXPECT_TRUE(imagesEqual(result, texels, width));
}

// Rendering into a texture, sampling it in a second pass and copying that to a third texture,
// all in one command list: both passes use the same convention, so the pattern comes out
// unchanged (a flip in either pass shows), and each step must see the previous one (barriers).
TEST_P(OrientationTest, RenderSampleAndCopyInOneCommandListPreservePattern) {
    TextureHandle first = createTexture2D(Format::RGBA8_UNORM, 8, 8, TextureUsage::RenderTarget | TextureUsage::Sampled);
    TextureHandle second = createTexture2D(Format::RGBA8_UNORM, 8, 8, TextureUsage::RenderTarget);
    TextureHandle copy = createTexture2D(Format::RGBA8_UNORM, 8, 8);
    PipelineHandle drawPattern = colorPipeline(Format::RGBA8_UNORM);
    PipelineHandle sample = fullscreenPipeline("rt_sample_2d_frag", Format::RGBA8_UNORM);
    BufferHandle vertices = createBufferFrom(BufferUsage::Vertex, orientationPattern());
    BindingSetHandle bindings =
        device().createBindingSet(BindingSetDesc().add(BindingItem::sampledTexture(0, first, nearestClampSampler())));
    submit([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(first, {0, 0, 0, 1})));
        cmd.setPipeline(drawPattern);
        cmd.setVertexBuffer(0, vertices);
        cmd.draw(uint32_t(orientationPattern().size()));
        cmd.endRenderPass();
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(second)));
        cmd.setPipeline(sample);
        cmd.setBindingSet(0, bindings);
        cmd.draw(3);
        cmd.endRenderPass();
        cmd.copyTexture(copy, {}, second, {});
    });
    std::vector<Rgba8> expected;
    for (const Color& c : rasterize(orientationPattern(), 8, 8, {0, 0, 0, 1})) expected.push_back(toRgba8(c));
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(first), expected, 8)) << "rendered";
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(second), expected, 8)) << "sampled";
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(copy), expected, 8)) << "copied";
}

TEST_P(OrientationTest, ReportsNativeConventions) {
    const Conventions& c = caps().conventions;
    bool vulkan = backend() == Backend::Vulkan;
    // GL and GLES report [0, 1] clip depth as native where clip control exists
    // (ConventionsTest.NativeClipDepthKeepsTinyDepths checks that claim).
    if (vulkan) {
        EXPECT_TRUE(c.nativeClipDepthZeroToOne);
    }
    EXPECT_EQ(c.nativeFramebufferOriginTopLeft, vulkan) << "GL and GLES address rows bottom-up natively";
    EXPECT_EQ(device().info().backend, backend());
    EXPECT_FALSE(device().info().apiVersion.empty());
    EXPECT_FALSE(device().info().deviceName.empty());
}

}  // namespace
}  // namespace janus::rhi::test
