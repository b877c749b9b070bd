#include "backend_test.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include <fmt/format.h>
#include <glm/gtc/packing.hpp>

#include "janus/shaders/shaders.h"

namespace janus::rhi::test {

const std::vector<BackendConfig>& allBackendConfigs() {
    static const std::vector<BackendConfig> configs = {
        {Backend::Vulkan, GLPlatform::EGL, "vulkan"},
        {Backend::GL, GLPlatform::EGL, "gl_egl"},
        {Backend::GL, GLPlatform::OSMesa, "gl_osmesa"},
        {Backend::GLES, GLPlatform::EGL, "gles"},
    };
    return configs;
}

std::string backendConfigName(const testing::TestParamInfo<BackendConfig>& info) {
    return info.param.name;
}

bool backendSelected(const BackendConfig& config) {
    const char* list = std::getenv("JANUS_TEST_BACKENDS");
    if (!list || !*list) return true;
    // Entries are instance names (gl_egl) or backend names (gl selects gl_egl and gl_osmesa).
    std::stringstream entries(list);
    std::string entry;
    while (std::getline(entries, entry, ',')) {
        if (entry == config.name || entry == toString(config.backend)) return true;
    }
    return false;
}

void BackendTest::SetUp() {
    const BackendConfig& config = GetParam();
    if (!backendSelected(config))
        GTEST_SKIP() << config.name << " is not in JANUS_TEST_BACKENDS=" << std::getenv("JANUS_TEST_BACKENDS");
    DeviceDesc desc;
    desc.setBackend(config.backend).setGLPlatform(config.glPlatform).setEnableValidation(true);
    try {
        m_device = createDevice(desc);
    } catch (const std::exception& e) {
        // Every backend is expected to start where the suite runs; restrict the list with
        // JANUS_TEST_BACKENDS on machines that lack one.
        FAIL() << "backend " << config.name << " could not start: " << e.what()
               << " (set JANUS_TEST_BACKENDS to run only the backends this machine has)";
    }
    ASSERT_TRUE(m_device) << "createDevice returned no device for " << config.name;
}

void BackendTest::TearDown() {
    if (!m_device) return;
    // Any validation / debug message is a failure, including ones from resource destruction.
    std::vector<DebugMessage> messages = m_device->takeDebugMessages();
    m_device->waitIdle();
    for (DebugMessage& m : m_device->takeDebugMessages()) messages.push_back(std::move(m));
    for (const DebugMessage& m : messages)
        ADD_FAILURE() << (m.severity == MessageSeverity::Error ? "validation error: " : "validation warning: ")
                      << m.text;
    m_device.reset();
}

ShaderHandle BackendTest::shader(std::string_view name) {
    ShaderStage stage = ShaderStage::Vertex;
    if (name.ends_with("_frag")) stage = ShaderStage::Fragment;
    else if (name.ends_with("_comp")) stage = ShaderStage::Compute;
    ShaderDesc desc;
    desc.setStage(stage).setSpirv(janus::shaders::get(name)).setDebugName(std::string(name));
    return device().createShader(desc);
}

BufferHandle BackendTest::createBuffer(BufferUsage usage, uint64_t size) {
    return device().createBuffer(BufferDesc().setSize(size).setUsage(usage));
}

BufferHandle BackendTest::createBuffer(BufferUsage usage, std::span<const std::byte> contents) {
    BufferHandle buffer = createBuffer(usage, contents.size());
    device().writeBuffer(buffer, contents.data(), contents.size());
    return buffer;
}

TextureHandle BackendTest::createTexture2D(Format format, uint32_t width, uint32_t height,
                                           TextureUsage usage, uint32_t mips) {
    return device().createTexture(
        TextureDesc().setFormat(format).setSize(width, height).setUsage(usage).setMipLevels(mips));
}

SamplerHandle BackendTest::nearestClampSampler() {
    return device().createSampler(SamplerDesc().setFilter(Filter::Nearest).setAddress(AddressMode::ClampToEdge));
}

PipelineHandle BackendTest::colorPipeline(Format colorFormat, Format depthFormat, RasterState raster,
                                          DepthState depth, BlendAttachment blend) {
    GraphicsPipelineDesc desc;
    desc.setShaders(shader("rt_vertex_color_vert"), shader("rt_vertex_color_frag"))
        .addVertexBuffer({0, sizeof(ColorVertex), false})
        .addVertexAttribute({0, VertexFormat::Float4, 0, offsetof(ColorVertex, x)})
        .addVertexAttribute({1, VertexFormat::Float4, 0, offsetof(ColorVertex, r)})
        .setRaster(raster)
        .setDepth(depth)
        .setDepthFormat(depthFormat)
        .setDebugName("vertex colour");
    if (colorFormat != Format::Unknown) desc.addColorFormat(colorFormat, blend);
    return device().createGraphicsPipeline(desc);
}

PipelineHandle BackendTest::fullscreenPipeline(std::string_view fragmentShader, Format colorFormat) {
    GraphicsPipelineDesc desc;
    desc.setShaders(shader("rt_fullscreen_vert"), shader(fragmentShader))
        .addColorFormat(colorFormat)
        .setDebugName(std::string(fragmentShader));
    return device().createGraphicsPipeline(desc);
}

void BackendTest::submit(const std::function<void(ICommandList&)>& body) {
    CommandListHandle commands = device().createCommandList();
    commands->begin();
    body(*commands);
    commands->end();
    device().execute(commands);
}

void BackendTest::drawVertices(const RenderPassDesc& pass, const PipelineHandle& pipeline,
                               const std::vector<ColorVertex>& vertices) {
    BufferHandle vertexBuffer = createBufferFrom(BufferUsage::Vertex, vertices);
    submit([&](ICommandList& cmd) {
        cmd.beginRenderPass(pass);
        cmd.setPipeline(pipeline);
        cmd.setVertexBuffer(0, vertexBuffer);
        cmd.draw(uint32_t(vertices.size()));
        cmd.endRenderPass();
    });
}

void BackendTest::drawFullscreen(const RenderPassDesc& pass, const PipelineHandle& pipeline,
                                 std::vector<BindingSetHandle> sets) {
    submit([&](ICommandList& cmd) {
        cmd.beginRenderPass(pass);
        cmd.setPipeline(pipeline);
        for (uint32_t s = 0; s < sets.size(); ++s)
            if (sets[s]) cmd.setBindingSet(s, sets[s]);
        cmd.draw(3);
        cmd.endRenderPass();
    });
}

std::vector<ColorVertex> triangle(std::array<float, 6> xy, std::array<float, 4> c, float z) {
    std::vector<ColorVertex> v;
    for (int i = 0; i < 3; ++i) v.push_back({xy[2 * i], xy[2 * i + 1], z, 1.0f, c[0], c[1], c[2], c[3]});
    return v;
}

std::vector<ColorVertex> rectangle(float x0, float y0, float x1, float y1, std::array<float, 4> c, float z) {
    std::vector<ColorVertex> v = triangle({x0, y0, x0, y1, x1, y0}, c, z);
    std::vector<ColorVertex> second = triangle({x1, y0, x0, y1, x1, y1}, c, z);
    v.insert(v.end(), second.begin(), second.end());
    return v;
}

void PrintTo(const Rgba8& c, std::ostream* os) {
    *os << fmt::format("rgba8({}, {}, {}, {})", c.r, c.g, c.b, c.a);
}

Rgba8 toRgba8(std::array<float, 4> c) {
    auto unorm = [](float v) { return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    return {unorm(c[0]), unorm(c[1]), unorm(c[2]), unorm(c[3])};
}

uint16_t toHalf(float value) { return glm::packHalf1x16(value); }
float fromHalf(uint16_t value) { return glm::unpackHalf1x16(value); }

testing::AssertionResult throwsRhiError(const std::function<void()>& body, ErrorCode code,
                                        std::vector<std::string> mentions) {
    try {
        body();
    } catch (const Error& e) {
        if (e.code() != code)
            return testing::AssertionFailure() << "threw " << toString(e.code()) << " instead of "
                                               << toString(code) << ": " << e.what();
        std::string message = e.what();
        for (const std::string& word : mentions)
            if (message.find(word) == std::string::npos)
                return testing::AssertionFailure() << "the message does not mention '" << word << "': " << message;
        return testing::AssertionSuccess() << e.what();
    } catch (const std::exception& e) {
        return testing::AssertionFailure() << "threw a non-rhi::Error exception: " << e.what();
    }
    return testing::AssertionFailure() << "did not throw (expected rhi::Error " << toString(code) << ")";
}

}  // namespace janus::rhi::test
