// A draw's or dispatch's bindings are checked against the sets bound, at the call that would be
// wrong, however often a set was checked before: with another pipeline, in another pass, or
// before it (or the pipeline) was destroyed and another object took its address. The GL backend
// caches passed checks in the binding set under the pipeline's binding signature (rhi-gl/README.md,
// "Command lists"); these tests fail if a cached check is used where it does not apply.
#include "backend_test.h"

namespace janus::rhi::test {
namespace {

class BindingCheckTest : public BackendTest {
protected:
    // Records `body` into `list` (begun here, ended when body returns) and says whether it threw
    // InvalidUsage naming `mentions`.
    testing::AssertionResult recordingThrows(ICommandList& list, const std::function<void(ICommandList&)>& body,
                                             std::vector<std::string> mentions) {
        list.begin();
        return throwsRhiError([&] { body(list); list.end(); }, ErrorCode::InvalidUsage, std::move(mentions));
    }
    // One fullscreen draw into `target` with `pipeline` and `sets` bound at 0, 1, ...
    std::function<void(ICommandList&)> drawInto(const TextureHandle& target, const PipelineHandle& pipeline,
                                                std::vector<BindingSetHandle> sets) {
        return [=](ICommandList& cmd) {
            cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::load(target)));
            cmd.setPipeline(pipeline);
            for (uint32_t i = 0; i < sets.size(); ++i) cmd.setBindingSet(i, sets[i]);
            cmd.draw(3);
            cmd.endRenderPass();
        };
    }
    void record(const CommandListHandle& list, const std::function<void(ICommandList&)>& body) {
        list->begin();
        body(*list);
        list->end();
        device().execute(list);
    }
    BindingSetHandle textureSet(Rgba8 color) {
        TextureHandle texture = createTexture2D(Format::RGBA8_UNORM, 1, 1);
        device().writeTexture(texture, {}, &color, sizeof color);
        return device().createBindingSet(BindingSetDesc().add(BindingItem::sampledTexture(0, texture, nearestClampSampler())));
    }
    BindingSetHandle uniformSet() {
        return device().createBindingSet(BindingSetDesc().add(BindingItem::uniformBuffer(0, createBuffer(BufferUsage::Uniform, 256))));
    }
};
JANUS_INSTANTIATE_BACKEND_TESTS(BindingCheckTest);

// rt_sample_2d_frag reads a texture at set 0 binding 0, rt_std140_read_frag a uniform buffer there:
// a set that passed with one pipeline is the wrong type for the other, in either order, whether
// the set is bound again after the pipeline change or stays bound.
TEST_P(BindingCheckTest, ASetThatPassedWithOnePipelineIsCheckedAgainstTheNext) {
    TextureHandle colour = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    TextureHandle bits = createTexture2D(Format::R32_UINT, 32, 1, TextureUsage::RenderTarget);
    PipelineHandle sampling = fullscreenPipeline("rt_sample_2d_frag", Format::RGBA8_UNORM);
    PipelineHandle reading = fullscreenPipeline("rt_std140_read_frag", Format::R32_UINT);
    BindingSetHandle texture = textureSet({255, 0, 0, 255}), uniform = uniformSet();
    CommandListHandle list = device().createCommandList();
    for (int round = 0; round < 2; ++round) {   // the second round finds the first one's checks
        record(list, drawInto(colour, sampling, {texture}));
        record(list, drawInto(bits, reading, {uniform}));
        EXPECT_TRUE(recordingThrows(*list, drawInto(bits, reading, {texture}), {"binding 0"})) << "round " << round;
        EXPECT_TRUE(recordingThrows(*list, drawInto(colour, sampling, {uniform}), {"binding 0"})) << "round " << round;
        // The set stays bound while the pipeline changes (one pass each, the second pipeline set
        // after the first pass's draw).
        EXPECT_TRUE(recordingThrows(*list, [&](ICommandList& cmd) {
            cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::load(colour)));
            cmd.setPipeline(sampling);
            cmd.setBindingSet(0, texture);
            cmd.draw(3);
            cmd.endRenderPass();
            cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::load(bits)));
            cmd.setPipeline(reading);
            cmd.draw(3);
            cmd.endRenderPass();
        }, {"binding 0"})) << "round " << round;
    }
    // The list still works, with the checks it passed.
    record(list, drawInto(colour, sampling, {texture}));
    EXPECT_EQ(readTextureAs<Rgba8>(colour), std::vector<Rgba8>(16, Rgba8{255, 0, 0, 255}));
}

// A pipeline destroyed and another created, likely at the same address, with other bindings: a
// set checked against the first must be checked against the second. Several rounds, so a reused
// address is all but certain (the test does not depend on it).
TEST_P(BindingCheckTest, APipelineMadeWhereADestroyedOneWasDoesNotInheritItsChecks) {
    TextureHandle colour = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    TextureHandle bits = createTexture2D(Format::R32_UINT, 32, 1, TextureUsage::RenderTarget);
    BindingSetHandle texture = textureSet({0, 255, 0, 255});
    CommandListHandle list = device().createCommandList();
    for (int round = 0; round < 4; ++round) {
        PipelineHandle sampling = fullscreenPipeline("rt_sample_2d_frag", Format::RGBA8_UNORM);
        record(list, drawInto(colour, sampling, {texture}));
        record(list, [](ICommandList&) {});   // lets go of the pipeline
        device().waitIdle();
        sampling.reset();
        PipelineHandle reading = fullscreenPipeline("rt_std140_read_frag", Format::R32_UINT);
        EXPECT_TRUE(recordingThrows(*list, drawInto(bits, reading, {texture}), {"binding 0"})) << "round " << round;
    }
}

// The same for binding sets: a set made after one that passed was destroyed (likely at its
// address) is checked itself, by the same list and the same pipeline.
TEST_P(BindingCheckTest, ASetMadeWhereADestroyedOneWasDoesNotInheritItsChecks) {
    TextureHandle colour = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    PipelineHandle sampling = fullscreenPipeline("rt_sample_2d_frag", Format::RGBA8_UNORM);
    CommandListHandle list = device().createCommandList();
    for (int round = 0; round < 4; ++round) {
        BindingSetHandle texture = textureSet({0, 0, 255, 255});
        record(list, drawInto(colour, sampling, {texture}));
        record(list, [](ICommandList&) {});   // lets go of the set
        device().waitIdle();
        texture.reset();
        BindingSetHandle uniform = uniformSet();
        EXPECT_TRUE(recordingThrows(*list, drawInto(colour, sampling, {uniform}), {"binding 0"})) << "round " << round;
    }
}

// Two sets: set 1 changes between draws while set 0 stays. Each combination is checked, and each
// draw reads its own set 1 (a stale check could pair a draw with another draw's items).
TEST_P(BindingCheckTest, ChangingOneOfTwoSetsIsCheckedAndRead) {
    Rgba8 a{204, 26, 0, 255};
    TextureHandle texA = createTexture2D(Format::RGBA8_UNORM, 1, 1);
    device().writeTexture(texA, {}, &a, sizeof a);
    std::array<float, 4> params{0.9f, 0.9f, 102.0f / 255.0f, 0.9f};
    BufferHandle ubo = createBuffer(BufferUsage::Uniform, std::as_bytes(std::span(params)));
    SamplerHandle sampler = nearestClampSampler();
    BindingSetHandle set0 = device().createBindingSet(
        BindingSetDesc().add(BindingItem::uniformBuffer(0, ubo)).add(BindingItem::sampledTexture(1, texA, sampler)));
    std::vector<BindingSetHandle> set1s;
    std::vector<TextureHandle> texBs;
    for (uint8_t green : {153, 51}) {
        Rgba8 b{51, green, 0, 255};
        TextureHandle texB = texBs.emplace_back(
            createTexture2D(Format::RGBA8_UNORM, 1, 1, TextureUsage::Sampled | TextureUsage::RenderTarget));
        device().writeTexture(texB, {}, &b, sizeof b);
        set1s.push_back(device().createBindingSet(BindingSetDesc().add(BindingItem::sampledTexture(2, texB, sampler))));
    }
    // Binding 2 is missing from this one (it has 1 instead).
    BindingSetHandle wrong = device().createBindingSet(BindingSetDesc().add(BindingItem::sampledTexture(1, texA, sampler)));
    PipelineHandle pipeline = fullscreenPipeline("rt_two_textures_two_sets_frag", Format::RGBA8_UNORM);
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    CommandListHandle list = device().createCommandList();
    for (int round = 0; round < 2; ++round) {
        record(list, [&](ICommandList& cmd) {
            cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
            cmd.setPipeline(pipeline);
            cmd.setBindingSet(0, set0);
            for (int half = 0; half < 2; ++half) {
                cmd.setBindingSet(1, set1s[half]);
                cmd.setScissor({2 * half, 0, 2, 4});
                cmd.draw(3);
            }
            cmd.endRenderPass();
        });
        std::vector<Rgba8> expected(16);
        for (size_t i = 0; i < 16; ++i) expected[i] = Rgba8{204, uint8_t(i % 4 < 2 ? 153 : 51), 102, 255};
        EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(target), expected, 4)) << "round " << round;
        EXPECT_TRUE(recordingThrows(*list, drawInto(target, pipeline, {set0, wrong}), {"binding 2"})) << "round " << round;
        EXPECT_TRUE(recordingThrows(*list, drawInto(target, pipeline, {set1s[0], set1s[1]}), {"binding 0"}))
            << "round " << round;
        // Set 1's texture as the attachment: the overlap is found among set 1's items.
        EXPECT_TRUE(recordingThrows(*list, drawInto(texBs[1], pipeline, {set0, set1s[1]}),
                                    {"binding 2", "colour attachment 0"}))
            << "round " << round;
    }
}

// What a binding check depends on besides the sets: the render pass. A set that passed while
// drawing into mip 0 of a texture whose mip 1 it samples overlaps the attachment when drawing
// into mip 1.
TEST_P(BindingCheckTest, ASetThatPassedInOnePassIsCheckedAgainstTheNextPass) {
    TextureHandle texture = createTexture2D(Format::RGBA8_UNORM, 8, 8, TextureUsage::Sampled | TextureUsage::RenderTarget, 2);
    BindingSetHandle set = device().createBindingSet(
        BindingSetDesc()
            .add(BindingItem::uniformBuffer(0, createBuffer(BufferUsage::Uniform, 80 * 16)))
            .add(BindingItem::sampledTexture(1, texture, nearestClampSampler()).setMips(1, 1)));
    PipelineHandle pipeline = fullscreenPipeline("rt_sample_lookup_2d_frag", Format::RGBA8_UNORM);
    auto drawIntoMip = [&](uint32_t mip) {
        return [=](ICommandList& cmd) {
            cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::load(texture, {mip, 0})));
            cmd.setPipeline(pipeline);
            cmd.setBindingSet(0, set);
            cmd.draw(3);
            cmd.endRenderPass();
        };
    };
    CommandListHandle list = device().createCommandList();
    for (int round = 0; round < 2; ++round) {
        record(list, drawIntoMip(0));
        EXPECT_TRUE(recordingThrows(*list, drawIntoMip(1), {"binding 1", "colour attachment 0", "mip 1"}))
            << "round " << round;
        // In one recording: the pass changes, the set stays bound.
        EXPECT_TRUE(recordingThrows(*list, [&](ICommandList& cmd) {
            drawIntoMip(0)(cmd);
            cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::load(texture, {1, 0})));
            cmd.setPipeline(pipeline);
            cmd.draw(3);
            cmd.endRenderPass();
        }, {"binding 1", "mip 1"})) << "round " << round;
    }
}

// rt_sample_at_shadow_frag declares a sampler2DShadow, rt_sample_at_2d_frag a sampler2D: each
// must get a sampler that compares exactly when its shader's does. Drivers leave a mismatch
// undefined (NVIDIA's GL reports it as undefined behaviour; Mesa and lavapipe draw something), so
// the binding check names it, with the same error on every backend.
TEST_P(BindingCheckTest, ASamplerComparesExactlyWhenTheShaderDeclaresAShadowSampler) {
    TextureHandle depth = createTexture2D(Format::D32_FLOAT, 1, 1, TextureUsage::Sampled);
    const float stored = 0.25f;
    device().writeTexture(depth, {}, &stored, sizeof stored);
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 1, 1, TextureUsage::RenderTarget);
    PipelineHandle shadow = fullscreenPipeline("rt_sample_at_shadow_frag", Format::RGBA8_UNORM);
    PipelineHandle plain = fullscreenPipeline("rt_sample_at_2d_frag", Format::RGBA8_UNORM);
    const std::array<float, 4 * 32> lookups{0.5f, 0.5f, 0.125f, 0.0f};   // texel centre, reference 0.125
    BufferHandle coords = createBuffer(BufferUsage::Uniform, std::as_bytes(std::span(lookups)));
    auto setWith = [&](const SamplerHandle& sampler) {
        return device().createBindingSet(
            BindingSetDesc().add(BindingItem::uniformBuffer(0, coords)).add(BindingItem::sampledTexture(1, depth, sampler)));
    };
    BindingSetHandle comparing = setWith(device().createSampler(
        SamplerDesc().setFilter(Filter::Nearest).setAddress(AddressMode::ClampToEdge).setCompare(CompareOp::LessOrEqual)));
    BindingSetHandle plainSampling = setWith(nearestClampSampler());
    CommandListHandle list = device().createCommandList();
    EXPECT_TRUE(recordingThrows(*list, drawInto(target, shadow, {plainSampling}), {"binding 1", "shadow sampler", "setCompare"}));
    EXPECT_TRUE(recordingThrows(*list, drawInto(target, plain, {comparing}), {"binding 1", "compares depth", "sampler2DShadow"}));
    // Matched, both draw: the comparison (reference <= texel: 0.125 <= 0.25) passes; the plain
    // lookup reads 0.25.
    record(list, drawInto(target, shadow, {comparing}));
    device().waitIdle();
    EXPECT_EQ(readTextureAs<Rgba8>(target), std::vector<Rgba8>(1, Rgba8{255, 255, 255, 255}));
    record(list, drawInto(target, plain, {plainSampling}));
    EXPECT_EQ(readTextureAs<Rgba8>(target)[0].r, 64) << "0.25 of 255, rounded";
}

// A storage image's texture must have the format its shader's qualifier declares
// (layout(rgba16f) image2D). Drivers leave a mismatch undefined: Mesa converts to the texture's
// format, other drivers reinterpret the bits; the check names both, with the same error on
// every backend. Two pipelines alike but for the qualifier: a set that passed with one is
// checked again with the other (the GL backend's cached checks are keyed by the qualifier).
TEST_P(BindingCheckTest, AStorageImageHasTheFormatItsShaderDeclares) {
    JANUS_REQUIRE_CAPABILITY(Capability::StorageImages);
    TextureHandle half = device().createTexture(TextureDesc()
                                                    .setFormat(Format::RGBA16_FLOAT)
                                                    .setSize(2, 2)
                                                    .setUsage(TextureUsage::Storage | TextureUsage::Sampled)
                                                    .setDebugName("half"));
    BindingSetHandle set = device().createBindingSet(BindingSetDesc().add(BindingItem::storageImage(0, half, 0)));
    PipelineHandle declaresHalf = computePipeline("rt_fill_image_rgba16f_comp");
    PipelineHandle declaresFloat = computePipeline("rt_fill_image_rgba32f_comp");
    auto dispatchWith = [&](const PipelineHandle& pipeline) {
        return [&, pipeline](ICommandList& cmd) {
            cmd.setPipeline(pipeline);
            cmd.setBindingSet(0, set);
            cmd.dispatch(2, 2);
        };
    };
    CommandListHandle list = device().createCommandList();
    EXPECT_TRUE(recordingThrows(*list, dispatchWith(declaresFloat),
                                {"binding 0", "layout(rgba32f)", "'half' is rgba16f", "declare layout(rgba16f)"}));
    record(list, dispatchWith(declaresHalf));
    EXPECT_TRUE(recordingThrows(*list, dispatchWith(declaresFloat), {"layout(rgba32f)"}))
        << "after the set passed with a pipeline that declares rgba16f";
}

// A uniform or storage buffer binding must show at least the block its shader declares (a
// storage block: its part before a runtime array). Reads past the range are undefined: Mesa read
// zeros for the rest of the block, other drivers read on into the buffer. Refused on every
// backend, as WebGPU does; a block that fits passes, and so does a storage block that is only a
// runtime array, whatever its range (ComputeTest.StorageBufferBindingHonoursOffsetAndRange).
TEST_P(BindingCheckTest, ABufferBindingHoldsTheBlockItsShaderDeclares) {
    // rt_std140_read_frag's uniform block ends at byte 136 (tail at 128, a vec2).
    TextureHandle target = createTexture2D(Format::R32_UINT, 32, 1, TextureUsage::RenderTarget);
    PipelineHandle reading = fullscreenPipeline("rt_std140_read_frag", Format::R32_UINT);
    BufferHandle buffer = createBuffer(BufferUsage::Uniform, 512);
    auto uniformSet = [&](uint64_t offset, uint64_t range) {
        return device().createBindingSet(BindingSetDesc().add(BindingItem::uniformBuffer(0, buffer, offset, range)));
    };
    CommandListHandle list = device().createCommandList();
    EXPECT_TRUE(recordingThrows(*list, drawInto(target, reading, {uniformSet(0, 16)}),
                                {"binding 0", "uniform block needs 136 bytes", "shows 16 bytes"}));
    // The rest of the buffer from an offset (range 0): its last alignment-sized piece is too short
    // where the alignment is below 136 bytes.
    if (const uint64_t alignment = caps().limits.uniformBufferOffsetAlignment; alignment < 136) {
        EXPECT_TRUE(recordingThrows(*list, drawInto(target, reading, {uniformSet(512 - alignment, 0)}), {"to the end"}));
    }
    record(list, drawInto(target, reading, {uniformSet(0, 136)}));
    record(list, drawInto(target, reading, {uniformSet(0, 0)}));

    if (!caps().compute || !caps().storageBuffers) return;
    // rt_layout_std430_comp's source block (binding 0) ends at byte 104 (tail at 96).
    PipelineHandle layout = computePipeline("rt_layout_std430_comp");
    BufferHandle source = createBuffer(BufferUsage::Storage, 512), out = createBuffer(BufferUsage::Storage, 512);
    auto storageSet = [&](uint64_t sourceRange) {
        return device().createBindingSet(BindingSetDesc()
                                             .add(BindingItem::storageBuffer(0, source, 0, sourceRange))
                                             .add(BindingItem::storageBuffer(1, out, 0, 256))
                                             .add(BindingItem::storageBuffer(2, out, 256, 256)));
    };
    auto dispatchWith = [&](const BindingSetHandle& set) {
        return [&, set](ICommandList& cmd) {
            cmd.setPipeline(layout);
            cmd.setBindingSet(0, set);
            cmd.dispatch(1);
        };
    };
    EXPECT_TRUE(recordingThrows(*list, dispatchWith(storageSet(32)), {"binding 0", "storage block needs 104 bytes"}));
    record(list, dispatchWith(storageSet(104)));
}

}  // namespace
}  // namespace janus::rhi::test
