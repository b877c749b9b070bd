// The benchmark workload expressed with the Janus RHI. The raw GL side also borrows the GLSL this
// scene's shaders were translated to, so both GL sides compile the identical program.
#pragma once

#include <janus/rhi/rhi.h>

#include <string>
#include <vector>

#include "bench_common.h"

namespace janus::bench {

class RhiScene : public Environment {
public:
    explicit RhiScene(rhi::Backend backend);

    rhi::IDevice& device() { return *m_device; }
    bool hasCompute() const { return m_computePipeline != nullptr; }
    const rhi::ShaderHandle& vertexShader() const { return m_vertexShader; }
    const rhi::ShaderHandle& fragmentShader() const { return m_fragmentShader; }
    const rhi::ShaderHandle& computeShader() const { return m_computeShader; }

    // Record and execute one frame (opsPerFrame() draws or dispatches); waitIdle() finishes it.
    void submitDraws(DrawSlices slices = DrawSlices::PerDrawSets);
    void submitDispatches();
    void waitIdle() { m_device->waitIdle(); }
    // `frames` of the submitted dispatch frames had their dispatches answered by a null driver
    // (null_driver.h): the counters did not move for them.
    void discountDispatchFrames(uint64_t frames) { m_dispatchFrames -= uint32_t(frames); }

    // Throw WrongResult unless the last frame's colour is in the target / every counter has
    // been incremented once per dispatch frame run so far.
    void checkDraws();
    void checkDispatches();
    // The driver's performance messages since the last call (validation on; none otherwise).
    std::vector<std::string> takePerformanceMessages();

private:
    void checkDebugMessages(const char* when);

    std::unique_ptr<rhi::IDevice> m_device;
    rhi::CommandListHandle m_commands;

    rhi::ShaderHandle m_vertexShader, m_fragmentShader, m_computeShader;
    rhi::TextureHandle m_target;
    rhi::BufferHandle m_vertices, m_drawParameters;
    rhi::PipelineHandle m_drawPipeline;
    std::vector<rhi::BindingSetHandle> m_drawBindings;
    // DrawSlices::DynamicOffsets: one set whose window moves per draw, and a pipeline reading it so.
    rhi::PipelineHandle m_dynamicDrawPipeline;
    rhi::BindingSetHandle m_dynamicDrawBinding;

    rhi::BufferHandle m_counters;
    rhi::PipelineHandle m_computePipeline;
    std::vector<rhi::BindingSetHandle> m_counterBindings;
    uint32_t m_dispatchFrames = 0;
};

// The scene of `backend`, created on first use and shared by every benchmark of that backend.
RhiScene& rhiScene(rhi::Backend backend);

}  // namespace janus::bench
