// Render targets: every attachment kind (2D mips, each cube face at every mip, each 3D slice),
// clears and draws into each, float formats, blending, sRGB encoding.
#include "backend_test.h"

namespace janus::rhi::test {
namespace {

class RenderTargetTest : public BackendTest {
protected:
    // rt_vertex_color_vert + rt_two_outputs_frag: the vertex colour to RGBA8 attachment 0, its
    // channels reversed (abgr) to RGBA8 attachment 1.
    PipelineHandle twoOutputsPipeline() {
        GraphicsPipelineDesc desc;
        desc.setShaders(shader("rt_vertex_color_vert"), shader("rt_two_outputs_frag"))
            .addVertexBuffer({0, sizeof(ColorVertex), false})
            .addVertexAttribute({0, VertexFormat::Float4, 0, offsetof(ColorVertex, x)})
            .addVertexAttribute({1, VertexFormat::Float4, 0, offsetof(ColorVertex, r)})
            .addColorFormat(Format::RGBA8_UNORM)
            .addColorFormat(Format::RGBA8_UNORM);
        return device().createGraphicsPipeline(desc);
    }
    // Clears every listed subresource of `texture` to its own colour, then draws the
    // orientation pattern over each (LoadOp::Load) and checks every subresource: pattern over
    // its own clear colour. Catches wrong face/slice/mip selection, incomplete framebuffers,
    // lost clears and flips, per subresource.
    void expectClearAndDrawEach(const TextureHandle& texture, const std::vector<TextureSubresource>& subs) {
        const TextureDesc& desc = texture->desc();
        PipelineHandle pipeline = colorPipeline(desc.format);
        auto background = [&](size_t i) {
            // Distinct per subresource and exact in the format, so no conversion rounding
            // enters: multiples of 1/255 for RGBA8, of 1/64 (6 significant bits, exact even in
            // the 10-bit floats of R11G11B10F) for float formats.
            float unit = formatInfo(desc.format).kind == FormatKind::Float ? 64.0f : 255.0f;
            return Color{float(1 + 3 * i) / unit, float(60 - 3 * i) / unit, float(1 + 2 * i) / unit, 1.0f};
        };
        for (size_t i = 0; i < subs.size(); ++i)
            submit([&](ICommandList& cmd) {
                cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(texture, background(i), subs[i])));
                cmd.endRenderPass();
            });
        for (const TextureSubresource& sub : subs)
            drawVertices(RenderPassDesc().addColor(Attachment::load(texture, sub)), pipeline, orientationPattern());
        for (size_t i = 0; i < subs.size(); ++i) {
            SCOPED_TRACE(fmt::format("{} {} mip {} layer {}", toString(desc.format), toString(desc.dimension),
                                     subs[i].mipLevel, subs[i].layer));
            uint32_t size = mipExtent(desc.width, subs[i].mipLevel);
            std::vector<Color> expected = rasterize(orientationPattern(), size, size, background(i));
            for (Color& c : expected) c = quantize(desc.format, c);
            EXPECT_TRUE(imagesEqual(readColors(device(), texture, subs[i]), expected, size));
        }
    }

    TextureHandle renderTarget(TextureDimension dim, Format format, uint32_t size, uint32_t depth, uint32_t mips) {
        return device().createTexture(TextureDesc().setDimension(dim).setFormat(format).setSize(size, size, depth)
                                          .setMipLevels(mips).setUsage(TextureUsage::RenderTarget | TextureUsage::Sampled));
    }
};
JANUS_INSTANTIATE_BACKEND_TESTS(RenderTargetTest);

TEST_P(RenderTargetTest, ClearsAndDrawsEach2DMip) {
    TextureHandle texture = renderTarget(TextureDimension::Texture2D, Format::RGBA8_UNORM, 16, 1, 3);
    expectClearAndDrawEach(texture, {{0, 0}, {1, 0}, {2, 0}});
}

TEST_P(RenderTargetTest, ClearsAndDrawsEachCubeFaceAtMip0) {
    TextureHandle texture = renderTarget(TextureDimension::TextureCube, Format::RGBA8_UNORM, 8, 1, 1);
    expectClearAndDrawEach(texture, {{0, 0}, {0, 1}, {0, 2}, {0, 3}, {0, 4}, {0, 5}});
}

// The incomplete-framebuffer pitfall: a cube face at mip 1+ of a texture with a mip chain.
TEST_P(RenderTargetTest, ClearsAndDrawsEachCubeFaceAtEveryMip) {
    JANUS_REQUIRE_CAPABILITY(Capability::RenderToCubeFaceMip);
    TextureHandle texture = renderTarget(TextureDimension::TextureCube, Format::RGBA8_UNORM, 16, 1, 3);
    std::vector<TextureSubresource> subs;
    for (uint32_t mip = 0; mip < 3; ++mip)
        for (uint32_t face = 0; face < 6; ++face) subs.push_back({mip, face});
    expectClearAndDrawEach(texture, subs);
}

TEST_P(RenderTargetTest, ClearsAndDrawsEach3DSliceAtEveryMip) {
    JANUS_REQUIRE_CAPABILITY(Capability::RenderToVolumeSlice);
    TextureHandle texture = renderTarget(TextureDimension::Texture3D, Format::RGBA8_UNORM, 8, 4, 2);
    expectClearAndDrawEach(texture, {{0, 0}, {0, 1}, {0, 2}, {0, 3}, {1, 0}, {1, 1}});
}

TEST_P(RenderTargetTest, ClearsAndDrawsSrgbTarget) {
    // The pattern uses 0 and 1 only, which sRGB encoding keeps; backgrounds are compared as
    // stored, so this checks the attachment path, not the encoding (see SrgbTargetEncodesLinear).
    TextureHandle texture = renderTarget(TextureDimension::Texture2D, Format::RGBA8_SRGB, 8, 1, 1);
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_SRGB);
    drawVertices(RenderPassDesc().addColor(Attachment::clear(texture, {0, 0, 0, 1})), pipeline, orientationPattern());
    EXPECT_TRUE(imagesEqual(readColors(device(), texture), rasterize(orientationPattern(), 8, 8, {0, 0, 0, 1}), 8));
}

TEST_P(RenderTargetTest, ClearsAndDrawsFloatFormats) {
    JANUS_REQUIRE_CAPABILITY(Capability::FloatRenderTargets);
    for (Format format : {Format::RGBA16_FLOAT, Format::RGBA32_FLOAT, Format::R11G11B10_FLOAT, Format::R32_FLOAT}) {
        TextureHandle texture = renderTarget(TextureDimension::Texture2D, format, 8, 1, 2);
        expectClearAndDrawEach(texture, {{0, 0}, {1, 0}});
        // Values outside [0, 1] survive in float targets (no clamping).
        TextureHandle wide = renderTarget(TextureDimension::Texture2D, format, 4, 1, 1);
        const Color clear = {2.5f, 1000.0f, 0.125f, 0.25f};
        submit([&](ICommandList& cmd) {
            cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(wide, clear)));
            cmd.endRenderPass();
        });
        EXPECT_TRUE(imagesEqual(readColors(device(), wide), std::vector<Color>(16, quantize(format, clear)), 4))
            << toString(format) << " cleared to (2.5, 1000, 0.125, 0.25)";
    }
}

TEST_P(RenderTargetTest, ClearsR32UintTarget) {
    TextureHandle texture = renderTarget(TextureDimension::Texture2D, Format::R32_UINT, 4, 1, 1);
    submit([&](ICommandList& cmd) {
        // Integer targets take the clear value as a number, not a normalised colour.
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(texture, {123456.0f, 0, 0, 0})));
        cmd.endRenderPass();
    });
    EXPECT_EQ(readTextureAs<uint32_t>(texture), std::vector<uint32_t>(16, 123456u));
}

TEST_P(RenderTargetTest, AdditiveBlendingRGBA8Clamps) {
    TextureHandle texture = renderTarget(TextureDimension::Texture2D, Format::RGBA8_UNORM, 4, 1, 1);
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_UNORM, Format::Unknown, {}, {}, BlendAttachment::additive());
    drawVertices(RenderPassDesc().addColor(Attachment::clear(texture, {0, 1, 0, 0})), pipeline,
                 rectangle(-1, -1, 1, 1, {1, 1, 0, 1}));
    EXPECT_EQ(readTextureAs<Rgba8>(texture), std::vector<Rgba8>(16, Rgba8{255, 255, 0, 255}));
}

TEST_P(RenderTargetTest, AlphaBlendingRGBA8) {
    TextureHandle texture = renderTarget(TextureDimension::Texture2D, Format::RGBA8_UNORM, 4, 1, 1);
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_UNORM, Format::Unknown, {}, {}, BlendAttachment::alpha());
    // src alpha 0 keeps the destination colour; dst alpha = 0 + 1 * (1 - 0) = 1.
    drawVertices(RenderPassDesc().addColor(Attachment::clear(texture, {0, 1, 0, 1})), pipeline,
                 rectangle(-1, -1, 1, 1, {1, 0, 1, 0}));
    EXPECT_EQ(readTextureAs<Rgba8>(texture), std::vector<Rgba8>(16, Rgba8{0, 255, 0, 255}));
}

TEST_P(RenderTargetTest, AdditiveBlendingFloat16) {
    JANUS_REQUIRE_CAPABILITY(Capability::FloatRenderTargets);
    TextureHandle texture = renderTarget(TextureDimension::Texture2D, Format::RGBA16_FLOAT, 4, 1, 1);
    PipelineHandle pipeline = colorPipeline(Format::RGBA16_FLOAT, Format::Unknown, {}, {}, BlendAttachment::additive());
    // Every value and sum is exact in half precision, and > 1 shows there is no clamping.
    drawVertices(RenderPassDesc().addColor(Attachment::clear(texture, {0.25f, 0.5f, 1.0f, 0.0f})), pipeline,
                 rectangle(-1, -1, 1, 1, {0.5f, 0.25f, 2.0f, 1.0f}));
    EXPECT_TRUE(imagesEqual(readColors(device(), texture), std::vector<Color>(16, Color{0.75f, 0.75f, 3.0f, 1.0f}), 4));
}

TEST_P(RenderTargetTest, AdditiveBlendingFloat32) {
    JANUS_REQUIRE_CAPABILITY(Capability::FloatRenderTargets);
    JANUS_REQUIRE_CAPABILITY(Capability::FloatBlend);
    TextureHandle texture = renderTarget(TextureDimension::Texture2D, Format::RGBA32_FLOAT, 4, 1, 1);
    PipelineHandle pipeline = colorPipeline(Format::RGBA32_FLOAT, Format::Unknown, {}, {}, BlendAttachment::additive());
    drawVertices(RenderPassDesc().addColor(Attachment::clear(texture, {0.25f, 100.0f, -1.0f, 0.0f})), pipeline,
                 rectangle(-1, -1, 1, 1, {0.5f, 1000.0f, 0.125f, 1.0f}));
    EXPECT_TRUE(imagesEqual(readColors(device(), texture), std::vector<Color>(16, Color{0.75f, 1100.0f, -0.875f, 1.0f}), 4));
}

// Linear 0.5 must be stored sRGB-encoded (GL needs GL_FRAMEBUFFER_SRGB enabled for that).
TEST_P(RenderTargetTest, SrgbTargetEncodesLinear) {
    TextureHandle texture = renderTarget(TextureDimension::Texture2D, Format::RGBA8_SRGB, 4, 1, 1);
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_SRGB);
    drawVertices(RenderPassDesc().addColor(Attachment::clear(texture, {0, 0, 0, 0})), pipeline,
                 rectangle(-1, -1, 1, 1, {0.5f, 0.5f, 0.5f, 0.5f}));
    for (const Rgba8& texel : readTextureAs<Rgba8>(texture)) {
        // sRGB(0.5) * 255 = 187.52: the exact value sits on a rounding boundary, and the specs
        // allow the encoding some error, so 187..189 are right; 128 means "not encoded".
        EXPECT_NEAR(texel.r, 188, 1);
        EXPECT_NEAR(texel.g, 188, 1);
        EXPECT_NEAR(texel.b, 188, 1);
        EXPECT_NEAR(texel.a, 128, 1) << "alpha is linear; 127.5 rounds either way";
    }
    // The clear colour is encoded too: linear 0.5 clears to 188.
    submit([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(texture, {0.5f, 0.0f, 1.0f, 1.0f})));
        cmd.endRenderPass();
    });
    for (const Rgba8& texel : readTextureAs<Rgba8>(texture)) {
        EXPECT_NEAR(texel.r, 188, 1) << "cleared to linear 0.5 (same tolerance as above)";
        EXPECT_EQ(texel.g, 0);
        EXPECT_EQ(texel.b, 255);
    }
}

TEST_P(RenderTargetTest, ViewportAndScissorCountRowsFromTheTop) {
    TextureHandle texture = renderTarget(TextureDimension::Texture2D, Format::RGBA8_UNORM, 8, 1, 1);
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_UNORM);
    BufferHandle red = createBufferFrom(BufferUsage::Vertex, rectangle(-1, -1, 1, 1, {1, 0, 0, 1}));
    BufferHandle green = createBufferFrom(BufferUsage::Vertex, rectangle(-1, -1, 1, 1, {0, 1, 0, 1}));
    submit([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(texture, {0, 0, 0, 1})));
        cmd.setPipeline(pipeline);
        cmd.setViewport({0, 0, 4, 4});          // top-left quadrant
        cmd.setVertexBuffer(0, red);
        cmd.draw(6);
        cmd.setViewport({0, 0, 8, 8});
        cmd.setScissor({6, 0, 2, 3});           // columns 6-7 of rows 0-2 (top right)
        cmd.setVertexBuffer(0, green);
        cmd.draw(6);
        cmd.endRenderPass();
    });
    std::vector<Rgba8> expected(64, Rgba8{0, 0, 0, 255});
    for (uint32_t y = 0; y < 8; ++y)
        for (uint32_t x = 0; x < 8; ++x) {
            if (x < 4 && y < 4) expected[y * 8 + x] = {255, 0, 0, 255};
            if (x >= 6 && y < 3) expected[y * 8 + x] = {0, 255, 0, 255};
        }
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(texture), expected, 8));
}

// Viewport and scissor reset to the full attachment at every render pass (rhi.h), even after a
// previous pass set them for a smaller target.
TEST_P(RenderTargetTest, ViewportAndScissorResetAtEachPass) {
    TextureHandle small = renderTarget(TextureDimension::Texture2D, Format::RGBA8_UNORM, 4, 1, 1);
    TextureHandle large = renderTarget(TextureDimension::Texture2D, Format::RGBA8_UNORM, 8, 1, 1);
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_UNORM);
    BufferHandle full = createBufferFrom(BufferUsage::Vertex, rectangle(-1, -1, 1, 1, {1, 0, 0, 1}));
    submit([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(small)));
        cmd.setPipeline(pipeline);
        cmd.setViewport({0, 0, 2, 2});
        cmd.setScissor({1, 1, 1, 1});
        cmd.setVertexBuffer(0, full);
        cmd.draw(6);
        cmd.endRenderPass();
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(large)));
        cmd.setPipeline(pipeline);
        cmd.setVertexBuffer(0, full);
        cmd.draw(6);
        cmd.endRenderPass();
    });
    EXPECT_EQ(readTextureAs<Rgba8>(large), std::vector<Rgba8>(64, Rgba8{255, 0, 0, 255})) << "the whole target is drawn";
    std::vector<Rgba8> expectedSmall(16, Rgba8{0, 0, 0, 0});
    expectedSmall[1 * 4 + 1] = {255, 0, 0, 255};
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(small), expectedSmall, 4)) << "only the scissored pixel (1, 1)";
}

// The write mask applies to draws only: a later clear writes every channel (GL's glClear obeys
// glColorMask / glDepthMask, so a backend must reset them before clearing).
TEST_P(RenderTargetTest, WriteMasksLimitDrawsButNotClears) {
    TextureHandle color = renderTarget(TextureDimension::Texture2D, Format::RGBA8_UNORM, 4, 1, 1);
    TextureHandle depth = device().createTexture(TextureDesc().setFormat(Format::D32_FLOAT).setSize(4, 4).setUsage(TextureUsage::RenderTarget));
    BlendAttachment redAndAlphaOnly;
    redAndAlphaOnly.writeMask = 0x1 | 0x8;
    PipelineHandle masked = colorPipeline(Format::RGBA8_UNORM, Format::D32_FLOAT, {}, {true, false, CompareOp::Always}, redAndAlphaOnly);
    drawVertices(RenderPassDesc().addColor(Attachment::clear(color, {0, 0, 1, 0})).setDepth(Attachment::clearDepthTo(depth, 0.5f)),
                 masked, rectangle(-1, -1, 1, 1, {1, 1, 0, 1}, 0.25f));
    EXPECT_EQ(readTextureAs<Rgba8>(color), std::vector<Rgba8>(16, Rgba8{255, 0, 255, 255})) << "only red and alpha written";
    EXPECT_EQ(readTextureAs<float>(depth), std::vector<float>(16, 0.5f)) << "depth write was off";
    submit([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(color, {0, 1, 0, 1})).setDepth(Attachment::clearDepthTo(depth, 0.75f)));
        cmd.endRenderPass();
    });
    EXPECT_EQ(readTextureAs<Rgba8>(color), std::vector<Rgba8>(16, Rgba8{0, 255, 0, 255})) << "the clear writes every channel";
    EXPECT_EQ(readTextureAs<float>(depth), std::vector<float>(16, 0.75f)) << "the depth clear writes depth";
}

TEST_P(RenderTargetTest, TwoColorAttachmentsGetTheirOwnOutputs) {
    // Different kinds on purpose: a 2D texture and a cube face.
    TextureHandle flat = renderTarget(TextureDimension::Texture2D, Format::RGBA8_UNORM, 4, 1, 1);
    TextureHandle cube = renderTarget(TextureDimension::TextureCube, Format::RGBA8_UNORM, 4, 1, 1);
    PipelineHandle pipeline = twoOutputsPipeline();
    drawVertices(RenderPassDesc().addColor(Attachment::clear(flat)).addColor(Attachment::clear(cube, {0, 0, 0, 0}, {0, 3})),
                 pipeline, rectangle(-1, -1, 1, 1, {1, 0, 0.2f, 0.6f}));
    EXPECT_EQ(readTextureAs<Rgba8>(flat), std::vector<Rgba8>(16, Rgba8{255, 0, 51, 153})) << "location 0";
    EXPECT_EQ(readTextureAs<Rgba8>(cube, {0, 3}), std::vector<Rgba8>(16, Rgba8{153, 51, 0, 255})) << "location 1 (abgr)";
    EXPECT_EQ(readTextureAs<Rgba8>(cube, {0, 2}), std::vector<Rgba8>(16, Rgba8{0, 0, 0, 0})) << "other faces untouched";
}

// Two faces of one cube as the two attachments of a pass: different subresources of one texture
// are separate targets (one subresource twice is refused: ValidationTest).
TEST_P(RenderTargetTest, TwoFacesOfOneTextureAreTwoAttachments) {
    TextureHandle cube = renderTarget(TextureDimension::TextureCube, Format::RGBA8_UNORM, 4, 1, 1);
    PipelineHandle pipeline = twoOutputsPipeline();
    drawVertices(RenderPassDesc()
                     .addColor(Attachment::clear(cube, {0, 0, 0, 0}, {0, 1}))
                     .addColor(Attachment::clear(cube, {0, 0, 0, 0}, {0, 4})),
                 pipeline, rectangle(-1, -1, 1, 1, {1, 0, 0.2f, 0.6f}));
    EXPECT_EQ(readTextureAs<Rgba8>(cube, {0, 1}), std::vector<Rgba8>(16, Rgba8{255, 0, 51, 153})) << "location 0";
    EXPECT_EQ(readTextureAs<Rgba8>(cube, {0, 4}), std::vector<Rgba8>(16, Rgba8{153, 51, 0, 255})) << "location 1 (abgr)";
    EXPECT_EQ(readTextureAs<Rgba8>(cube, {0, 0}), std::vector<Rgba8>(16, Rgba8{0, 0, 0, 0})) << "other faces untouched";
}

TEST_P(RenderTargetTest, DontCareLoadThenFullDrawIsDefined) {
    TextureHandle texture = renderTarget(TextureDimension::Texture2D, Format::RGBA8_UNORM, 4, 1, 1);
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_UNORM);
    Attachment attachment = Attachment::clear(texture);
    attachment.loadOp = LoadOp::DontCare;
    drawVertices(RenderPassDesc().addColor(attachment), pipeline, rectangle(-1, -1, 1, 1, {0, 0, 1, 1}));
    EXPECT_EQ(readTextureAs<Rgba8>(texture), std::vector<Rgba8>(16, Rgba8{0, 0, 255, 255}));
}

}  // namespace
}  // namespace janus::rhi::test
