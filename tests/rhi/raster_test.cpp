// Rasteriser state: depth range [0, 1] on every backend, depth test and write, polygon offset,
// winding and culling.
#include "backend_test.h"

namespace janus::rhi::test {
namespace {

class RasterTest : public BackendTest {
protected:
    TextureHandle color8x8() { return createTexture2D(Format::RGBA8_UNORM, 8, 8, TextureUsage::RenderTarget); }
    TextureHandle depth8x8() { return createTexture2D(Format::D32_FLOAT, 8, 8, TextureUsage::RenderTarget | TextureUsage::Sampled); }
    RenderPassDesc pass(const TextureHandle& color, const TextureHandle& depth, float clearDepth = 1.0f) {
        return RenderPassDesc().addColor(Attachment::clear(color, {0, 0, 0, 1})).setDepth(Attachment::clearDepthTo(depth, clearDepth));
    }
};
JANUS_INSTANTIATE_BACKEND_TESTS(RasterTest);

const Color kRed = {1, 0, 0, 1}, kGreen = {0, 1, 0, 1};

// The [-1, 1] vs [0, 1] pitfall: NDC z 0.25 must be stored as 0.25 on every backend (GL maps
// z' = 2z - w and back, which is exact for these values, so the comparison is exact).
TEST_P(RasterTest, DepthIsStoredInZeroToOne) {
    TextureHandle color = color8x8(), depth = depth8x8();
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_UNORM, Format::D32_FLOAT, {}, {true, true, CompareOp::Always});
    std::vector<ColorVertex> quads = rectangle(-1, -1, 0, 1, kRed, 0.25f);
    std::vector<ColorVertex> right = rectangle(0, -1, 1, 1, kGreen, 0.75f);
    quads.insert(quads.end(), right.begin(), right.end());
    drawVertices(pass(color, depth), pipeline, quads);
    std::vector<float> values = readTextureAs<float>(depth);
    std::vector<float> expected(64);
    for (size_t i = 0; i < 64; ++i) expected[i] = i % 8 < 4 ? 0.25f : 0.75f;
    EXPECT_TRUE(imagesEqual(values, expected, 8));
}

// A depth-only pass (shadow-map style): no colour attachment at all.
TEST_P(RasterTest, DepthOnlyPassWritesDepth) {
    TextureHandle depth = depth8x8();
    PipelineHandle pipeline = colorPipeline(Format::Unknown, Format::D32_FLOAT, {}, {true, true, CompareOp::Less});
    drawVertices(RenderPassDesc().setDepth(Attachment::clearDepthTo(depth, 1.0f)), pipeline,
                 rectangle(-1, -1, 0, 0, kRed, 0.5f));
    std::vector<float> expected(64, 1.0f);
    for (size_t i = 0; i < 64; ++i)
        if (i % 8 < 4 && i / 8 < 4) expected[i] = 0.5f;
    EXPECT_TRUE(imagesEqual(readTextureAs<float>(depth), expected, 8)) << "top-left quadrant at 0.5";
}

TEST_P(RasterTest, DepthClearValueIsStored) {
    TextureHandle color = color8x8(), depth = depth8x8();
    submit([&](ICommandList& cmd) { cmd.beginRenderPass(pass(color, depth, 0.375f)); cmd.endRenderPass(); });
    EXPECT_EQ(readTextureAs<float>(depth), std::vector<float>(64, 0.375f));
}

TEST_P(RasterTest, DepthTestKeepsTheNearestWhateverTheOrder) {
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_UNORM, Format::D32_FLOAT, {}, {true, true, CompareOp::Less});
    std::vector<ColorVertex> nearLeft = rectangle(-1, -1, 0.5f, 1, kRed, 0.25f);
    std::vector<ColorVertex> farAll = rectangle(-1, -1, 1, 1, kGreen, 0.75f);
    for (bool nearFirst : {true, false}) {
        SCOPED_TRACE(nearFirst ? "near drawn first" : "far drawn first");
        TextureHandle color = color8x8(), depth = depth8x8();
        std::vector<ColorVertex> vertices = nearFirst ? nearLeft : farAll;
        const std::vector<ColorVertex>& second = nearFirst ? farAll : nearLeft;
        vertices.insert(vertices.end(), second.begin(), second.end());
        drawVertices(pass(color, depth), pipeline, vertices);
        std::vector<Rgba8> expectedColor(64);
        std::vector<float> expectedDepth(64);
        for (size_t i = 0; i < 64; ++i) {
            bool nearCovers = i % 8 < 6;
            expectedColor[i] = nearCovers ? Rgba8{255, 0, 0, 255} : Rgba8{0, 255, 0, 255};
            expectedDepth[i] = nearCovers ? 0.25f : 0.75f;
        }
        EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(color), expectedColor, 8));
        EXPECT_TRUE(imagesEqual(readTextureAs<float>(depth), expectedDepth, 8));
    }
}

TEST_P(RasterTest, DepthWriteDisabledLeavesDepthButTestsIt) {
    TextureHandle color = color8x8(), depth = depth8x8();
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_UNORM, Format::D32_FLOAT, {}, {true, false, CompareOp::Less});
    std::vector<ColorVertex> vertices = rectangle(-1, -1, 1, 1, kRed, 0.25f);
    drawVertices(pass(color, depth, 0.5f), pipeline, vertices);
    EXPECT_EQ(readTextureAs<float>(depth), std::vector<float>(64, 0.5f)) << "depth write was off";
    EXPECT_EQ(readTextureAs<Rgba8>(color), std::vector<Rgba8>(64, Rgba8{255, 0, 0, 255})) << "0.25 < 0.5 passes";
    drawVertices(pass(color, depth, 0.125f), pipeline, vertices);
    EXPECT_EQ(readTextureAs<Rgba8>(color), std::vector<Rgba8>(64, Rgba8{0, 0, 0, 255})) << "0.25 < 0.125 fails";
}

TEST_P(RasterTest, PolygonOffsetPushesDepth) {
    auto depthWith = [&](bool bias) {
        TextureHandle color = color8x8(), depth = depth8x8();
        RasterState raster;
        raster.depthBiasEnable = bias;
        raster.depthBiasConstant = 16.0f;
        PipelineHandle pipeline = colorPipeline(Format::RGBA8_UNORM, Format::D32_FLOAT, raster, {true, true, CompareOp::Always});
        drawVertices(pass(color, depth), pipeline, rectangle(-1, -1, 1, 1, kRed, 0.5f));
        return readTextureAs<float>(depth);
    };
    std::vector<float> plain = depthWith(false), biased = depthWith(true);
    ASSERT_EQ(plain.size(), 64u);
    ASSERT_EQ(biased.size(), 64u);
    EXPECT_EQ(plain, std::vector<float>(64, 0.5f));
    // 16 units of the minimum resolvable difference: its size depends on the implementation
    // (2^-24 near 0.5 for D32F), so check the direction and a generous upper bound.
    for (float d : biased) {
        EXPECT_GT(d, 0.5f);
        EXPECT_LT(d, 0.51f);
    }
}

// Left: counter-clockwise in the image (top-left, bottom-left, top-centre). Right: clockwise.
std::vector<ColorVertex> windingPair() {
    std::vector<ColorVertex> v = triangle({-1, -1, -1, 1, 0, -1}, kRed);
    std::vector<ColorVertex> cw = triangle({0, -1, 1, -1, 0, 1}, kGreen);
    v.insert(v.end(), cw.begin(), cw.end());
    return v;
}

TEST_P(RasterTest, CullingFollowsImageWinding) {
    struct Case { const char* name; CullMode cull; FrontFace front; bool keepCcw, keepCw; };
    for (const Case& c : {Case{"ccw front, cull back", CullMode::Back, FrontFace::CounterClockwise, true, false},
                          Case{"ccw front, cull front", CullMode::Front, FrontFace::CounterClockwise, false, true},
                          Case{"cw front, cull back", CullMode::Back, FrontFace::Clockwise, false, true},
                          Case{"no culling", CullMode::None, FrontFace::CounterClockwise, true, true}}) {
        SCOPED_TRACE(c.name);
        TextureHandle color = color8x8();
        RasterState raster;
        raster.cullMode = c.cull;
        raster.frontFace = c.front;
        drawVertices(RenderPassDesc().addColor(Attachment::clear(color, {0, 0, 0, 1})), colorPipeline(Format::RGBA8_UNORM, Format::Unknown, raster),
                     windingPair());
        std::vector<ColorVertex> kept;
        std::vector<ColorVertex> all = windingPair();
        if (c.keepCcw) kept.insert(kept.end(), all.begin(), all.begin() + 3);
        if (c.keepCw) kept.insert(kept.end(), all.begin() + 3, all.end());
        std::vector<Rgba8> expected;
        for (const Color& px : rasterize(kept, 8, 8, {0, 0, 0, 1})) expected.push_back(toRgba8(px));
        EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(color), expected, 8));
    }
}

TEST_P(RasterTest, TriangleStripCoversTheRectangle) {
    TextureHandle color = color8x8();
    GraphicsPipelineDesc desc;
    desc.setShaders(shader("rt_vertex_color_vert"), shader("rt_vertex_color_frag"))
        .addVertexBuffer({0, sizeof(ColorVertex), false})
        .addVertexAttribute({0, VertexFormat::Float4, 0, offsetof(ColorVertex, x)})
        .addVertexAttribute({1, VertexFormat::Float4, 0, offsetof(ColorVertex, r)})
        .setTopology(PrimitiveTopology::TriangleStrip)
        .addColorFormat(Format::RGBA8_UNORM);
    // The bottom half of the target as a 4-vertex strip; a list would draw one triangle.
    std::vector<ColorVertex> strip = {{-1, 0, 0, 1, 1, 0, 0, 1}, {-1, 1, 0, 1, 1, 0, 0, 1},
                                      {1, 0, 0, 1, 1, 0, 0, 1},  {1, 1, 0, 1, 1, 0, 0, 1}};
    drawVertices(RenderPassDesc().addColor(Attachment::clear(color, {0, 0, 0, 1})), device().createGraphicsPipeline(desc), strip);
    std::vector<Rgba8> expected(64, Rgba8{0, 0, 0, 255});
    for (size_t i = 32; i < 64; ++i) expected[i] = {255, 0, 0, 255};
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(color), expected, 8)) << "rows 4-7 red";
}

// NDC of the centre of pixel (x, y) of an 8x8 target (row 0 on top, as everywhere in the RHI).
ColorVertex pixelCenter(float x, float y, std::array<float, 4> c) {
    return {(x + 0.5f) / 4.0f - 1.0f, (y + 0.5f) / 4.0f - 1.0f, 0, 1, c[0], c[1], c[2], c[3]};
}

// Points are one pixel each (the vertex shader writes gl_PointSize 1), exactly where they are.
TEST_P(RasterTest, PointListDrawsOnePixelPerPoint) {
    TextureHandle color = color8x8();
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_UNORM, Format::Unknown, {}, {}, {}, PrimitiveTopology::PointList);
    const std::vector<ColorVertex> points = {pixelCenter(1, 2, kRed), pixelCenter(6, 5, kGreen), pixelCenter(3, 7, kRed)};
    drawVertices(RenderPassDesc().addColor(Attachment::clear(color, {0, 0, 0, 1})), pipeline, points);
    std::vector<Rgba8> expected(64, Rgba8{0, 0, 0, 255});
    expected[2 * 8 + 1] = {255, 0, 0, 255};
    expected[5 * 8 + 6] = {0, 255, 0, 255};
    expected[7 * 8 + 3] = {255, 0, 0, 255};
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(color), expected, 8));
}

// A line list draws each pair as its own segment (no segment joins one pair to the next), one
// pixel wide along a row or column of pixel centres. Endpoint pixels are left out of the check:
// GL's diamond-exit rule and Vulkan's line rasterisation may differ on the last pixel of a
// segment that ends inside it; every pixel in between is exact.
TEST_P(RasterTest, LineListDrawsSeparateOnePixelSegments) {
    TextureHandle color = color8x8();
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_UNORM, Format::Unknown, {}, {}, {}, PrimitiveTopology::LineList);
    const std::vector<ColorVertex> lines = {pixelCenter(-0.25f, 1, kRed), pixelCenter(7.25f, 1, kRed),        // row 1
                                            pixelCenter(5, 2.75f, kGreen), pixelCenter(5, 7.25f, kGreen)};   // column 5, rows 3..7
    drawVertices(RenderPassDesc().addColor(Attachment::clear(color, {0, 0, 0, 1})), pipeline, lines);
    const std::vector<Rgba8> image = readTextureAs<Rgba8>(color);
    auto at = [&](int x, int y) { return image[size_t(y) * 8 + size_t(x)]; };
    const Rgba8 black{0, 0, 0, 255}, red{255, 0, 0, 255}, green{0, 255, 0, 255};
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const bool onRow = y == 1, onColumn = x == 5 && y >= 3;
            const bool endpoint = (onRow && (x == 0 || x == 7)) || (onColumn && (y == 3 || y == 7));
            if (endpoint) continue;
            const Rgba8 expected = onRow ? red : onColumn ? green : black;
            EXPECT_EQ(at(x, y), expected) << "pixel (" << x << ", " << y << ")";
        }
}

}  // namespace
}  // namespace janus::rhi::test
