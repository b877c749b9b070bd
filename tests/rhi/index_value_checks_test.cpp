// With validation on (every backend test), IDevice::execute checks the index values of indexed
// draws against the per-vertex buffers before the backend runs the list
// (rhi/backend-api/janus/rhi/index_value_validation.h): an index past the last vertex reads memory
// the draw does not own (Mesa: zeros, a silent wrong image; other drivers: other memory or a device
// fault). The check sees what the host wrote, in the order the device and the lists write it.
#include "backend_test.h"

namespace janus::rhi::test {
namespace {

constexpr Rgba8 kBefore{0, 0, 255, 255};   // what the target holds before a list that is refused

class IndexValueTest : public BackendTest {
protected:
    void SetUp() override {
        BackendTest::SetUp();
        if (IsSkipped()) return;
        m_target = createTexture2D(Format::RGBA8_UNORM, 8, 8, TextureUsage::RenderTarget);
        m_threeVertices = createBufferFrom(BufferUsage::Vertex, triangle({-1, -1, 3, -1, -1, 3}, {1, 0, 0, 1}));
        m_pipeline = colorPipeline(Format::RGBA8_UNORM);
    }

    struct Draw {
        uint32_t indexCount = 3, firstIndex = 0;
        int32_t vertexOffset = 0;
    };
    // A list that runs `before` (outside the pass), then draws each of `draws` from `indices`
    // over the three-vertex triangle, which covers the target (red).
    CommandListHandle record(const BufferHandle& indices, std::vector<Draw> draws, IndexType type = IndexType::UInt16,
                             const std::function<void(ICommandList&)>& before = {},
                             const BufferHandle& vertices = nullptr) {
        CommandListHandle list = device().createCommandList();
        list->begin();
        if (before) before(*list);
        list->beginRenderPass(RenderPassDesc().addColor(Attachment::clear(m_target, {0, 0, 0, 1})));
        list->setPipeline(m_pipeline);
        list->setVertexBuffer(0, vertices ? vertices : m_threeVertices);
        list->setIndexBuffer(indices, type);
        for (const Draw& d : draws) list->drawIndexed(d.indexCount, 1, d.firstIndex, d.vertexOffset);
        list->endRenderPass();
        list->end();
        return list;
    }
    // The target cleared to kBefore by a list of its own.
    void resetTarget() {
        submit([&](ICommandList& cmd) {
            cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(m_target, {0, 0, 1, 1})));
            cmd.endRenderPass();
        });
    }
    Rgba8 targetTexel() { return readTextureAs<Rgba8>(m_target)[0]; }

    // `list` executes, and its triangle covered the target.
    testing::AssertionResult executes(const CommandListHandle& list) {
        resetTarget();
        try {
            device().execute(list);
        } catch (const Error& e) {
            return testing::AssertionFailure() << "execute() threw: " << e.what();
        }
        if (const Rgba8 texel = targetTexel(); texel != Rgba8{255, 0, 0, 255})
            return testing::AssertionFailure() << "the list executed, but texel (0, 0) is " << testing::PrintToString(texel) << ", not red";
        return testing::AssertionSuccess();
    }
    // execute(`list`) throws InvalidUsage naming `mentions`, and the list did not run.
    testing::AssertionResult refused(const CommandListHandle& list, std::vector<std::string> mentions) {
        resetTarget();
        testing::AssertionResult result =
            throwsRhiError([&] { device().execute(list); }, ErrorCode::InvalidUsage, std::move(mentions));
        if (!result) return result;
        if (const Rgba8 texel = targetTexel(); texel != kBefore)
            return testing::AssertionFailure() << "refused, but the list ran: texel (0, 0) is " << testing::PrintToString(texel);
        return testing::AssertionSuccess();
    }

    TextureHandle m_target;
    BufferHandle m_threeVertices;
    PipelineHandle m_pipeline;
};
JANUS_INSTANTIATE_BACKEND_TESTS(IndexValueTest);

TEST_P(IndexValueTest, ValuesPastTheLastVertexAreRefusedBeforeTheListRuns) {
    BufferHandle indices = createBufferFrom(BufferUsage::Index, std::vector<uint16_t>{0, 1, 2, 0, 1, 3});
    EXPECT_TRUE(executes(record(indices, {{3}})));
    EXPECT_TRUE(refused(record(indices, {{6}}), {"drawIndexed #1", "index value 3 at index 5", "16-bit",
                                                 "names vertex 3", "vertex buffer slot 0 holds 3 vertices",
                                                 "stride 32", "vertices 0..2"}));
    // The second draw of the list is the one named; the first still did not run.
    EXPECT_TRUE(refused(record(indices, {{3}, {3, 3}}), {"drawIndexed #2", "index value 3 at index 5"}));

    BufferHandle wide = createBufferFrom(BufferUsage::Index, std::vector<uint32_t>{0, 1, 2, 70000});
    EXPECT_TRUE(executes(record(wide, {{3}}, IndexType::UInt32)));
    EXPECT_TRUE(refused(record(wide, {{3, 1}}, IndexType::UInt32), {"index value 70000 at index 3", "32-bit"}));
}

TEST_P(IndexValueTest, TheVertexOffsetIsAddedToEveryValue) {
    BufferHandle indices = createBufferFrom(BufferUsage::Index, std::vector<uint16_t>{1, 0, 2});
    EXPECT_TRUE(refused(record(indices, {{3, 0, 1}}), {"index value 2 at index 2", "plus vertexOffset 1",
                                                      "names vertex 3", "or the vertexOffset"}));
    if (backend() == Backend::GLES) {
        // ES moves the attribute pointers by vertexOffset instead of a base vertex, which cannot
        // go before the buffer: refused when recorded, before any index is looked at
        // (BufferTest.ANegativeVertexOffsetDrawsItsVerticesOrSaysWhyNot).
        try {
            record(indices, {{3, 0, -1}});
            ADD_FAILURE() << "gles recorded a vertexOffset that moves its attribute pointers before the buffer";
        } catch (const Error& error) {
            EXPECT_EQ(error.code(), ErrorCode::UnsupportedCapability) << error.what();
        }
    } else {
        EXPECT_TRUE(refused(record(indices, {{3, 0, -1}}), {"index value 0 at index 1", "names vertex -1"}));
    }
    // With a fourth vertex, offset 1 names vertices 1..3: inside.
    std::vector<ColorVertex> four = triangle({-1, -1, 3, -1, -1, 3}, {1, 0, 0, 1});
    four.insert(four.begin(), four[2]);
    BufferHandle fourVertices = createBufferFrom(BufferUsage::Vertex, four);
    EXPECT_TRUE(executes(record(indices, {{3, 0, 1}}, IndexType::UInt16, {}, fourVertices)));
}

TEST_P(IndexValueTest, HostWritesAfterRecordingAreWhatTheCheckSees) {
    BufferHandle indices = createBufferFrom(BufferUsage::Index, std::vector<uint16_t>{0, 1, 2});
    CommandListHandle list = record(indices, {{3}});
    const std::vector<uint16_t> bad{0, 1, 3}, good{0, 1, 2};
    device().writeBuffer(indices, bad.data(), 6);
    EXPECT_TRUE(refused(list, {"index value 3 at index 2"}));
    device().writeBuffer(indices, &good[2], 2, 4);   // the last index only
    EXPECT_TRUE(executes(list)) << "the same list, executed again after the fix";
}

TEST_P(IndexValueTest, AListSeesItsOwnWritesInOrder) {
    const std::vector<uint16_t> bad{0, 1, 3}, good{0, 1, 2};
    BufferHandle indices = createBufferFrom(BufferUsage::Index, bad);
    auto writes = [&](const std::vector<uint16_t>& values) {
        return [&values, &indices](ICommandList& cmd) { cmd.writeBuffer(indices, values.data(), 6); };
    };
    EXPECT_TRUE(executes(record(indices, {{3}}, IndexType::UInt16, writes(good)))) << "written before its draw";
    EXPECT_TRUE(executes(record(indices, {{3}}))) << "the executed list's write stays";
    EXPECT_TRUE(refused(record(indices, {{3}}, IndexType::UInt16, writes(bad)), {"index value 3"}));
    // The refused list never ran, so its write did not happen either.
    EXPECT_TRUE(executes(record(indices, {{3}})));
    EXPECT_EQ(readBufferAs<uint16_t>(indices), good);
}

// A copy into an index buffer puts there what the host never saw: such a buffer is not checked
// (neither against stale contents nor at all) until the host writes all of it again.
TEST_P(IndexValueTest, CopiedIndicesAreLeftUncheckedUntilTheHostWritesThemAll) {
    const std::vector<uint16_t> bad{0, 1, 3}, good{0, 1, 2};
    BufferHandle indices = createBufferFrom(BufferUsage::Index, bad);
    BufferHandle staging = createBufferFrom(BufferUsage::None, good);
    EXPECT_TRUE(executes(record(indices, {{3}}, IndexType::UInt16,
                                [&](ICommandList& cmd) { cmd.copyBuffer(indices, 0, staging, 0, 6); })));
    EXPECT_TRUE(executes(record(indices, {{3}}))) << "still unchecked after that list";
    device().writeBuffer(indices, bad.data(), 6);
    EXPECT_TRUE(refused(record(indices, {{3}}), {"index value 3"})) << "known again after a whole write";
    device().writeBuffer(indices, good.data(), 6);
}

// What a shader writes the host cannot know: a buffer a binding set can write is not checked.
TEST_P(IndexValueTest, IndicesAShaderCanWriteAreNotChecked) {
    JANUS_REQUIRE_CAPABILITY(Capability::StorageBuffers);
    const std::vector<uint32_t> bad{0, 1, 3};
    BufferHandle indices = createBufferFrom(BufferUsage::Index | BufferUsage::Storage, bad);
    EXPECT_TRUE(refused(record(indices, {{3}}, IndexType::UInt32), {"index value 3"})) << "before any binding set";
    PipelineHandle writeIndices = computePipeline("rt_write_indices_comp");
    BindingSetHandle storage = storageSlice(indices, 0, 3 * sizeof(uint32_t));
    EXPECT_TRUE(executes(record(indices, {{3}}, IndexType::UInt32, [&](ICommandList& cmd) {
        cmd.setPipeline(writeIndices);
        cmd.setBindingSet(0, storage);
        cmd.dispatch(1);
    })));
    EXPECT_EQ(readBufferAs<uint32_t>(indices), (std::vector<uint32_t>{0, 1, 2}));
}

// Without a per-vertex buffer the values name no memory (the shader makes the vertex of its index).
TEST_P(IndexValueTest, APipelineWithoutVertexBuffersTakesAnyValue) {
    PipelineHandle fullscreen = fullscreenPipeline("rt_uv_frag", Format::RGBA8_UNORM);
    BufferHandle indices = createBufferFrom(BufferUsage::Index, std::vector<uint16_t>{0, 1, 2, 60000});
    submit([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(m_target)));
        cmd.setPipeline(fullscreen);
        cmd.setIndexBuffer(indices, IndexType::UInt16);
        cmd.drawIndexed(4);
        cmd.endRenderPass();
    });
}

}  // namespace
}  // namespace janus::rhi::test
