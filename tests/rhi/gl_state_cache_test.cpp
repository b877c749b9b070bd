// The GL backend sets fixed-function state (a pipeline's raster, depth and blend state, the masks
// and depth range a pass's clears need) only where it changes (gl_state_cache.h): a frame drawn
// again with the same pipeline makes no state call but glUseProgram, and a pipeline after another
// sets only what differs. What the frames draw is checked too, so a state the cache wrongly
// skipped shows as wrong pixels as well as in the log. (RenderTargetTest and RasterTest check
// the states themselves on every backend, across lists.)
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "gl_call_log.h"

namespace janus::rhi::test {
namespace {

// The state calls made, in order: the function's name, and for glEnable and the like its cap.
GLCallLog& calls() { return GLCallLogTest::log(); }

void APIENTRY loggedEnable(GLenum cap) {
    calls().calls.push_back(fmt::format("glEnable {:#x}", cap));
    calls().original.glEnable(cap);
}
void APIENTRY loggedDisable(GLenum cap) {
    calls().calls.push_back(fmt::format("glDisable {:#x}", cap));
    calls().original.glDisable(cap);
}
void APIENTRY loggedEnablei(GLenum cap, GLuint index) {
    calls().calls.push_back(fmt::format("glEnablei {:#x}", cap));
    calls().original.glEnablei(cap, index);
}
void APIENTRY loggedDisablei(GLenum cap, GLuint index) {
    calls().calls.push_back(fmt::format("glDisablei {:#x}", cap));
    calls().original.glDisablei(cap, index);
}
void APIENTRY loggedCullFace(GLenum face) {
    calls().calls.push_back("glCullFace");
    calls().original.glCullFace(face);
}
void APIENTRY loggedFrontFace(GLenum winding) {
    calls().calls.push_back("glFrontFace");
    calls().original.glFrontFace(winding);
}
void APIENTRY loggedPolygonOffset(GLfloat slope, GLfloat constant) {
    calls().calls.push_back("glPolygonOffset");
    calls().original.glPolygonOffset(slope, constant);
}
void APIENTRY loggedDepthFunc(GLenum compare) {
    calls().calls.push_back("glDepthFunc");
    calls().original.glDepthFunc(compare);
}
void APIENTRY loggedDepthMask(GLboolean write) {
    calls().calls.push_back(fmt::format("glDepthMask {}", write ? "on" : "off"));
    calls().original.glDepthMask(write);
}
void APIENTRY loggedDepthRangef(GLfloat nearest, GLfloat farthest) {
    calls().calls.push_back("glDepthRangef");
    calls().original.glDepthRangef(nearest, farthest);
}
void APIENTRY loggedBlendFuncSeparate(GLenum a, GLenum b, GLenum c, GLenum d) {
    calls().calls.push_back("glBlendFunc");
    calls().original.glBlendFuncSeparate(a, b, c, d);
}
void APIENTRY loggedBlendFuncSeparatei(GLuint index, GLenum a, GLenum b, GLenum c, GLenum d) {
    calls().calls.push_back("glBlendFunc");
    calls().original.glBlendFuncSeparatei(index, a, b, c, d);
}
void APIENTRY loggedBlendEquationSeparate(GLenum color, GLenum alpha) {
    calls().calls.push_back("glBlendEquation");
    calls().original.glBlendEquationSeparate(color, alpha);
}
void APIENTRY loggedBlendEquationSeparatei(GLuint index, GLenum color, GLenum alpha) {
    calls().calls.push_back("glBlendEquation");
    calls().original.glBlendEquationSeparatei(index, color, alpha);
}
std::string colorMask(GLboolean r, GLboolean g, GLboolean b, GLboolean a) {
    return fmt::format("glColorMask {}{}{}{}", r ? "r" : "-", g ? "g" : "-", b ? "b" : "-", a ? "a" : "-");
}
void APIENTRY loggedColorMask(GLboolean r, GLboolean g, GLboolean b, GLboolean a) {
    calls().calls.push_back(colorMask(r, g, b, a));
    calls().original.glColorMask(r, g, b, a);
}
void APIENTRY loggedColorMaski(GLuint index, GLboolean r, GLboolean g, GLboolean b, GLboolean a) {
    calls().calls.push_back(colorMask(r, g, b, a));   // one attachment or all: the same here (one attachment)
    calls().original.glColorMaski(index, r, g, b, a);
}

class GLStateCacheTest : public GLCallLogTest {
protected:
    const char* watched() const override { return "the state cache"; }
    void watch(gl::GLFunctions& gl, GLEntryPointOverrides& overrides) override {
        overrides.replace(gl.glEnable, loggedEnable);
        overrides.replace(gl.glDisable, loggedDisable);
        overrides.replace(gl.glCullFace, loggedCullFace);
        overrides.replace(gl.glFrontFace, loggedFrontFace);
        overrides.replace(gl.glPolygonOffset, loggedPolygonOffset);
        overrides.replace(gl.glDepthFunc, loggedDepthFunc);
        overrides.replace(gl.glDepthMask, loggedDepthMask);
        overrides.replace(gl.glDepthRangef, loggedDepthRangef);
        overrides.replace(gl.glBlendFuncSeparate, loggedBlendFuncSeparate);
        overrides.replace(gl.glBlendEquationSeparate, loggedBlendEquationSeparate);
        overrides.replace(gl.glColorMask, loggedColorMask);
        // The indexed forms (GL 4.0; ES 3.0 has none, and the backend uses them only on GL).
        if (gl.glEnablei) overrides.replace(gl.glEnablei, loggedEnablei);
        if (gl.glDisablei) overrides.replace(gl.glDisablei, loggedDisablei);
        if (gl.glBlendFuncSeparatei) overrides.replace(gl.glBlendFuncSeparatei, loggedBlendFuncSeparatei);
        if (gl.glBlendEquationSeparatei) overrides.replace(gl.glBlendEquationSeparatei, loggedBlendEquationSeparatei);
        if (gl.glColorMaski) overrides.replace(gl.glColorMaski, loggedColorMaski);
    }

    // One list: a pass clearing `color` (and `depth` to 1) drawing `vertices` with each pipeline in
    // turn; returns the state calls it made.
    std::vector<std::string> frame(const TextureHandle& color, const TextureHandle& depth,
                                   const std::vector<PipelineHandle>& pipelines, const std::vector<ColorVertex>& vertices) {
        BufferHandle buffer = createBufferFrom(BufferUsage::Vertex, vertices);
        takeCalls();
        submit([&](ICommandList& cmd) {
            RenderPassDesc pass = RenderPassDesc().addColor(Attachment::clear(color, {0, 0, 1, 1}));
            if (depth) pass.setDepth(Attachment::clearDepthTo(depth, 1.0f));
            cmd.beginRenderPass(pass);
            cmd.setVertexBuffer(0, buffer);
            for (const PipelineHandle& pipeline : pipelines) {
                cmd.setPipeline(pipeline);
                cmd.draw(uint32_t(vertices.size()));
            }
            cmd.endRenderPass();
        });
        return takeCalls();
    }

    TextureHandle colorTarget() { return createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget); }
    TextureHandle depthTarget() {
        return device().createTexture(TextureDesc().setFormat(Format::D32_FLOAT).setSize(4, 4).setUsage(TextureUsage::RenderTarget));
    }
};
JANUS_INSTANTIATE_BACKEND_TESTS(GLStateCacheTest);

constexpr Rgba8 kRed{255, 0, 0, 255};

// The first frame sets what the pipeline needs; the same frame again sets nothing: the context
// still has it all (every state this pipeline sets is not GL's default, so a frame that set it
// again would show).
TEST_P(GLStateCacheTest, AFrameDrawnAgainSetsNoStateAgain) {
    TextureHandle color = colorTarget(), depth = depthTarget();
    RasterState raster;
    raster.cullMode = CullMode::Back;
    raster.depthBiasEnable = true;
    raster.depthBiasConstant = 1.0f;
    PipelineHandle pipeline = colorPipeline(Format::RGBA8_UNORM, Format::D32_FLOAT, raster,
                                            {true, true, CompareOp::LessOrEqual}, BlendAttachment::alpha());
    const std::vector<ColorVertex> square = rectangle(-1, -1, 1, 1, {1, 0, 0, 1}, 0.5f);
    const std::vector<std::string> first = frame(color, depth, {pipeline}, square);
    EXPECT_NE(std::find(first.begin(), first.end(), "glCullFace"), first.end()) << fmt::format("{}", fmt::join(first, ", "));
    EXPECT_NE(std::find(first.begin(), first.end(), "glBlendFunc"), first.end()) << fmt::format("{}", fmt::join(first, ", "));
    EXPECT_EQ(readTextureAs<Rgba8>(color), std::vector<Rgba8>(16, kRed));

    const std::vector<std::string> again = frame(color, depth, {pipeline}, square);
    EXPECT_TRUE(again.empty()) << fmt::format("{}", fmt::join(again, ", "));
    EXPECT_EQ(readTextureAs<Rgba8>(color), std::vector<Rgba8>(16, kRed)) << "the second frame draws as the first";
    for (float d : readTextureAs<float>(depth)) {   // 0.5 pushed back by one unit of depth bias
        EXPECT_GT(d, 0.5f);
        EXPECT_LT(d, 0.51f);
    }
}

// A pipeline after another sets only the states in which they differ: here the cull face.
TEST_P(GLStateCacheTest, APipelineAfterAnotherSetsOnlyWhatDiffers) {
    TextureHandle color = colorTarget();
    RasterState back, front;
    back.cullMode = CullMode::Back;
    front.cullMode = CullMode::Front;
    PipelineHandle cullBack = colorPipeline(Format::RGBA8_UNORM, Format::Unknown, back);
    PipelineHandle cullFront = colorPipeline(Format::RGBA8_UNORM, Format::Unknown, front);
    // Counter-clockwise in the image (RasterTest.CullingFollowsImageWinding): kept by the first
    // pipeline, culled by the second.
    const std::vector<ColorVertex> square = rectangle(-1, -1, 1, 1, {1, 0, 0, 1});
    frame(color, {}, {cullBack}, square);
    const std::vector<std::string> calls = frame(color, {}, {cullBack, cullFront}, square);
    EXPECT_EQ(calls, std::vector<std::string>{"glCullFace"});
    EXPECT_EQ(readTextureAs<Rgba8>(color), std::vector<Rgba8>(16, kRed)) << "drawn by the first, culled by the second";
}

// Write masks the pipeline narrows are widened for the next pass's clears and narrowed again for
// its draws, every frame: the clears need them, and the cache must not skip them. (A pass that
// clears no depth leaves the depth mask alone: APipelineAfterAnotherSetsOnlyWhatDiffers.)
TEST_P(GLStateCacheTest, NarrowedWriteMasksAreWidenedForEachPassesClears) {
    TextureHandle color = colorTarget(), depth = depthTarget();
    BlendAttachment redOnly;
    redOnly.writeMask = 0x1;
    PipelineHandle masked = colorPipeline(Format::RGBA8_UNORM, Format::D32_FLOAT, {}, {true, false, CompareOp::Always}, redOnly);
    const std::vector<ColorVertex> square = rectangle(-1, -1, 1, 1, {1, 1, 1, 1}, 0.25f);
    frame(color, depth, {masked}, square);
    const std::vector<std::string> calls = frame(color, depth, {masked}, square);
    EXPECT_EQ(calls, (std::vector<std::string>{colorMask(1, 1, 1, 1), "glDepthMask on", "glDepthMask off",
                                               colorMask(1, 0, 0, 0)}));
    EXPECT_EQ(readTextureAs<Rgba8>(color), std::vector<Rgba8>(16, Rgba8{255, 0, 255, 255})) << "blue cleared, red drawn";
    EXPECT_EQ(readTextureAs<float>(depth), std::vector<float>(16, 1.0f)) << "depth cleared, not written";
}

}  // namespace
}  // namespace janus::rhi::test
