// Small helpers every feature module uses (internal to the renderer).
#pragma once

#include <chrono>
#include <cstdint>
#include <cstring>
#include <vector>

#include <fmt/format.h>

#include "janus/renderer/frame_report.h"
#include "janus/renderer/settings.h"
#include "janus/rhi/rhi.h"
#include "janus/shaders/shaders.h"

namespace janus::renderer {

inline uint64_t alignUp(uint64_t value, uint64_t alignment) { return alignment ? (value + alignment - 1) / alignment * alignment : value; }

// A shader from the embedded SPIR-V registry (shaders/) by its registered name.
inline rhi::ShaderHandle makeShader(rhi::IDevice& device, rhi::ShaderStage stage, const char* name) {
    return device.createShader(rhi::ShaderDesc{}.setStage(stage).setSpirv(shaders::get(name)).setDebugName(name));
}

// A uniform buffer holding `value` (written once, immediately).
template <class T>
rhi::BufferHandle makeUniformBuffer(rhi::IDevice& device, const T& value, const char* name) {
    rhi::BufferHandle buffer =
        device.createBuffer(rhi::BufferDesc{}.setSize(sizeof(T)).setUsage(rhi::BufferUsage::Uniform).setDebugName(name));
    device.writeBuffer(buffer, &value, sizeof(T));
    return buffer;
}

inline double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// A render pass `pass` that draws one fullscreen triangle (fullscreen.vert) with `pipeline` and
// `bindings` at set 0.
inline void drawFullscreenTriangle(rhi::ICommandList& cmd, const rhi::RenderPassDesc& pass, const rhi::PipelineHandle& pipeline,
                                   const rhi::BindingSetHandle& bindings, PassReport& report) {
    cmd.beginRenderPass(pass);
    cmd.setPipeline(pipeline);
    cmd.setBindingSet(0, bindings);
    cmd.draw(3);
    ++report.draws;
    cmd.endRenderPass();
}
// The same into one colour target.
inline void drawFullscreenTriangle(rhi::ICommandList& cmd, const rhi::Attachment& target, const rhi::PipelineHandle& pipeline,
                                   const rhi::BindingSetHandle& bindings, PassReport& report) {
    drawFullscreenTriangle(cmd, rhi::RenderPassDesc{}.addColor(target), pipeline, bindings, report);
}

// Reads back a D32F texture's mip 0 (row 0 on top). Waits for the GPU.
inline std::vector<float> readDepth32F(rhi::IDevice& device, const rhi::TextureHandle& texture) {
    const rhi::TextureDesc& desc = texture->desc();
    const std::vector<std::byte> bytes = device.readTexture(texture, {});
    const size_t pixels = size_t(desc.width) * desc.height;
    if (bytes.size() != pixels * 4)
        throw RendererError(fmt::format("depth readback returned {} bytes, expected {} for {}x{} D32F", bytes.size(), pixels * 4,
                                        desc.width, desc.height));
    std::vector<float> depth(pixels);
    std::memcpy(depth.data(), bytes.data(), bytes.size());
    return depth;
}

}  // namespace janus::renderer
