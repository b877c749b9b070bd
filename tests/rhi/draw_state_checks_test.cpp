// A draw is checked against everything recorded since the last draw that passed: the pass, the
// pipeline and the sets. The GL backend records a draw whose state did not change without any
// check (rhi-gl/README.md, "Command lists"); these tests fail if a change is missed.
#include "backend_test.h"

namespace janus::rhi::test {
namespace {

class DrawStateCheckTest : public BackendTest {
protected:
    // Records `body` into a new list and says whether it threw InvalidUsage naming `mentions`.
    testing::AssertionResult recordingThrows(const std::function<void(ICommandList&)>& body,
                                             std::vector<std::string> mentions) {
        CommandListHandle list = device().createCommandList();
        list->begin();
        return throwsRhiError([&] { body(*list); list->end(); }, ErrorCode::InvalidUsage, std::move(mentions));
    }
    BindingSetHandle uniformSet() {
        return device().createBindingSet(BindingSetDesc().add(BindingItem::uniformBuffer(0, createBuffer(BufferUsage::Uniform, 256))));
    }
    BindingSetHandle textureSet() {
        TextureHandle texture = createTexture2D(Format::RGBA8_UNORM, 1, 1);
        return device().createBindingSet(BindingSetDesc().add(BindingItem::sampledTexture(0, texture, nearestClampSampler())));
    }
};
JANUS_INSTANTIATE_BACKEND_TESTS(DrawStateCheckTest);

// After a draw that passed: the pass ends, the next draw has none.
TEST_P(DrawStateCheckTest, ADrawAfterTheEndOfThePassIsRejected) {
    TextureHandle target = createTexture2D(Format::R32_UINT, 32, 1, TextureUsage::RenderTarget);
    PipelineHandle reading = fullscreenPipeline("rt_std140_read_frag", Format::R32_UINT);
    BindingSetHandle uniform = uniformSet();
    EXPECT_TRUE(recordingThrows([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        cmd.setPipeline(reading);
        cmd.setBindingSet(0, uniform);
        cmd.draw(3);
        cmd.draw(3);
        cmd.endRenderPass();
        cmd.draw(3);
    }, {"draw", "render pass"}));
}

// After a draw that passed: a set without the pipeline's binding type, in the same pass.
TEST_P(DrawStateCheckTest, ASetOfTheWrongTypeAfterADrawIsRejected) {
    TextureHandle target = createTexture2D(Format::R32_UINT, 32, 1, TextureUsage::RenderTarget);
    PipelineHandle reading = fullscreenPipeline("rt_std140_read_frag", Format::R32_UINT);
    BindingSetHandle uniform = uniformSet(), texture = textureSet();
    EXPECT_TRUE(recordingThrows([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        cmd.setPipeline(reading);
        cmd.setBindingSet(0, uniform);
        cmd.draw(3);
        cmd.setBindingSet(0, texture);
        cmd.draw(3);
        cmd.endRenderPass();
    }, {"binding 0"}));
}

// After a draw that passed: a pipeline whose colour format is not the pass's, in the same pass.
TEST_P(DrawStateCheckTest, APipelineOfAnotherFormatAfterADrawIsRejected) {
    JANUS_REQUIRE_CAPABILITY(Capability::FloatRenderTargets);
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    PipelineHandle sampling = fullscreenPipeline("rt_sample_2d_frag", Format::RGBA8_UNORM);
    PipelineHandle otherFormat = fullscreenPipeline("rt_sample_2d_frag", Format::RGBA16_FLOAT);
    BindingSetHandle texture = textureSet();
    EXPECT_TRUE(recordingThrows([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        cmd.setPipeline(sampling);
        cmd.setBindingSet(0, texture);
        cmd.draw(3);
        cmd.setPipeline(otherFormat);
        cmd.draw(3);
        cmd.endRenderPass();
    }, {"rgba16f", "rgba8"}));
}

// After a draw that passed: the same checks again, in a new pass of another format.
TEST_P(DrawStateCheckTest, ANewPassIsCheckedAgainstThePipeline) {
    JANUS_REQUIRE_CAPABILITY(Capability::FloatRenderTargets);
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    TextureHandle other = createTexture2D(Format::RGBA16_FLOAT, 4, 4, TextureUsage::RenderTarget);
    PipelineHandle sampling = fullscreenPipeline("rt_sample_2d_frag", Format::RGBA8_UNORM);
    BindingSetHandle texture = textureSet();
    EXPECT_TRUE(recordingThrows([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        cmd.setPipeline(sampling);
        cmd.setBindingSet(0, texture);
        cmd.draw(3);
        cmd.endRenderPass();
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(other)));
        cmd.draw(3);
        cmd.endRenderPass();
    }, {"rgba16f", "rgba8"}));
}

}  // namespace
}  // namespace janus::rhi::test
