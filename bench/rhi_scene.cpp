// The RHI side: the workload of bench_common.h recorded into a command list and executed.
#include "rhi_scene.h"

#include "gl_device.h"
#include "null_driver.h"
#include "vulkan_backend.h"

#include <fmt/format.h>
#include <janus/shaders/shaders.h>

#include <cstdlib>
#include <cstring>
#include <string_view>

namespace janus::bench {

using namespace janus::rhi;

bool validationRequested() {
    const char* value = std::getenv("JANUS_BENCH_VALIDATE");
    return value && std::string_view(value) != "0";
}

RhiScene::RhiScene(Backend backend) {
    m_device = createDevice(DeviceDesc().setBackend(backend).setEnableValidation(validationRequested()));
    IDevice& device = *m_device;
    m_commands = device.createCommandList();

    m_vertexShader = device.createShader(
        ShaderDesc().setStage(ShaderStage::Vertex).setSpirv(shaders::get("bench_triangle_vert")).setDebugName("bench triangle"));
    m_fragmentShader = device.createShader(ShaderDesc()
                                               .setStage(ShaderStage::Fragment)
                                               .setSpirv(shaders::get("bench_uniform_color_frag"))
                                               .setDebugName("bench uniform colour"));
    m_target = device.createTexture(TextureDesc()
                                        .setFormat(Format::RGBA8_UNORM)
                                        .setSize(kTargetSize, kTargetSize)
                                        .setUsage(TextureUsage::RenderTarget)
                                        .setDebugName("bench target"));
    m_vertices = device.createBuffer(
        BufferDesc().setSize(sizeof(kTriangle)).setUsage(BufferUsage::Vertex).setDebugName("bench triangle"));
    device.writeBuffer(m_vertices, kTriangle.data(), sizeof(kTriangle));
    m_drawParameters = device.createBuffer(
        BufferDesc().setSize(slicedBufferBytes()).setUsage(BufferUsage::Uniform).setDebugName("bench draw colours"));
    const std::vector<std::byte> parameters = drawParameterData();
    device.writeBuffer(m_drawParameters, parameters.data(), parameters.size());
    m_drawPipeline = device.createGraphicsPipeline(GraphicsPipelineDesc()
                                                       .setShaders(m_vertexShader, m_fragmentShader)
                                                       .addVertexBuffer({0, sizeof(float) * 2, false})
                                                       .addVertexAttribute({0, VertexFormat::Float2, 0, 0})
                                                       .addColorFormat(Format::RGBA8_UNORM)
                                                       .setDebugName("bench draw"));
    for (uint32_t i = 0; i < opsPerFrame(); ++i)
        m_drawBindings.push_back(device.createBindingSet(
            BindingSetDesc().add(BindingItem::uniformBuffer(0, m_drawParameters, i * kSliceBytes, kSliceBytes))));
    m_dynamicDrawPipeline = device.createGraphicsPipeline(GraphicsPipelineDesc()
                                                              .setShaders(m_vertexShader, m_fragmentShader)
                                                              .addVertexBuffer({0, sizeof(float) * 2, false})
                                                              .addVertexAttribute({0, VertexFormat::Float2, 0, 0})
                                                              .addColorFormat(Format::RGBA8_UNORM)
                                                              .addDynamicUniformBuffer(0, 0)
                                                              .setDebugName("bench draw, dynamic offsets"));
    m_dynamicDrawBinding = device.createBindingSet(
        BindingSetDesc().add(BindingItem::uniformBuffer(0, m_drawParameters, 0, kSliceBytes).setDynamicOffset()));

    if (device.capabilities().has(Capability::Compute) && device.capabilities().has(Capability::StorageBuffers)) {
        m_computeShader = device.createShader(ShaderDesc()
                                                  .setStage(ShaderStage::Compute)
                                                  .setSpirv(shaders::get("bench_increment_comp"))
                                                  .setDebugName("bench increment"));
        m_computePipeline = device.createComputePipeline(
            ComputePipelineDesc().setShader(m_computeShader).setDebugName("bench increment"));
        m_counters = device.createBuffer(
            BufferDesc().setSize(slicedBufferBytes()).setUsage(BufferUsage::Storage).setDebugName("bench counters"));
        const std::vector<std::byte> zeros(slicedBufferBytes());
        device.writeBuffer(m_counters, zeros.data(), zeros.size());
        for (uint32_t i = 0; i < opsPerFrame(); ++i)
            m_counterBindings.push_back(device.createBindingSet(
                BindingSetDesc().add(BindingItem::storageBuffer(0, m_counters, i * kSliceBytes, kSliceBytes))));
    }

    // One untimed frame of each kind: backends create descriptor sets, framebuffers and the like
    // on first use, and the results prove the work is really done before anything is timed.
    for (const DrawSlices slices : {DrawSlices::DynamicOffsets, DrawSlices::PerDrawSets}) {
        submitDraws(slices);
        waitIdle();
        checkDraws();
    }
    if (hasCompute()) {
        submitDispatches();
        waitIdle();
        checkDispatches();
    }
}

void RhiScene::submitDraws(DrawSlices slices) {
    ICommandList& commands = *m_commands;
    commands.begin();
    commands.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(m_target)));
    commands.setVertexBuffer(0, m_vertices);
    if (slices == DrawSlices::PerDrawSets) {
        commands.setPipeline(m_drawPipeline);
        for (const BindingSetHandle& bindings : m_drawBindings) {
            commands.setBindingSet(0, bindings);
            commands.draw(3);
        }
    } else {
        commands.setPipeline(m_dynamicDrawPipeline);
        for (uint32_t i = 0; i < opsPerFrame(); ++i) {
            const uint32_t offset = uint32_t(i * kSliceBytes);
            commands.setBindingSet(0, m_dynamicDrawBinding, std::span(&offset, 1));
            commands.draw(3);
        }
    }
    commands.endRenderPass();
    commands.end();
    m_device->execute(m_commands);
}

void RhiScene::submitDispatches() {
    ICommandList& commands = *m_commands;
    commands.begin();
    commands.setPipeline(m_computePipeline);
    for (const BindingSetHandle& bindings : m_counterBindings) {
        commands.setBindingSet(0, bindings);
        commands.dispatch(1);
    }
    commands.end();
    m_device->execute(m_commands);
    ++m_dispatchFrames;
}

void RhiScene::checkDraws() {
    const std::vector<std::byte> pixels = m_device->readTexture(m_target, {});
    if (pixels.size() < 4) throw WrongResult("readTexture returned no texel");
    requireLastDrawColor(pixels.data(), fmt::format("{} RHI", toString(m_device->info().backend)));
    checkDebugMessages("drawing");
}

void RhiScene::checkDispatches() {
    const std::vector<std::byte> bytes = m_device->readBuffer(m_counters);
    for (uint32_t i = 0; i < opsPerFrame(); ++i) {
        uint32_t value = 0;
        std::memcpy(&value, bytes.data() + i * kSliceBytes, sizeof(value));
        if (value != m_dispatchFrames)
            throw WrongResult(fmt::format("{} RHI: counter {} is {} after {} dispatch frames",
                                          toString(m_device->info().backend), i, value, m_dispatchFrames));
    }
    checkDebugMessages("dispatching");
}

std::vector<std::string> RhiScene::takePerformanceMessages() {
    std::vector<std::string> texts;
    for (const DebugMessage& message : m_device->takePerformanceMessages()) texts.push_back(message.text);
    return texts;
}

void RhiScene::checkDebugMessages(const char* when) {
    const std::vector<DebugMessage> messages = m_device->takeDebugMessages();
    if (!messages.empty())
        throw WrongResult(fmt::format("{} RHI: {} debug message(s) while {}, the first: {}",
                                      toString(m_device->info().backend), messages.size(), when, messages[0].text));
}

// ---------------------------------------------------------------------------------------------

namespace {

RhiScene& sceneFor(Backend backend) {
    switch (backend) {
        case Backend::Vulkan: return sharedEnvironment<RhiScene>(Backend::Vulkan);
        case Backend::GL: {
            struct GLScene : RhiScene {   // distinct type: one shared scene per backend
                GLScene() : RhiScene(Backend::GL) {}
            };
            return sharedEnvironment<GLScene>();
        }
        case Backend::GLES: {
            struct GLESScene : RhiScene {
                GLESScene() : RhiScene(Backend::GLES) {}
            };
            return sharedEnvironment<GLESScene>();
        }
    }
    throw std::logic_error("unknown backend");
}

}  // namespace

RhiScene& rhiScene(Backend backend) { return sceneFor(backend); }

namespace {
// JANUS_BENCH_TEST_PERFORMANCE_MESSAGE=1: each frame of the RHI side also inserts a performance
// message through the device, so that tests/bench/rhi_smoke.sh can check the counting end to end.
bool testPerformanceMessageRequested() {
    const char* value = std::getenv("JANUS_BENCH_TEST_PERFORMANCE_MESSAGE");
    return value && std::string_view(value) != "0";
}
}  // namespace

void rhiDraws(benchmark::State& state, Backend backend, DrawSlices slices) {
    runGuarded(state, [&] {
        RhiScene& scene = rhiScene(backend);
        const bool insert = testPerformanceMessageRequested();
        runFrames(
            state,
            [&] {
                scene.submitDraws(slices);
                if (insert) scene.device().insertPerformanceMessageForTesting("bench test message");
            },
            [&] { scene.waitIdle(); }, [&] { return scene.takePerformanceMessages(); });
        scene.checkDraws();
    });
}

void rhiDrawsWithNullDriver(benchmark::State& state, Backend backend, DrawSlices slices) {
    runGuarded(state, [&] {
        RhiScene& scene = rhiScene(backend);
        const std::string who = fmt::format("{} RHI", toString(backend));
        auto run = [&](const auto& driver) {
            runFrames(state, [&] { scene.submitDraws(slices); }, [&] { scene.waitIdle(); },
                      [&] { return scene.takePerformanceMessages(); });
            driver.requireFrames(uint64_t(state.iterations()), who);
        };
        if (backend == Backend::Vulkan) {
            rhi::vulkan::Context* vk = rhi::vulkan::contextOf(scene.device());
            if (!vk) throw std::runtime_error("the vulkan scene's device is not the Vulkan backend's");
            run(nullVulkanDriver(vk->cmdBindDescriptorSets, vk->cmdDraw, slices));
        } else {
            rhi::gl::GLFunctions& gl = dynamic_cast<rhi::gl::Device&>(scene.device()).context().gl;
            run(nullGLDriver(gl.glBindBufferRange, gl.glDrawArrays));
        }
        // The real driver again: nothing of the stubbed frames stayed behind in the device.
        scene.submitDraws(slices);
        scene.waitIdle();
        scene.checkDraws();
    });
}

void rhiDispatchesWithNullDriver(benchmark::State& state) {
    runGuarded(state, [&] {
        RhiScene& scene = rhiScene(Backend::Vulkan);
        rhi::vulkan::Context* vk = rhi::vulkan::contextOf(scene.device());
        if (!vk) throw std::runtime_error("the vulkan scene's device is not the Vulkan backend's");
        {
            const NullVulkanDispatchDriver driver = nullVulkanDispatchDriver(vk->cmdBindDescriptorSets, vk->cmdDispatch);
            runFrames(state, [&] { scene.submitDispatches(); }, [&] { scene.waitIdle(); },
                      [&] { return scene.takePerformanceMessages(); });
            scene.discountDispatchFrames(uint64_t(state.iterations()));
            driver.requireFrames(uint64_t(state.iterations()), "vulkan RHI");
        }
        // The real driver again: nothing of the stubbed frames stayed behind in the device.
        scene.submitDispatches();
        scene.waitIdle();
        scene.checkDispatches();
    });
}

FrameSide rhiSide(Backend backend, Work work) {
    RhiScene& scene = work == Work::Dispatches ? requireCompute(rhiScene(backend), backend) : rhiScene(backend);
    return frameSideOf(scene, work, [&scene] { scene.waitIdle(); });
}

void rhiDispatches(benchmark::State& state, Backend backend) {
    runGuarded(state, [&] {
        RhiScene& scene = requireCompute(rhiScene(backend), backend);
        runFrames(state, [&] { scene.submitDispatches(); }, [&] { scene.waitIdle(); },
                  [&] { return scene.takePerformanceMessages(); });
        scene.checkDispatches();
    });
}

}  // namespace janus::bench
