// What the GL backend checks and says while a list replays (validation only):
// - the draw-time sampler check (Device::checkSamplerUnits): a draw whose program samples a
//   texture unit with nothing of its target bound, or reads a shadow sampler through a sampler
//   that does not compare, is reported as an error. NVIDIA's GL reports both as undefined
//   behaviour (id 131222); Mesa draws something and says nothing, so without the check such a
//   state would first show on a user's machine. The binding checks keep the RHI from producing
//   either, so these tests break the replay on purpose: the device's glBindTexture or
//   glBindSampler entry point is wrapped to bind nothing while one list replays;
// - a driver message during replay names the last pipeline bound (a wrapped draw call makes
//   the driver report an error);
// - a list leaves no program in use (NVIDIA checks the program in use on later calls that draw
//   nothing, when a texture it sampled may already be deleted).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "backend_test.h"
#include "gl_device.h"
#include "gl_entry_points.h"

namespace janus::rhi::test {
namespace {

struct DroppedBinds {
    PFNGLBINDTEXTUREPROC bindTexture = nullptr;
    PFNGLBINDSAMPLERPROC bindSampler = nullptr;
    PFNGLDRAWARRAYSPROC drawArrays = nullptr;
    PFNGLENABLEPROC enable = nullptr;
    bool dropTextures = false;
    bool dropSamplers = false;
    bool badEnableBeforeDraws = false;
};
DroppedBinds* g_dropped = nullptr;   // GL entry points are plain functions: the wrappers find it here

void APIENTRY droppingBindTexture(GLenum target, GLuint texture) {
    g_dropped->bindTexture(target, g_dropped->dropTextures ? 0 : texture);
}
void APIENTRY droppingBindSampler(GLuint unit, GLuint sampler) {
    g_dropped->bindSampler(unit, g_dropped->dropSamplers ? 0 : sampler);
}
void APIENTRY drawAfterABadEnable(GLenum mode, GLint first, GLsizei count) {
    if (g_dropped->badEnableBeforeDraws) g_dropped->enable(0xFFFFu);   // GL_INVALID_ENUM
    g_dropped->drawArrays(mode, first, count);
}

class GLReplayChecksTest : public BackendTest {
protected:
    void SetUp() override {
        BackendTest::SetUp();
        if (IsSkipped() || HasFatalFailure()) return;   // configuration not selected: no device
        if (backend() == Backend::Vulkan) GTEST_SKIP() << "the GL backend's draw-time check";
        m_gl = &dynamic_cast<gl::Device&>(device()).context().gl;
        g_dropped = &m_dropped;
        m_dropped.enable = m_gl->glEnable;
        m_dropped.bindTexture = m_overrides.replace(m_gl->glBindTexture, droppingBindTexture);
        m_dropped.bindSampler = m_overrides.replace(m_gl->glBindSampler, droppingBindSampler);
        m_dropped.drawArrays = m_overrides.replace(m_gl->glDrawArrays, drawAfterABadEnable);   // draw(3): one instance
    }
    void TearDown() override {
        m_overrides.restoreAll();
        g_dropped = nullptr;
        BackendTest::TearDown();
    }
    // One fullscreen draw of `fragmentShader` with `set` at 0, replayed with the chosen binds
    // dropped; returns the error messages it produced.
    std::vector<std::string> drawDropping(const char* fragmentShader, const BindingSetHandle& set, bool textures,
                                          bool samplers, bool badEnable = false) {
        TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 1, 1, TextureUsage::RenderTarget);
        PipelineHandle pipeline = fullscreenPipeline(fragmentShader, Format::RGBA8_UNORM);
        discardDebugMessages();
        m_dropped.dropTextures = textures;
        m_dropped.dropSamplers = samplers;
        m_dropped.badEnableBeforeDraws = badEnable;
        submit([&](ICommandList& cmd) {
            cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
            cmd.setPipeline(pipeline);
            cmd.setBindingSet(0, set);
            cmd.draw(3);
            cmd.endRenderPass();
        });
        device().waitIdle();
        m_dropped.dropTextures = m_dropped.dropSamplers = m_dropped.badEnableBeforeDraws = false;
        // The backend's own check, and the driver where it checks the same (NVIDIA: id 131222).
        std::vector<std::string> errors;
        for (const DebugMessage& m : device().takeDebugMessages()) {
            if (m.text.starts_with("GL debug (id 131222)") && !badEnable) continue;
            if (m.severity == MessageSeverity::Error) errors.push_back(m.text);
        }
        return errors;
    }
    BindingSetHandle depthSet(const SamplerDesc& sampler) {
        TextureHandle depth = createTexture2D(Format::D32_FLOAT, 1, 1, TextureUsage::Sampled);
        const float stored = 0.25f;
        device().writeTexture(depth, {}, &stored, sizeof stored);
        const std::array<float, 4 * 32> lookups{0.5f, 0.5f, 0.125f, 0.0f};
        return device().createBindingSet(BindingSetDesc()
                                             .add(BindingItem::uniformBuffer(0, createBuffer(BufferUsage::Uniform, std::as_bytes(std::span(lookups)))))
                                             .add(BindingItem::sampledTexture(1, depth, device().createSampler(sampler))));
    }

    const gl::GLFunctions& gl() const { return *m_gl; }

private:
    gl::GLFunctions* m_gl = nullptr;
    GLEntryPointOverrides m_overrides;
    DroppedBinds m_dropped;
};
JANUS_INSTANTIATE_BACKEND_TESTS(GLReplayChecksTest);

testing::AssertionResult mentions(const std::string& text, const std::string& part) {
    if (text.find(part) != std::string::npos) return testing::AssertionSuccess();
    return testing::AssertionFailure() << "'" << text << "' does not mention '" << part << "'";
}

const SamplerDesc kComparing =
    SamplerDesc().setFilter(Filter::Nearest).setAddress(AddressMode::ClampToEdge).setCompare(CompareOp::LessOrEqual);

TEST_P(GLReplayChecksTest, ADrawWithEverythingBoundReportsNothing) {
    EXPECT_EQ(drawDropping("rt_sample_at_shadow_frag", depthSet(kComparing), false, false), std::vector<std::string>{});
}

TEST_P(GLReplayChecksTest, AUnitLeftWithoutATextureIsReported) {
    const std::vector<std::string> errors = drawDropping("rt_sample_at_shadow_frag", depthSet(kComparing), true, false);
    ASSERT_EQ(errors.size(), 1u) << testing::PrintToString(errors);
    EXPECT_TRUE(mentions(errors[0], "janus_texture1"));
    EXPECT_TRUE(mentions(errors[0], "texture unit 1"));
    EXPECT_TRUE(mentions(errors[0], "no 2D texture is bound there"));
}

TEST_P(GLReplayChecksTest, AShadowSamplerReadWithoutComparisonIsReported) {
    // No sampler object: the texture's own parameters apply, which do not compare.
    const std::vector<std::string> errors = drawDropping("rt_sample_at_shadow_frag", depthSet(kComparing), false, true);
    ASSERT_EQ(errors.size(), 1u) << testing::PrintToString(errors);
    EXPECT_TRUE(mentions(errors[0], "janus_texture1"));
    EXPECT_TRUE(mentions(errors[0], "does not compare"));
}

TEST_P(GLReplayChecksTest, ADriverMessageDuringReplayNamesTheLastPipelineBound) {
    const std::vector<std::string> errors = drawDropping("rt_sample_at_shadow_frag", depthSet(kComparing), false, false, true);
    ASSERT_EQ(errors.size(), 1u) << testing::PrintToString(errors);
    EXPECT_TRUE(mentions(errors[0], "GL_INVALID_ENUM"));
    EXPECT_TRUE(mentions(errors[0], "last pipeline bound: 'rt_sample_at_shadow_frag'"));
    // Outside replay, messages name no pipeline.
    device().provokeValidationErrorForTesting();
    const std::vector<DebugMessage> outside = device().takeDebugMessages();
    ASSERT_FALSE(outside.empty());
    EXPECT_EQ(outside[0].text.find("last pipeline bound"), std::string::npos) << outside[0].text;
}

TEST_P(GLReplayChecksTest, AListLeavesNoProgramInUse) {
    EXPECT_EQ(drawDropping("rt_sample_at_shadow_frag", depthSet(kComparing), false, false), std::vector<std::string>{});
    GLint program = -1;
    gl().glGetIntegerv(GL_CURRENT_PROGRAM, &program);
    EXPECT_EQ(program, 0);
}

}  // namespace
}  // namespace janus::rhi::test
