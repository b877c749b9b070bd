// Draws may not read past their vertex, instance or index buffers (rhi/backend-api/janus/rhi/
// draw_range_validation.h): drivers leave such reads undefined (Mesa reads zeros, a silent wrong
// image), so every backend refuses them with InvalidUsage, as WebGPU does. Each case also draws
// right up to the end, which must pass, and repeats the bad draw after a good one with the same
// state (the GL backend records such a draw on its unchecked path).
#include "backend_test.h"

namespace janus::rhi::test {
namespace {

class DrawRangeTest : public BackendTest {
protected:
    // Records `body` in a render pass on an 8x8 target; returns whether it threw InvalidUsage
    // naming `mentions` (or, with no mentions, that it did not throw and the list executed).
    testing::AssertionResult recordDraws(const std::function<void(ICommandList&)>& body,
                                         std::vector<std::string> mentions = {}) {
        TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 8, 8, TextureUsage::RenderTarget);
        CommandListHandle list = device().createCommandList();
        list->begin();
        auto record = [&] {
            list->beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
            body(*list);
            list->endRenderPass();
            list->end();
        };
        if (!mentions.empty()) return throwsRhiError(record, ErrorCode::InvalidUsage, std::move(mentions));
        try {
            record();
            device().execute(list);
        } catch (const Error& e) {
            return testing::AssertionFailure() << "a draw inside its buffers threw: " << e.what();
        }
        return testing::AssertionSuccess();
    }
};
JANUS_INSTANTIATE_BACKEND_TESTS(DrawRangeTest);

TEST_P(DrawRangeTest, VerticesPastTheVertexBufferAreRefused) {
    BufferHandle three = createBufferFrom(BufferUsage::Vertex, triangle({-1, -1, 1, -1, -1, 1}, {1, 0, 0, 1}));
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_UNORM);
    auto bind = [&](ICommandList& cmd) {
        cmd.setPipeline(pipeline);
        cmd.setVertexBuffer(0, three);
    };
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) { bind(cmd); cmd.draw(3); cmd.draw(1, 1, 2); }));
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) { bind(cmd); cmd.draw(4); }, {"vertices 0..3", "slot 0", "3 vertices"}));
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) { bind(cmd); cmd.draw(3, 1, 1); }, {"vertices 1..3"}));
    // A first vertex far past the end: no 32-bit wrap-around lets it through.
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) { bind(cmd); cmd.draw(3, 1, 0xFFFFFFFFu); }, {"slot 0"}));
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) { bind(cmd); cmd.draw(3); cmd.draw(4); }, {"vertices 0..3"}))
        << "after a draw that passed with the same state";
}

TEST_P(DrawRangeTest, AVertexBufferOffsetLeavesLessToRead) {
    std::vector<ColorVertex> four = triangle({-1, -1, 1, -1, -1, 1}, {1, 0, 0, 1});
    four.push_back(four[0]);
    BufferHandle buffer = createBufferFrom(BufferUsage::Vertex, four);
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_UNORM);
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) {
        cmd.setPipeline(pipeline);
        cmd.setVertexBuffer(0, buffer, sizeof(ColorVertex));
        cmd.draw(3);
    }));
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) {
        cmd.setPipeline(pipeline);
        cmd.setVertexBuffer(0, buffer, 2 * sizeof(ColorVertex));
        cmd.draw(3);
    }, {"offset 64", "2 vertices"}));
}

// The last vertex needs only the bytes its attributes read, not a whole stride.
TEST_P(DrawRangeTest, TheLastVertexNeedsOnlyItsAttributes) {
    struct Padded { float x, y; float pad[6]; };   // stride 32, attribute bytes 0..7
    std::vector<std::byte> bytes(2 * sizeof(Padded) + 2 * sizeof(float));   // three vertices, the last short
    BufferHandle buffer = createBuffer(BufferUsage::Vertex, bytes);
    GraphicsPipelineDesc desc;
    desc.setShaders(shader("rt_vertex_color_vert"), shader("rt_vertex_color_frag"))
        .addVertexBuffer({0, sizeof(Padded), false})
        .addVertexAttribute({0, VertexFormat::Float2, 0, 0})
        .addVertexAttribute({1, VertexFormat::Float2, 0, 0})
        .addColorFormat(Format::RGBA8_UNORM);
    PipelineHandle pipeline = device().createGraphicsPipeline(desc);
    auto bind = [&](ICommandList& cmd) {
        cmd.setPipeline(pipeline);
        cmd.setVertexBuffer(0, buffer);
    };
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) { bind(cmd); cmd.draw(3); }));
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) { bind(cmd); cmd.draw(4); }, {"3 vertices", "stride 32"}));
}

TEST_P(DrawRangeTest, InstancesPastThePerInstanceBufferAreRefused) {
    BufferHandle vertices = createBufferFrom(BufferUsage::Vertex, triangle({-1, -1, 1, -1, -1, 1}, {0, 0, 0, 0}));
    BufferHandle twoInstances = createBufferFrom(BufferUsage::Vertex, std::vector<Color>{{1, 0, 0, 1}, {0, 1, 0, 1}});
    BufferHandle indices = createBufferFrom(BufferUsage::Index, std::vector<uint16_t>{0, 1, 2});
    PipelineHandle pipeline = instancedPipeline();
    auto bind = [&](ICommandList& cmd) {
        cmd.setPipeline(pipeline);
        cmd.setVertexBuffer(0, vertices);
        cmd.setVertexBuffer(1, twoInstances);
        cmd.setIndexBuffer(indices, IndexType::UInt16);
    };
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) { bind(cmd); cmd.draw(3, 2); cmd.drawIndexed(3, 1, 0, 0, 1); }));
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) { bind(cmd); cmd.draw(3, 3); }, {"instances 0..2", "slot 1"}));
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) { bind(cmd); cmd.drawIndexed(3, 2, 0, 0, 1); }, {"instances 1..2"}));
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) { bind(cmd); cmd.draw(3, 2); cmd.draw(3, 2, 0, 1); }, {"instances 1..2"}))
        << "after a draw that passed with the same state";
}

TEST_P(DrawRangeTest, IndicesPastTheIndexBufferAreRefused) {
    BufferHandle vertices = createBufferFrom(BufferUsage::Vertex, triangle({-1, -1, 1, -1, -1, 1}, {1, 0, 0, 1}));
    // As 32-bit indices the same 12 bytes are 0, 1, 2 (little-endian): every value names a vertex.
    BufferHandle sixShorts = createBufferFrom(BufferUsage::Index, std::vector<uint16_t>{0, 0, 1, 0, 2, 0});
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_UNORM);
    auto bind = [&](ICommandList& cmd, IndexType type, uint64_t offset) {
        cmd.setPipeline(pipeline);
        cmd.setVertexBuffer(0, vertices);
        cmd.setIndexBuffer(sixShorts, type, offset);
    };
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) { bind(cmd, IndexType::UInt16, 0); cmd.drawIndexed(6); cmd.drawIndexed(3, 1, 3); }));
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) { bind(cmd, IndexType::UInt16, 0); cmd.drawIndexed(7); },
                            {"indices 0..6", "6 16-bit indices"}));
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) { bind(cmd, IndexType::UInt16, 4); cmd.drawIndexed(5); },
                            {"indices 0..4", "4 16-bit indices from offset 4"}));
    // The same 12 bytes hold three 32-bit indices.
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) { bind(cmd, IndexType::UInt32, 0); cmd.drawIndexed(3); }));
    EXPECT_TRUE(recordDraws([&](ICommandList& cmd) { bind(cmd, IndexType::UInt32, 0); cmd.drawIndexed(3); cmd.drawIndexed(3, 1, 1); },
                            {"indices 1..3", "3 32-bit indices"}))
        << "after a draw that passed with the same state";
}

}  // namespace
}  // namespace janus::rhi::test
