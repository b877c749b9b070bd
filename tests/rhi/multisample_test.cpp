// Multisampling: multisampled colour and depth attachments resolved at the end of a pass
// (TextureDesc::sampleCount, Attachment::resolveTo, GraphicsPipelineDesc::sampleCount), alpha to
// coverage (GraphicsPipelineDesc::alphaToCoverage), and the
// validation of every way to misuse them, with the same error code on every backend.
#include <set>

#include "backend_test.h"

namespace janus::rhi::test {
namespace {

constexpr uint32_t kSize = 32;
constexpr uint32_t kSamples = 4;   // every backend allows 4 for RGBA8 and D32F (GL 4.3, ES 3.0, Vulkan)

class MultisampleTest : public BackendTest {
protected:
    TextureHandle multisampled(Format format, uint32_t samples = kSamples) {
        return device().createTexture(TextureDesc()
                                          .setFormat(format)
                                          .setSize(kSize, kSize)
                                          .setUsage(TextureUsage::RenderTarget)
                                          .setSampleCount(samples)
                                          .setDebugName(fmt::format("{}x {}", samples, toString(format))));
    }
    TextureHandle resolveTarget(Format format = Format::RGBA8_UNORM) {
        return createTexture2D(format, kSize, kSize, TextureUsage::RenderTarget | TextureUsage::Sampled);
    }
    // The vertex colour pipeline into RGBA8 (and `depthFormat`) with `samples` samples.
    GraphicsPipelineDesc pipelineDesc(uint32_t samples, Format depthFormat = Format::Unknown, DepthState depth = {}) {
        GraphicsPipelineDesc desc;
        desc.setShaders(shader("rt_vertex_color_vert"), shader("rt_vertex_color_frag"))
            .addVertexBuffer({0, sizeof(ColorVertex), false})
            .addVertexAttribute({0, VertexFormat::Float4, 0, offsetof(ColorVertex, x)})
            .addVertexAttribute({1, VertexFormat::Float4, 0, offsetof(ColorVertex, r)})
            .addColorFormat(Format::RGBA8_UNORM)
            .setDepthFormat(depthFormat)
            .setDepth(depth)
            .setSampleCount(samples)
            .setDebugName(fmt::format("{}x colour", samples));
        return desc;
    }
    PipelineHandle pipeline(uint32_t samples, Format depthFormat = Format::Unknown, DepthState depth = {}) {
        return device().createGraphicsPipeline(pipelineDesc(samples, depthFormat, depth));
    }
    // rt_fullscreen_vert + rt_alpha_ramp_frag (white, alpha 0 at the left edge to 1 at the right)
    // into RGBA8 with `samples` samples.
    GraphicsPipelineDesc alphaRampDesc(uint32_t samples, bool alphaToCoverage) {
        GraphicsPipelineDesc desc;
        desc.setShaders(shader("rt_fullscreen_vert"), shader("rt_alpha_ramp_frag"))
            .addColorFormat(Format::RGBA8_UNORM)
            .setSampleCount(samples)
            .setAlphaToCoverage(alphaToCoverage)
            .setDebugName(fmt::format("{}x alpha ramp{}", samples, alphaToCoverage ? ", alpha to coverage" : ""));
        return desc;
    }
    // The resolved image, copied out in the same command list as the pass (so the resolve's
    // write and the copy's read meet the hazard tracking, which validation watches).
    std::vector<Rgba8> renderAndResolve(const RenderPassDesc& pass, const PipelineHandle& pipe,
                                        const std::vector<ColorVertex>& vertices, const TextureHandle& resolved) {
        BufferHandle vb = createBufferFrom(BufferUsage::Vertex, vertices);
        BufferHandle readback = createBuffer(BufferUsage::None, uint64_t(kSize) * kSize * 4);
        submit([&](ICommandList& cmd) {
            cmd.beginRenderPass(pass);
            cmd.setPipeline(pipe);
            cmd.setVertexBuffer(0, vb);
            cmd.draw(uint32_t(vertices.size()));
            cmd.endRenderPass();
            cmd.copyTextureToBuffer(readback, 0, resolved, {});
        });
        return readBufferAs<Rgba8>(readback);
    }
};
JANUS_INSTANTIATE_BACKEND_TESTS(MultisampleTest);

// Signed distance in pixels of pixel (x, y)'s centre from the edge a -> b (positive on the left
// of a -> b in pixel space, which for the counter-clockwise triangle below is inside).
double edgeDistance(std::array<double, 2> a, std::array<double, 2> b, double x, double y) {
    const double ex = b[0] - a[0], ey = b[1] - a[1];
    return (ex * (y - a[1]) - ey * (x - a[0])) / std::hypot(ex, ey);
}

// A white triangle in front of a red rectangle, with a blue rectangle behind both drawn last,
// into 4x colour and depth, resolved. Each pixel is the average of its four samples, so every
// value is a multiple of 255/4; pixels wholly inside or outside the triangle are exact; the
// triangle's edges have coverage between; the covered area is the triangle's; and no sample
// shows the blue rectangle (the depth test ran per sample).
TEST_P(MultisampleTest, ResolvesTheAverageOfEachPixelsSamples) {
    const TextureHandle color = multisampled(Format::RGBA8_UNORM);
    const TextureHandle depth = multisampled(Format::D32_FLOAT);
    const TextureHandle resolved = resolveTarget();
    const PipelineHandle pipe = pipeline(kSamples, Format::D32_FLOAT, DepthState{true, true, CompareOp::Less});
    const std::array<float, 6> ndc = {-0.8f, -0.7f, 0.75f, -0.2f, -0.3f, 0.85f};
    std::vector<ColorVertex> vertices = rectangle(-1.0f, -1.0f, 1.0f, 1.0f, {1.0f, 0.0f, 0.0f, 1.0f}, 0.5f);
    for (const ColorVertex& v : triangle(ndc, {1.0f, 1.0f, 1.0f, 1.0f}, 0.2f)) vertices.push_back(v);
    for (const ColorVertex& v : rectangle(-1.0f, -1.0f, 1.0f, 1.0f, {0.0f, 0.0f, 1.0f, 1.0f}, 0.8f)) vertices.push_back(v);
    RenderPassDesc pass;
    pass.addColor(Attachment::clear(color, {0.0f, 0.0f, 0.0f, 1.0f}).resolveTo(resolved));
    Attachment depthAttachment = Attachment::clearDepthTo(depth, 1.0f);
    depthAttachment.storeOp = StoreOp::DontCare;   // multisampled depth is not resolved
    pass.setDepth(depthAttachment);
    const std::vector<Rgba8> pixels = renderAndResolve(pass, pipe, vertices, resolved);
    ASSERT_EQ(pixels.size(), size_t(kSize) * kSize);

    // The triangle in pixel coordinates (row 0 = NDC y -1), counter-clockwise there.
    std::array<std::array<double, 2>, 3> corner;
    for (int i = 0; i < 3; ++i) corner[i] = {(ndc[2 * i] + 1.0) * 0.5 * kSize, (ndc[2 * i + 1] + 1.0) * 0.5 * kSize};
    const double area = 0.5 * std::abs((corner[1][0] - corner[0][0]) * (corner[2][1] - corner[0][1]) -
                                       (corner[2][0] - corner[0][0]) * (corner[1][1] - corner[0][1]));
    size_t partial = 0, checkedInside = 0, checkedOutside = 0;
    double covered = 0.0;
    for (uint32_t y = 0; y < kSize; ++y)
        for (uint32_t x = 0; x < kSize; ++x) {
            const Rgba8 p = pixels[y * kSize + x];
            SCOPED_TRACE(fmt::format("pixel ({}, {}) = ({}, {}, {}, {})", x, y, p.r, p.g, p.b, p.a));
            // White over red: red stays 255, green (= blue) is the triangle's coverage.
            EXPECT_EQ(p.r, 255);
            EXPECT_EQ(p.g, p.b);
            EXPECT_EQ(p.a, 255);
            const double coverage = p.g / 255.0;
            const double steps = coverage * kSamples;
            // Multiples of 1/4 stored as 8 bits: within one step of rounding.
            EXPECT_LE(std::abs(steps - std::round(steps)) * 255.0 / kSamples, 1.0);
            covered += coverage;
            double nearest = 1e9;
            for (int e = 0; e < 3; ++e)
                nearest = std::min(nearest, edgeDistance(corner[e], corner[(e + 1) % 3], x + 0.5, y + 0.5));
            // A pixel whose square lies wholly on one side of every edge (half its diagonal: 0.71).
            if (nearest > 0.75) {
                EXPECT_EQ(p.g, 255) << "wholly inside the triangle";
                ++checkedInside;
            } else if (nearest < -0.75 && std::abs(nearest) > 0.75) {
                bool outside = false;
                for (int e = 0; e < 3; ++e)
                    outside = outside || edgeDistance(corner[e], corner[(e + 1) % 3], x + 0.5, y + 0.5) < -0.75;
                if (outside) {
                    EXPECT_EQ(p.g, 0) << "wholly outside the triangle";
                    ++checkedOutside;
                }
            }
            if (p.g > 0 && p.g < 255) ++partial;
        }
    EXPECT_GT(checkedInside, 100u);
    EXPECT_GT(checkedOutside, 300u);
    // One sample per pixel would leave none partly covered; 4 samples give the edges steps.
    EXPECT_GE(partial, 30u) << "too few edge pixels between 0 and 255: not multisampled?";
    // Four samples per pixel estimate each edge pixel's coverage to a quarter, errors that
    // cancel along the edges: the covered area is the triangle's within 2 %.
    EXPECT_NEAR(covered, area, 0.02 * area);
}

// A multisampled texture reads as zero until something is rendered to it, as every new texture
// does: loading a fresh one and resolving it gives zeros (GL clears a renderbuffer on its first
// pass; Vulkan clears every image when it is made).
TEST_P(MultisampleTest, ANewMultisampledTextureLoadsAsZero) {
    const TextureHandle color = multisampled(Format::RGBA8_UNORM);
    const TextureHandle resolved = resolveTarget();
    submit([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(resolved, {0.5f, 0.5f, 0.5f, 0.5f})));
        cmd.endRenderPass();
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::load(color).resolveTo(resolved)));
        cmd.endRenderPass();
    });
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(resolved), std::vector<Rgba8>(kSize * kSize, Rgba8{}), kSize));
}

// A pass's samples stay for the next pass that loads them: two passes drawing two halves,
// each resolving, the second resolve shows both (and the first only its own).
TEST_P(MultisampleTest, LoadKeepsTheSamplesOfThePreviousPass) {
    const TextureHandle color = multisampled(Format::RGBA8_UNORM);
    const TextureHandle first = resolveTarget(), second = resolveTarget();
    const PipelineHandle pipe = pipeline(kSamples);
    const std::vector<ColorVertex> left = rectangle(-1.0f, -1.0f, 0.0f, 1.0f, {0.0f, 1.0f, 0.0f, 1.0f});
    const std::vector<ColorVertex> right = rectangle(0.0f, -1.0f, 1.0f, 1.0f, {0.0f, 0.0f, 1.0f, 1.0f});
    renderAndResolve(RenderPassDesc().addColor(Attachment::clear(color, {1.0f, 0.0f, 0.0f, 1.0f}).resolveTo(first)), pipe,
                     left, first);
    const std::vector<Rgba8> both =
        renderAndResolve(RenderPassDesc().addColor(Attachment::load(color).resolveTo(second)), pipe, right, second);
    const std::vector<Rgba8> one = readTextureAs<Rgba8>(first);
    // The halves' edge runs between pixel columns (x = 16 exactly): no pixel is partly covered.
    for (uint32_t y = 0; y < kSize; ++y)
        for (uint32_t x = 0; x < kSize; ++x) {
            const bool isLeft = x < kSize / 2;
            EXPECT_EQ(both[y * kSize + x], isLeft ? (Rgba8{0, 255, 0, 255}) : (Rgba8{0, 0, 255, 255})) << x << ", " << y;
            EXPECT_EQ(one[y * kSize + x], isLeft ? (Rgba8{0, 255, 0, 255}) : (Rgba8{255, 0, 0, 255})) << x << ", " << y;
        }
}

// A resolve writes the subresource it names and nothing else: mip 1 of a 2D texture, face 4 of a
// cube and slice 2 of a volume (the clear colour of a pass without draws, in every pixel). On
// lavapipe a resolve attachment's view of face 4 wrote face 0; Vulkan resolves layers other than
// 0 after the pass with vkCmdResolveImage since.
TEST_P(MultisampleTest, ResolvesIntoTheSubresourceItNames) {
    const TextureHandle color = multisampled(Format::RGBA8_UNORM);
    const TextureHandle mips = device().createTexture(TextureDesc()
                                                          .setSize(2 * kSize, 2 * kSize)
                                                          .setMipLevels(2)
                                                          .setUsage(TextureUsage::RenderTarget | TextureUsage::Sampled));
    const TextureHandle cube = device().createTexture(TextureDesc()
                                                          .setDimension(TextureDimension::TextureCube)
                                                          .setSize(kSize, kSize)
                                                          .setUsage(TextureUsage::RenderTarget | TextureUsage::Sampled));
    const Color first = {0.2f, 0.4f, 0.6f, 1.0f}, second = {1.0f, 0.8f, 0.0f, 0.4f};
    submit([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(color, first).resolveTo(mips, {1, 0})));
        cmd.endRenderPass();
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(color, second).resolveTo(cube, {0, 4})));
        cmd.endRenderPass();
    });
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(mips, {1, 0}), std::vector<Rgba8>(kSize * kSize, toRgba8(first)), kSize));
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(mips, {0, 0}), std::vector<Rgba8>(4 * kSize * kSize, Rgba8{}), 2 * kSize));
    for (uint32_t face = 0; face < 6; ++face)
        EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(cube, {0, face}),
                                std::vector<Rgba8>(kSize * kSize, face == 4 ? toRgba8(second) : Rgba8{}), kSize))
            << "face " << face;
    if (!caps().has(Capability::RenderToVolumeSlice)) return;
    // Slice 2 of a volume (layer = slice).
    const TextureHandle volume = device().createTexture(TextureDesc()
                                                            .setDimension(TextureDimension::Texture3D)
                                                            .setSize(kSize, kSize, 4)
                                                            .setUsage(TextureUsage::RenderTarget | TextureUsage::Sampled));
    submit([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(color, first).resolveTo(volume, {0, 2})));
        cmd.endRenderPass();
    });
    for (uint32_t slice = 0; slice < 4; ++slice)
        EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(volume, {0, slice}),
                                std::vector<Rgba8>(kSize * kSize, slice == 2 ? toRgba8(first) : Rgba8{}), kSize))
            << "slice " << slice;
}

TEST_P(MultisampleTest, EveryMisuseHasOneErrorCodeOnEveryBackend) {
    constexpr ErrorCode kDesc = ErrorCode::InvalidDescription;
    constexpr ErrorCode kUsage = ErrorCode::InvalidUsage;
    constexpr ErrorCode kUnsupported = ErrorCode::UnsupportedCapability;
    IDevice& dev = device();
    const TextureHandle color = multisampled(Format::RGBA8_UNORM);
    const TextureHandle depth = multisampled(Format::D32_FLOAT);
    const TextureHandle resolved = resolveTarget();
    const TextureHandle single = resolveTarget();
    const TextureHandle halfFloat = resolveTarget(Format::RGBA16_FLOAT);
    const TextureHandle sampledOnly = createTexture2D(Format::RGBA8_UNORM, kSize, kSize, TextureUsage::Sampled);
    const TextureHandle smaller = createTexture2D(Format::RGBA8_UNORM, kSize / 2, kSize / 2, TextureUsage::RenderTarget);
    const BufferHandle buffer = createBuffer(BufferUsage::None, uint64_t(kSize) * kSize * 4);
    auto texture = [&](TextureDesc desc) { return [&dev, desc] { dev.createTexture(desc); }; };
    const TextureDesc base = TextureDesc().setFormat(Format::RGBA8_UNORM).setSize(kSize, kSize).setUsage(TextureUsage::RenderTarget);
    auto pass = [&](RenderPassDesc desc) {
        return [this, desc] { submit([&](ICommandList& cmd) { cmd.beginRenderPass(desc); cmd.endRenderPass(); }); };
    };
    // A triangle drawn into `target` with a pipeline of `samples` samples.
    auto drawWith = [this](uint32_t samples, const TextureHandle& target) {
        return [this, samples, target] {
            const PipelineHandle pipe = pipeline(samples);
            const BufferHandle vb = createBufferFrom(BufferUsage::Vertex, triangle({-1, -1, 1, -1, 0, 1}, {1, 1, 1, 1}));
            submit([&](ICommandList& cmd) {
                cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
                cmd.setPipeline(pipe);
                cmd.setVertexBuffer(0, vb);
                cmd.draw(3);
                cmd.endRenderPass();
            });
        };
    };
    struct Mistake {
        const char* what;
        ErrorCode code;
        std::vector<std::string> mentions;
        std::function<void()> make;
    };
    const std::vector<Mistake> mistakes = {
        {"a sample count that is no power of two", kDesc, {"sampleCount is 3"}, texture(TextureDesc(base).setSampleCount(3))},
        {"a sample count of 0", kDesc, {"sampleCount is 0"}, texture(TextureDesc(base).setSampleCount(0))},
        {"a sample count the format does not allow", kUnsupported, {"sampleCount 64", "FormatCapabilities::sampleCounts"},
         texture(TextureDesc(base).setSampleCount(64))},
        {"a multisampled integer texture", kUnsupported, {"sampleCount 4", "r32ui"},
         texture(TextureDesc(base).setFormat(Format::R32_UINT).setSampleCount(4))},
        {"a multisampled texture that is also sampled", kDesc, {"RenderTarget alone"},
         texture(TextureDesc(base).setUsage(TextureUsage::RenderTarget | TextureUsage::Sampled).setSampleCount(4))},
        {"a multisampled texture with mips", kDesc, {"mipLevels 1"}, texture(TextureDesc(base).setMipLevels(2).setSampleCount(4))},
        {"a multisampled cube", kDesc, {"Texture2D with one layer"},
         texture(TextureDesc(base).setDimension(TextureDimension::TextureCube).setSampleCount(4))},
        {"a pipeline with 3 samples", kDesc, {"sampleCount is 3"}, [&] { dev.createGraphicsPipeline(pipelineDesc(3)); }},
        {"readTexture of a multisampled texture", kUsage, {"multisampled", "resolve"}, [&] { dev.readTexture(color, {}); }},
        {"copyTextureToBuffer from a multisampled texture", kUsage, {"multisampled", "resolve"},
         [&] { submit([&](ICommandList& cmd) { cmd.copyTextureToBuffer(buffer, 0, color, {}); }); }},
        {"copyTexture into a multisampled texture", kUsage, {"multisampled"},
         [&] { submit([&](ICommandList& cmd) { cmd.copyTexture(color, {}, single, {}); }); }},
        {"attachments with different sample counts", kDesc, {"same sampleCount"},
         pass(RenderPassDesc().addColor(Attachment::clear(color)).setDepth(Attachment::clearDepthTo(
             createTexture2D(Format::D32_FLOAT, kSize, kSize, TextureUsage::RenderTarget))))},
        {"resolving a single-sampled attachment", kDesc, {"single-sampled"},
         pass(RenderPassDesc().addColor(Attachment::clear(single).resolveTo(resolved)))},
        {"resolving into a multisampled texture", kDesc, {"resolveTexture", "multisampled"},
         pass(RenderPassDesc().addColor(Attachment::clear(color).resolveTo(multisampled(Format::RGBA8_UNORM))))},
        {"resolving into another format", kDesc, {"rgba16f", "formats must be the same"},
         pass(RenderPassDesc().addColor(Attachment::clear(color).resolveTo(halfFloat)))},
        {"resolving into another size", kDesc, {"16x16", "same size"},
         pass(RenderPassDesc().addColor(Attachment::clear(color).resolveTo(smaller)))},
        {"resolving into a texture that is no render target", kDesc, {"RenderTarget"},
         pass(RenderPassDesc().addColor(Attachment::clear(color).resolveTo(sampledOnly)))},
        {"resolving depth", kDesc, {"depth attachment cannot be resolved"},
         pass(RenderPassDesc().addColor(Attachment::clear(color)).setDepth(Attachment::clearDepthTo(depth).resolveTo(
             createTexture2D(Format::D32_FLOAT, kSize, kSize, TextureUsage::RenderTarget))))},
        {"two attachments resolving into one texture", kDesc, {"resolves into texture"},
         pass(RenderPassDesc()
                  .addColor(Attachment::clear(color).resolveTo(resolved))
                  .addColor(Attachment::clear(multisampled(Format::RGBA8_UNORM)).resolveTo(resolved)))},
        {"a single-sampled pipeline in a multisampled pass", kUsage, {"1 sample(s)", "have 4"}, drawWith(1, color)},
        {"a multisampled pipeline in a single-sampled pass", kUsage, {"4 sample(s)", "have 1"}, drawWith(kSamples, single)},
        {"alpha to coverage with one sample", kDesc, {"alphaToCoverage needs a multisampled pipeline", "sampleCount 1"},
         [&] { dev.createGraphicsPipeline(alphaRampDesc(1, true)); }},
        {"alpha to coverage in a depth-only pipeline", kDesc, {"alphaToCoverage needs a colour attachment"},
         [&] {
             GraphicsPipelineDesc desc = alphaRampDesc(kSamples, true);
             desc.colorFormats.clear();
             desc.blend.clear();
             desc.setDepthFormat(Format::D32_FLOAT).setDepth(DepthState{true, true, CompareOp::Less});
             dev.createGraphicsPipeline(desc);
         }},
        {"alpha to coverage from a shader without a colour output", kDesc, {"alphaToCoverage", "rt_no_color_frag", "location 0"},
         [&] {
             GraphicsPipelineDesc desc = alphaRampDesc(kSamples, true);
             desc.fragmentShader = shader("rt_no_color_frag");
             dev.createGraphicsPipeline(desc);
         }},
    };
    for (const Mistake& m : mistakes) EXPECT_TRUE(throwsRhiError(m.make, m.code, m.mentions)) << m.what;
}

// Alpha to coverage (GraphicsPipelineDesc::alphaToCoverage): a white fullscreen triangle whose
// alpha ramps from 0 to 1 across the target covers about alpha x 4 of each pixel's samples, so
// the resolved image ramps too: every pixel a multiple of 1/4, each column's mean near its
// alpha (which samples a driver picks, and whether it varies them between pixels, is its own),
// and at least three levels between black and white. The same pipeline without it covers every
// sample; drawn right after the one with it (GL keeps the state on the context), it still does.
TEST_P(MultisampleTest, AlphaToCoverageCoversAsManySamplesAsAlphaSays) {
    const PipelineHandle withCoverage = device().createGraphicsPipeline(alphaRampDesc(kSamples, true));
    const PipelineHandle without = device().createGraphicsPipeline(alphaRampDesc(kSamples, false));
    const TextureHandle color = multisampled(Format::RGBA8_UNORM);
    const TextureHandle resolved = resolveTarget(), resolvedWithout = resolveTarget();
    BufferHandle readback = createBuffer(BufferUsage::None, uint64_t(kSize) * kSize * 4 * 2);
    submit([&](ICommandList& cmd) {
        for (const auto& [pipe, target] : {std::pair{withCoverage, resolved}, std::pair{without, resolvedWithout}}) {
            cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(color, {0.0f, 0.0f, 0.0f, 0.0f}).resolveTo(target)));
            cmd.setPipeline(pipe);
            cmd.draw(3);
            cmd.endRenderPass();
        }
        cmd.copyTextureToBuffer(readback, 0, resolved, {});
        cmd.copyTextureToBuffer(readback, uint64_t(kSize) * kSize * 4, resolvedWithout, {});
    });
    const std::vector<Rgba8> pixels = readBufferAs<Rgba8>(readback);
    ASSERT_EQ(pixels.size(), size_t(kSize) * kSize * 2);
    std::set<int> levels;
    double total = 0.0;
    for (uint32_t x = 0; x < kSize; ++x) {
        double column = 0.0;
        for (uint32_t y = 0; y < kSize; ++y) {
            const Rgba8 p = pixels[y * kSize + x];
            const double steps = p.r / 255.0 * kSamples;
            EXPECT_LE(std::abs(steps - std::round(steps)) * 255.0 / kSamples, 1.0)
                << "pixel (" << x << ", " << y << ") = " << int(p.r) << ", no multiple of 1/4";
            levels.insert(int(std::lround(steps)));
            column += p.r / 255.0;
            EXPECT_EQ(pixels[size_t(kSize) * kSize + y * kSize + x].r, 255) << "without alpha to coverage, pixel (" << x << ", " << y << ")";
        }
        column /= kSize;
        total += column;
        const double alpha = (x + 0.5) / kSize;
        // A quarter: the coverage is alpha rounded to whole samples (or dithered around it).
        EXPECT_NEAR(column, alpha, 0.25) << "column " << x;
    }
    // The mean alpha is 1/2; rounding each pixel's alpha x 4 up (llvmpipe and lavapipe: any alpha
    // above 0 covers a sample) or down moves the mean by 1/8 at most.
    EXPECT_NEAR(total / kSize, 0.5, 0.125 + 1.0 / 255.0);   // and the 8-bit storage of quarters
    EXPECT_GE(levels.size(), 3u) << "alpha to coverage gave only full or no coverage";
}

// What `janus info` shows: every backend allows 4 samples where GL 4.3, ES 3.0 and Vulkan
// promise them, and no integer format is multisampled.
TEST_P(MultisampleTest, FormatTableListsTheSampleCounts) {
    for (Format format : {Format::RGBA8_UNORM, Format::D32_FLOAT}) {
        const FormatCapabilities c = device().formatCapabilities(format);
        EXPECT_TRUE(c.supportsSampleCount(1) && c.supportsSampleCount(4)) << toString(format) << ": " << c.sampleCounts;
    }
    for (Format format : {Format::R32_UINT, Format::RGBA32_UINT})
        EXPECT_EQ(device().formatCapabilities(format).sampleCounts, 1u) << toString(format);
    for (const FormatInfo& info : allFormats()) {
        const FormatCapabilities c = device().formatCapabilities(info.format);
        EXPECT_TRUE(c.supportsSampleCount(1)) << info.name;
        if (!c.has(FormatCapability::RenderTarget)) EXPECT_EQ(c.sampleCounts, 1u) << info.name;
    }
}

}  // namespace
}  // namespace janus::rhi::test
