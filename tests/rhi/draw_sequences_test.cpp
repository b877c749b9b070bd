// Draws whose state changes between them: each draw renders what it was given, whatever the draw
// before it did. The GL backend replays a draw of one instance from instance 0 as glDrawArrays
// alone while nothing changed since such a draw (Device::draw); each step below changes one thing
// that must end that (a vertex buffer, a pipeline with another vertex layout, a draw from another
// instance, an indexed draw with a vertex offset, which ES 3.0 makes by moving the attribute
// pointers).
#include "backend_test.h"

namespace janus::rhi::test {
namespace {

class DrawSequenceTest : public BackendTest {
protected:
    static constexpr Color kRed{1, 0, 0, 1}, kGreen{0, 1, 0, 1}, kBlue{0, 0, 1, 1}, kYellow{1, 1, 0, 1};
    static constexpr std::array<float, 6> kWholeTarget{-1, -1, 3, -1, -1, 3};
    static constexpr Rgba8 r{255, 0, 0, 255}, g{0, 255, 0, 255}, b{0, 0, 255, 255}, y{255, 255, 0, 255};

    // Vertices 0..2: a red triangle over the whole target; vertices 3..5: a green one.
    BufferHandle redThenGreenTriangles() {
        std::vector<ColorVertex> vertices = triangle(kWholeTarget, kRed);
        for (const ColorVertex& v : triangle(kWholeTarget, kGreen)) vertices.push_back(v);
        return createBufferFrom(BufferUsage::Vertex, vertices);
    }
    // Slot 1 of instancedPipeline(): instance 0 blue, instance 1 yellow.
    BufferHandle blueThenYellowInstances() {
        return createBufferFrom(BufferUsage::Vertex, std::vector<Color>{kBlue, kYellow});
    }
};
JANUS_INSTANTIATE_BACKEND_TESTS(DrawSequenceTest);

TEST_P(DrawSequenceTest, EachDrawRendersItsOwnStateAfterAnyOther) {
    BufferHandle twoTriangles = redThenGreenTriangles();
    BufferHandle greenTriangle = createBufferFrom(BufferUsage::Vertex, triangle(kWholeTarget, kGreen));
    BufferHandle instanceColors = blueThenYellowInstances();
    BufferHandle indices = createBufferFrom(BufferUsage::Index, std::vector<uint16_t>{0, 1, 2});
    PipelineHandle vertexColors = colorPipeline(Format::RGBA8_UNORM);
    PipelineHandle instanced = instancedPipeline();   // slot 0: positions, slot 1: a colour per instance
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 9, 1, TextureUsage::RenderTarget);
    submit([&](ICommandList& cmd) {
        // Each draw into a column of its own. rt_instanced_vert moves instance i right by 0.5 *
        // gl_InstanceIndex, which leaves columns 0 and 1 uncovered for any instance but 0.
        auto at = [&](int32_t column) { cmd.setScissor({column, 0, 1, 1}); };
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        cmd.setPipeline(vertexColors);
        cmd.setVertexBuffer(0, twoTriangles);
        at(2);
        cmd.draw(3);   // red
        cmd.setVertexBuffer(0, greenTriangle);
        at(3);
        cmd.draw(3);   // green: another buffer
        cmd.setPipeline(instanced);
        cmd.setVertexBuffer(1, instanceColors);
        at(1);
        cmd.draw(3);   // blue: another vertex layout
        at(4);
        cmd.draw(3, 1, 0, 1);   // yellow: instance 1
        at(0);
        cmd.draw(3);   // blue: instance 0 again, not moved right
        cmd.setPipeline(vertexColors);
        at(5);
        cmd.draw(3);   // green: the first layout again
        cmd.setVertexBuffer(0, twoTriangles);
        cmd.setIndexBuffer(indices, IndexType::UInt16);
        at(6);
        cmd.draw(3);   // red
        at(7);
        cmd.drawIndexed(3, 1, 0, 3);   // green: vertices 3..5
        at(8);
        cmd.draw(3);   // red: vertices 0..2, not 3..5
        cmd.endRenderPass();
    });
    EXPECT_EQ(readTextureAs<Rgba8>(target), (std::vector<Rgba8>{b, b, r, g, y, g, r, g, r}));
}

// A set bound right before a draw: the GL backend records the two as one command, with a form of
// its own for a draw of one instance from instance 0. Each draw must still take its own
// arguments: a first vertex, an instance count, a first instance. (The pipelines read no set: what
// is tested is the command a bind and a draw make together, which does not depend on it.)
TEST_P(DrawSequenceTest, DrawsRightAfterASetBindTakeTheirOwnArguments) {
    BufferHandle twoTriangles = redThenGreenTriangles();
    BufferHandle instanceColors = blueThenYellowInstances();
    BufferHandle uniforms = createBufferFrom(BufferUsage::Uniform, std::vector<float>(128, 0.0f));
    // Two sets, bound in turn: binding the set already bound records nothing.
    const std::array<BindingSetHandle, 2> sets{
        device().createBindingSet(BindingSetDesc().add(BindingItem::uniformBuffer(0, uniforms, 0, 256))),
        device().createBindingSet(BindingSetDesc().add(BindingItem::uniformBuffer(0, uniforms, 256, 256)))};
    PipelineHandle vertexColors = colorPipeline(Format::RGBA8_UNORM);
    PipelineHandle instanced = instancedPipeline();
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 6, 1, TextureUsage::RenderTarget);
    submit([&](ICommandList& cmd) {
        uint32_t next = 0;
        auto at = [&](int32_t column) {
            cmd.setScissor({column, 0, 1, 1});
            cmd.setBindingSet(0, sets[next++ % 2]);   // right before the draw
        };
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        cmd.setPipeline(vertexColors);
        cmd.setVertexBuffer(0, twoTriangles);
        at(0);
        cmd.draw(3);   // red
        at(1);
        cmd.draw(3, 1, 3);   // green: vertices 3..5
        cmd.setPipeline(instanced);
        cmd.setVertexBuffer(1, instanceColors);
        at(2);
        cmd.draw(3);   // blue: instance 0
        at(3);
        cmd.draw(3, 1, 0, 1);   // yellow: instance 1 (moved right, still covering columns 2..5)
        at(4);
        cmd.draw(3, 2);   // yellow: instance 1 drawn over instance 0
        at(5);
        cmd.draw(3, 1, 3);   // blue: vertices 3..5 of instance 0
        cmd.endRenderPass();
    });
    EXPECT_EQ(readTextureAs<Rgba8>(target), (std::vector<Rgba8>{r, g, b, y, y, b}));
}

}  // namespace
}  // namespace janus::rhi::test
