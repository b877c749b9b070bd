// The fixed-function state the GL backend sets, as it last set it on one context: a pipeline's
// raster, depth and blend state, and the write masks and depth range a render pass's clears need.
// A setter calls GL only when the value differs, so the pipeline a frame binds again (in its next
// pass or its next list) costs its glUseProgram and nothing else, as in raw GL, which sets such
// state once (each call is driver CPU time per frame: docs/BENCHMARKS.md, session 24). It stays true because nothing else sets these states: every call that does goes through
// here (Pipeline::applyState, Device::beginRenderPass). State it does not know yet (a new
// context) is set on first use.
#pragma once

#include <array>
#include <cstdint>
#include <utility>

#include "gl_functions.h"

namespace janus::rhi::gl {

class GLStateCache {
public:
    // Indexed colour state beyond this many attachments is set on every call, uncached.
    static constexpr uint32_t kCachedAttachments = 8;

    // `gl` outlives the cache (both are the context's); `es`: one blend state and colour mask for
    // all attachments (ES 3.0 has no indexed ones).
    GLStateCache(const GLFunctions& gl, bool es) : m_gl(gl), m_es(es) {}

    void setCulling(bool enable, GLenum face) {
        if (m_cullEnable.update(enable)) enable ? m_gl.glEnable(GL_CULL_FACE) : m_gl.glDisable(GL_CULL_FACE);
        if (enable && m_cullFace.update(face)) m_gl.glCullFace(face);
    }
    void setFrontFace(GLenum winding) {
        if (m_frontFace.update(winding)) m_gl.glFrontFace(winding);
    }
    void setPolygonOffset(bool enable, float slope, float constant) {
        if (m_offsetEnable.update(enable))
            enable ? m_gl.glEnable(GL_POLYGON_OFFSET_FILL) : m_gl.glDisable(GL_POLYGON_OFFSET_FILL);
        if (enable && m_offset.update({slope, constant})) m_gl.glPolygonOffset(slope, constant);
    }
    void setDepthTest(bool enable, GLenum compare) {
        if (m_depthTest.update(enable)) enable ? m_gl.glEnable(GL_DEPTH_TEST) : m_gl.glDisable(GL_DEPTH_TEST);
        if (enable && m_depthFunc.update(compare)) m_gl.glDepthFunc(compare);
    }
    void setAlphaToCoverage(bool enable) {
        if (m_alphaToCoverage.update(enable))
            enable ? m_gl.glEnable(GL_SAMPLE_ALPHA_TO_COVERAGE) : m_gl.glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
    }
    void setDepthMask(bool write) {
        if (m_depthMask.update(write)) m_gl.glDepthMask(write ? GL_TRUE : GL_FALSE);
    }
    void setDepthRange(float nearest, float farthest) {
        if (m_depthRange.update({nearest, farthest})) m_gl.glDepthRangef(nearest, farthest);
    }

    // Blending of colour attachment `index` (on ES, of all of them): enabled with these factors
    // and operations, or disabled (`factors` and `operations` then unused).
    struct Blend {
        bool enable = false;
        std::array<GLenum, 4> factors{};      // source colour, destination colour, source alpha, destination alpha
        std::array<GLenum, 2> operations{};   // colour, alpha
    };
    void setBlend(uint32_t index, const Blend& blend) {
        const bool cached = index < kCachedAttachments;
        Attachment* a = cached ? &m_attachments[index] : nullptr;
        if (!cached || a->blendEnable.update(blend.enable)) {
            if (m_es) blend.enable ? m_gl.glEnable(GL_BLEND) : m_gl.glDisable(GL_BLEND);
            else blend.enable ? m_gl.glEnablei(GL_BLEND, index) : m_gl.glDisablei(GL_BLEND, index);
        }
        if (!blend.enable) return;
        const auto& [srcColor, dstColor, srcAlpha, dstAlpha] = blend.factors;
        if (!cached || a->blendFactors.update(blend.factors)) {
            if (m_es) m_gl.glBlendFuncSeparate(srcColor, dstColor, srcAlpha, dstAlpha);
            else m_gl.glBlendFuncSeparatei(index, srcColor, dstColor, srcAlpha, dstAlpha);
        }
        if (!cached || a->blendOperations.update(blend.operations)) {
            if (m_es) m_gl.glBlendEquationSeparate(blend.operations[0], blend.operations[1]);
            else m_gl.glBlendEquationSeparatei(index, blend.operations[0], blend.operations[1]);
        }
    }
    // The colour write mask (RGBA bits) of attachment `index` (on ES, of all of them).
    void setColorMask(uint32_t index, uint8_t mask) {
        if (index < kCachedAttachments) {
            if (!m_attachments[index].colorMask.update(mask)) return;
        } else {
            m_uncachedMasksMayDiffer = true;
        }
        if (m_es) m_gl.glColorMask(channel(mask, 1), channel(mask, 2), channel(mask, 4), channel(mask, 8));
        else m_gl.glColorMaski(index, channel(mask, 1), channel(mask, 2), channel(mask, 4), channel(mask, 8));
    }
    // Every attachment's colour write mask at once (glColorMask).
    void setAllColorMasks(uint8_t mask) {
        bool changed = false;
        for (uint32_t i = 0; i < (m_es ? 1 : kCachedAttachments); ++i) changed = m_attachments[i].colorMask.update(mask) || changed;
        if (!changed && !m_uncachedMasksMayDiffer) return;
        m_gl.glColorMask(channel(mask, 1), channel(mask, 2), channel(mask, 4), channel(mask, 8));
        m_uncachedMasksMayDiffer = false;
    }

private:
    template <class T>
    struct Known {
        T value{};
        bool known = false;
        // Whether `v` differs from what GL has (or GL's value is not known): then it is recorded.
        bool update(const T& v) {
            if (known && value == v) return false;
            value = v;
            known = true;
            return true;
        }
    };
    struct Attachment {
        Known<bool> blendEnable;
        Known<std::array<GLenum, 4>> blendFactors;
        Known<std::array<GLenum, 2>> blendOperations;
        Known<uint8_t> colorMask;
    };
    static GLboolean channel(uint8_t mask, uint8_t bit) { return (mask & bit) ? GL_TRUE : GL_FALSE; }

    const GLFunctions& m_gl;
    bool m_es;
    Known<bool> m_cullEnable, m_offsetEnable, m_depthTest, m_depthMask, m_alphaToCoverage;
    Known<GLenum> m_cullFace, m_frontFace, m_depthFunc;
    Known<std::pair<float, float>> m_offset, m_depthRange;
    std::array<Attachment, kCachedAttachments> m_attachments;
    bool m_uncachedMasksMayDiffer = true;   // attachments past kCachedAttachments (GL only)
};

}  // namespace janus::rhi::gl
