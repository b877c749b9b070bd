// Dynamic uniform buffers (BindingItem::dynamicOffset): one binding set, its windows moved by the
// offsets each setBindingSet gives. Every draw and dispatch must read the slice its offsets select,
// also after switching sets, rebinding the same set, a set bound at another index taking the
// binding point (GL's one namespace), and a write right before the read; and every misuse is the
// same error on every backend.
#include <array>

#include "backend_test.h"

namespace janus::rhi::test {
namespace {

class DynamicOffsetTest : public BackendTest {
protected:
    // Slices one std140 vec4 each, at offsets every backend accepts.
    uint32_t sliceStride() const { return std::max<uint32_t>(caps().limits.uniformBufferOffsetAlignment, 16); }
    // A uniform buffer of one vec4 slice per colour (unorm values), `sliceStride()` apart.
    BufferHandle sliceBuffer(const std::vector<Rgba8>& colours) {
        std::vector<std::byte> bytes(colours.size() * sliceStride());
        for (size_t i = 0; i < colours.size(); ++i) {
            const std::array<float, 4> c{colours[i].r / 255.0f, colours[i].g / 255.0f, colours[i].b / 255.0f,
                                         colours[i].a / 255.0f};
            std::memcpy(bytes.data() + i * sliceStride(), c.data(), sizeof c);
        }
        return createBuffer(BufferUsage::Uniform, bytes);
    }
    BindingItem dynamicSlice(uint32_t binding, const BufferHandle& buffer) {
        return BindingItem::uniformBuffer(binding, buffer, 0, 16).setDynamicOffset();
    }
    // rt_fullscreen_vert + `fragment` into RGBA8, reading `dynamic` (set 0 bindings) dynamically.
    PipelineHandle pipelineReading(std::string_view fragment, const std::vector<uint32_t>& dynamic) {
        std::vector<DynamicUniformBuffer> set0;
        for (uint32_t binding : dynamic) set0.push_back({0, binding});
        return fullscreenPipeline(fragment, Format::RGBA8_UNORM, set0);
    }
    // A 4x4 target drawn column by column: `bindColumn(cmd, column)` binds what column draws with.
    std::vector<Rgba8> drawColumns(const PipelineHandle& pipeline,
                                   const std::function<void(ICommandList&, uint32_t)>& bindColumn) {
        TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
        submit([&](ICommandList& cmd) {
            cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
            cmd.setPipeline(pipeline);
            for (uint32_t column = 0; column < 4; ++column) {
                cmd.setScissor({int32_t(column), 0, 1, 4});
                bindColumn(cmd, column);
                cmd.draw(3);
            }
            cmd.endRenderPass();
        });
        return readTextureAs<Rgba8>(target);
    }
    static std::vector<Rgba8> columns(const std::array<Rgba8, 4>& colours) {
        std::vector<Rgba8> image(16);
        for (size_t i = 0; i < 16; ++i) image[i] = colours[i % 4];
        return image;
    }
    std::array<uint32_t, 1> at(uint32_t slice) const { return {slice * sliceStride()}; }

    const std::array<Rgba8, 4> m_colours = {Rgba8{255, 0, 0, 255}, Rgba8{0, 255, 0, 255}, Rgba8{0, 0, 255, 255},
                                            Rgba8{255, 255, 0, 255}};
};
JANUS_INSTANTIATE_BACKEND_TESTS(DynamicOffsetTest);

// Columns read slices 2, 0, 3, 1: each must show its own (the previous column's means the new
// offset was not bound; slice 0 everywhere means the offsets were dropped).
TEST_P(DynamicOffsetTest, EachDrawReadsTheSliceItsOffsetSelects) {
    BufferHandle slices = sliceBuffer({m_colours.begin(), m_colours.end()});
    BindingSetHandle set = device().createBindingSet(BindingSetDesc().add(dynamicSlice(0, slices)));
    const std::array<uint32_t, 4> order = {2, 0, 3, 1};
    const std::vector<Rgba8> image = drawColumns(pipelineReading("bench_uniform_color_frag", {0}),
                                                 [&](ICommandList& cmd, uint32_t c) { cmd.setBindingSet(0, set, at(order[c])); });
    EXPECT_TRUE(imagesEqual(image, columns({m_colours[2], m_colours[0], m_colours[3], m_colours[1]}), 4));
}

// Two sets over two buffers, alternating, each at its own offsets; and one set bound twice at the
// same offsets (nothing to bind again, and the draw still reads the slice).
TEST_P(DynamicOffsetTest, SwitchingSetsAndRebindingKeepEachSetsOffsets) {
    BufferHandle first = sliceBuffer({m_colours.begin(), m_colours.end()});
    BufferHandle second = sliceBuffer({m_colours.rbegin(), m_colours.rend()});
    BindingSetHandle a = device().createBindingSet(BindingSetDesc().add(dynamicSlice(0, first)));
    BindingSetHandle b = device().createBindingSet(BindingSetDesc().add(dynamicSlice(0, second)));
    const std::vector<Rgba8> image =
        drawColumns(pipelineReading("bench_uniform_color_frag", {0}), [&](ICommandList& cmd, uint32_t c) {
            if (c % 2 == 0) {
                cmd.setBindingSet(0, a, at(c + 1));
                cmd.setBindingSet(0, a, at(c + 1));
            } else {
                cmd.setBindingSet(0, b, at(c));   // b's slice c is colour 3 - c
            }
        });
    EXPECT_TRUE(imagesEqual(image, columns({m_colours[1], m_colours[2], m_colours[3], m_colours[0]}), 4));
}

// The set lists binding 1 before binding 0; its offsets come in binding order. Swapped, column 0
// would show (0, 255, 0, 255)'s red-green with the first slice's blue-alpha.
TEST_P(DynamicOffsetTest, OffsetsAreTakenInBindingOrderNotItemOrder) {
    BufferHandle slices = sliceBuffer({m_colours.begin(), m_colours.end()});
    BindingSetHandle set =
        device().createBindingSet(BindingSetDesc().add(dynamicSlice(1, slices)).add(dynamicSlice(0, slices)));
    // rt_two_uniforms_frag: (binding 0's red and green, binding 1's blue and alpha).
    const std::array<std::array<uint32_t, 2>, 4> slicesOf = {{{0, 2}, {1, 0}, {3, 3}, {2, 1}}};
    const std::vector<Rgba8> image = drawColumns(pipelineReading("rt_two_uniforms_frag", {0, 1}), [&](ICommandList& cmd, uint32_t c) {
        const std::array<uint32_t, 2> offsets = {slicesOf[c][0] * sliceStride(), slicesOf[c][1] * sliceStride()};
        cmd.setBindingSet(0, set, offsets);
    });
    std::array<Rgba8, 4> expected;
    for (size_t c = 0; c < 4; ++c) {
        const Rgba8 zero = m_colours[slicesOf[c][0]], one = m_colours[slicesOf[c][1]];
        expected[c] = {zero.r, zero.g, one.b, one.a};
    }
    EXPECT_TRUE(imagesEqual(image, columns(expected), 4));
}

// Binding 1 is an ordinary uniform buffer beside the dynamic binding 0: only binding 0 moves.
TEST_P(DynamicOffsetTest, AStaticItemBesideADynamicOneStaysWhereItIs) {
    BufferHandle slices = sliceBuffer({m_colours.begin(), m_colours.end()});
    BufferHandle fixed = sliceBuffer({Rgba8{0, 0, 128, 64}});
    BindingSetHandle set = device().createBindingSet(
        BindingSetDesc().add(dynamicSlice(0, slices)).add(BindingItem::uniformBuffer(1, fixed, 0, 16)));
    const std::vector<Rgba8> image = drawColumns(pipelineReading("rt_two_uniforms_frag", {0}),
                                                 [&](ICommandList& cmd, uint32_t c) { cmd.setBindingSet(0, set, at(3 - c)); });
    std::array<Rgba8, 4> expected;
    for (size_t c = 0; c < 4; ++c) expected[c] = {m_colours[3 - c].r, m_colours[3 - c].g, 128, 64};
    EXPECT_TRUE(imagesEqual(image, columns(expected), 4));
}

// GL has one binding point per number for all sets: a set bound at index 1 with an item at
// binding 0 takes point 0 from the dynamic set at index 0, which the pipeline reads. The point is
// bound again before the draw, at the set's offset, not its first window.
TEST_P(DynamicOffsetTest, ASetBoundAtAnotherIndexDoesNotResetTheWindow) {
    BufferHandle slices = sliceBuffer({m_colours.begin(), m_colours.end()});
    BindingSetHandle set = device().createBindingSet(BindingSetDesc().add(dynamicSlice(0, slices)));
    BindingSetHandle other = device().createBindingSet(
        BindingSetDesc().add(BindingItem::uniformBuffer(0, sliceBuffer({Rgba8{9, 9, 9, 9}}), 0, 16)));
    const std::vector<Rgba8> image =
        drawColumns(pipelineReading("bench_uniform_color_frag", {0}), [&](ICommandList& cmd, uint32_t c) {
            cmd.setBindingSet(0, set, at(c));
            cmd.setBindingSet(1, other);   // the pipeline reads no set 1
        });
    EXPECT_TRUE(imagesEqual(image, columns(m_colours), 4));
}

// The slice is written in the same list right before the pass whose draw reads it: the draw must
// see the write (on Vulkan, the pass's barrier covers it; the dispatch test below checks the
// window's own tracking).
TEST_P(DynamicOffsetTest, AWriteRightBeforeTheDrawIsWhatTheDrawReads) {
    BufferHandle slices = sliceBuffer({m_colours.begin(), m_colours.end()});
    BindingSetHandle set = device().createBindingSet(BindingSetDesc().add(dynamicSlice(0, slices)));
    PipelineHandle pipeline = pipelineReading("bench_uniform_color_frag", {0});
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    const std::array<float, 4> white = {1, 1, 1, 1};
    submit([&](ICommandList& cmd) {
        cmd.writeBuffer(slices, white.data(), sizeof white, 2 * sliceStride());
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        cmd.setPipeline(pipeline);
        cmd.setBindingSet(0, set, at(2));
        cmd.draw(3);
        cmd.endRenderPass();
    });
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(target), std::vector<Rgba8>(16, Rgba8{255, 255, 255, 255}), 4));
}

// Four dispatches, one set: each writes the value of the slice its offset selects at that slice's
// index, so each result says which slice its dispatch read. Slice 2 is written in the list, right
// before: the dispatch reading it must wait for that write, though the set's first window (slice
// 0) does not overlap it (Vulkan's synchronisation validation reports a missing barrier).
TEST_P(DynamicOffsetTest, EachDispatchReadsTheSliceItsOffsetSelects) {
    JANUS_REQUIRE_CAPABILITY(Capability::Compute);
    JANUS_REQUIRE_CAPABILITY(Capability::StorageBuffers);
    std::vector<std::byte> bytes(4 * sliceStride());
    for (uint32_t i = 0; i < 4; ++i) {
        const std::array<uint32_t, 2> slice = {i, i == 2 ? 0 : 100 + i};
        std::memcpy(bytes.data() + i * sliceStride(), slice.data(), sizeof slice);
    }
    const std::array<uint32_t, 2> slice2 = {2, 102};
    BufferHandle slices = createBuffer(BufferUsage::Uniform, bytes);
    BufferHandle results = createBufferFrom(BufferUsage::Storage, std::vector<uint32_t>(4, 0));
    BindingSetHandle set = device().createBindingSet(BindingSetDesc()
                                                         .add(BindingItem::uniformBuffer(0, slices, 0, 8).setDynamicOffset())
                                                         .add(BindingItem::storageBuffer(1, results)));
    PipelineHandle pipeline = computePipeline("rt_dynamic_slice_comp", {{0, 0}});
    submit([&](ICommandList& cmd) {
        cmd.writeBuffer(slices, slice2.data(), sizeof slice2, 2 * sliceStride());
        cmd.setPipeline(pipeline);
        for (uint32_t slice : {2u, 3u, 1u, 0u}) {   // slice 2 first: no earlier barrier covers its write
            cmd.setBindingSet(0, set, at(slice));
            cmd.dispatch(1);
        }
    });
    EXPECT_EQ(readBufferAs<uint32_t>(results), (std::vector<uint32_t>{100, 101, 102, 103}));
}

// --- misuse: the same code on every backend, and a message naming what to change ---------------

TEST_P(DynamicOffsetTest, ASetWithDynamicOffsetsBoundWithoutThemIsRefused) {
    BindingSetHandle set =
        device().createBindingSet(BindingSetDesc().add(dynamicSlice(0, sliceBuffer({m_colours.begin(), m_colours.end()}))));
    CommandListHandle list = device().createCommandList();
    list->begin();
    EXPECT_TRUE(throwsRhiError([&] { list->setBindingSet(0, set); }, ErrorCode::InvalidUsage,
                               {"1 dynamic uniform buffer", "no offsets"}));
    EXPECT_TRUE(throwsRhiError([&] { list->setBindingSet(0, set, std::vector<uint32_t>{0, 0}); },
                               ErrorCode::InvalidUsage, {"2 dynamic offsets given", "has 1"}));
    BindingSetHandle plain = device().createBindingSet(
        BindingSetDesc().add(BindingItem::uniformBuffer(0, sliceBuffer({m_colours[0]}))));
    EXPECT_TRUE(throwsRhiError([&] { list->setBindingSet(0, plain, at(0)); }, ErrorCode::InvalidUsage,
                               {"1 dynamic offset given", "has 0"}));
}

TEST_P(DynamicOffsetTest, OffsetsMustBeAlignedAndKeepTheWindowInside) {
    BufferHandle slices = sliceBuffer({m_colours.begin(), m_colours.end()});
    BindingSetHandle set = device().createBindingSet(BindingSetDesc().add(dynamicSlice(0, slices)));
    CommandListHandle list = device().createCommandList();
    list->begin();
    if (caps().limits.uniformBufferOffsetAlignment > 1) {
        const std::array<uint32_t, 1> misaligned = {sliceStride() + 1};
        EXPECT_TRUE(throwsRhiError([&] { list->setBindingSet(0, set, misaligned); }, ErrorCode::InvalidUsage,
                                   {"not a multiple", "uniformBufferOffsetAlignment"}));
    }
    // The last slice starts at 3 strides: its 16-byte window ends inside; the next one would not.
    EXPECT_NO_THROW(list->setBindingSet(0, set, at(3)));
    EXPECT_TRUE(throwsRhiError([&] { list->setBindingSet(0, set, at(4)); }, ErrorCode::InvalidUsage,
                               {"past the end", std::to_string(3 * sliceStride())}));
}

// A refused bind changes nothing: its first offset was fine, its second outside; the draw after
// it reads where the last accepted bind put both windows (on Vulkan the offsets wait in the list
// until the draw binds them, so a half-taken refusal would show).
TEST_P(DynamicOffsetTest, ARefusedBindLeavesTheLastOffsets) {
    BufferHandle slices = sliceBuffer({m_colours.begin(), m_colours.end()});
    BindingSetHandle set =
        device().createBindingSet(BindingSetDesc().add(dynamicSlice(0, slices)).add(dynamicSlice(1, slices)));
    PipelineHandle pipeline = pipelineReading("rt_two_uniforms_frag", {0, 1});
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    const std::array<uint32_t, 2> accepted = {0, sliceStride()}, refused = {3 * sliceStride(), 4 * sliceStride()};
    submit([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        cmd.setPipeline(pipeline);
        cmd.setBindingSet(0, set, accepted);
        EXPECT_TRUE(throwsRhiError([&] { cmd.setBindingSet(0, set, refused); }, ErrorCode::InvalidUsage, {"past the end"}));
        cmd.draw(3);
        cmd.endRenderPass();
    });
    const Rgba8 zero = m_colours[0], one = m_colours[1];
    EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(target), std::vector<Rgba8>(16, Rgba8{zero.r, zero.g, one.b, one.a}), 4));
}

TEST_P(DynamicOffsetTest, OnlyUniformBuffersWithARangeTakeDynamicOffsets) {
    BufferHandle uniform = sliceBuffer({m_colours[0]});
    EXPECT_TRUE(throwsRhiError(
        [&] { device().createBindingSet(BindingSetDesc().add(BindingItem::uniformBuffer(0, uniform).setDynamicOffset())); },
        ErrorCode::InvalidDescription, {"needs a range"}));
    if (caps().storageBuffers) {
        BufferHandle storage = createBuffer(BufferUsage::Storage, 256);
        EXPECT_TRUE(throwsRhiError(
            [&] {
                device().createBindingSet(
                    BindingSetDesc().add(BindingItem::storageBuffer(0, storage, 0, 16).setDynamicOffset()));
            },
            ErrorCode::InvalidDescription, {"only uniform buffers"}));
    }
    BindingSetDesc tooMany;
    for (uint32_t b = 0; b <= kMaxDynamicOffsetsPerSet; ++b) tooMany.add(dynamicSlice(b, uniform));
    EXPECT_TRUE(throwsRhiError([&] { device().createBindingSet(tooMany); }, ErrorCode::InvalidDescription,
                               {"kMaxDynamicOffsetsPerSet"}));
}

TEST_P(DynamicOffsetTest, APipelineDeclaresOnlyUniformBlocksItReads) {
    GraphicsPipelineDesc desc;
    desc.setShaders(shader("rt_fullscreen_vert"), shader("rt_sample_2d_frag")).addColorFormat(Format::RGBA8_UNORM);
    EXPECT_TRUE(throwsRhiError([&] { device().createGraphicsPipeline(GraphicsPipelineDesc(desc).addDynamicUniformBuffer(0, 0)); },
                               ErrorCode::InvalidDescription, {"set 0 binding 0", "not a uniform block"}));
    EXPECT_TRUE(throwsRhiError([&] { device().createGraphicsPipeline(GraphicsPipelineDesc(desc).addDynamicUniformBuffer(0, 5)); },
                               ErrorCode::InvalidDescription, {"set 0 binding 5", "do not read"}));
}

// Vulkan bakes the binding's kind into the pipeline's layout, so the set and the pipeline must
// agree on it; GL would not notice, and refuses it too, with the same code.
TEST_P(DynamicOffsetTest, ASetAndAPipelineMustAgreeOnWhichBindingsAreDynamic) {
    BufferHandle slices = sliceBuffer({m_colours.begin(), m_colours.end()});
    BindingSetHandle dynamicSet = device().createBindingSet(BindingSetDesc().add(dynamicSlice(0, slices)));
    BindingSetHandle staticSet = device().createBindingSet(BindingSetDesc().add(BindingItem::uniformBuffer(0, slices, 0, 16)));
    PipelineHandle dynamicPipeline = pipelineReading("bench_uniform_color_frag", {0});
    PipelineHandle staticPipeline = pipelineReading("bench_uniform_color_frag", {});
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    const auto drawWith = [&](const PipelineHandle& pipeline, const std::function<void(ICommandList&)>& bind) {
        CommandListHandle list = device().createCommandList();
        list->begin();
        list->beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        list->setPipeline(pipeline);
        bind(*list);
        list->draw(3);
    };
    EXPECT_TRUE(throwsRhiError([&] { drawWith(staticPipeline, [&](ICommandList& c) { c.setBindingSet(0, dynamicSet, at(1)); }); },
                               ErrorCode::InvalidUsage, {"set 0 binding 0", "addDynamicUniformBuffer(set, 0)"}));
    EXPECT_TRUE(throwsRhiError([&] { drawWith(dynamicPipeline, [&](ICommandList& c) { c.setBindingSet(0, staticSet); }); },
                               ErrorCode::InvalidUsage, {"set 0 binding 0", "setDynamicOffset()"}));
}

}  // namespace
}  // namespace janus::rhi::test
