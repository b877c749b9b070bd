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
    desc.setBackend(config.backend).setGLPlatform(config.glPlatform).setEnableValidation(true).setEnableSynchronizationValidation(true);
    customizeDeviceDesc(desc);
    // Keep the suite's own callback (if a test set one) and also record every message.
    desc.messageCallback = [sink = m_sink, user = desc.messageCallback](const DebugMessage& message) {
        {
            std::lock_guard lock(sink->mutex);
            sink->messages.push_back(message);
        }
        if (user) user(message);
    };
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
    // Then destroy the device and fail on whatever it reported while going (e.g. Vulkan's
    // "objects not destroyed" at vkDestroyDevice), which no takeDebugMessages() can see.
    {
        std::lock_guard lock(m_sink->mutex);
        m_sink->messages.clear();
    }
    m_device.reset();
    std::lock_guard lock(m_sink->mutex);
    for (const DebugMessage& m : m_sink->messages)
        if (m.severity != MessageSeverity::Performance) ADD_FAILURE() << "message while the device was destroyed: " << m.text;
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
                                          DepthState depth, BlendAttachment blend, PrimitiveTopology topology) {
    GraphicsPipelineDesc desc;
    desc.setShaders(shader("rt_vertex_color_vert"), shader("rt_vertex_color_frag"))
        .setTopology(topology)
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

PipelineHandle BackendTest::instancedPipeline() {
    GraphicsPipelineDesc desc;
    desc.setShaders(shader("rt_instanced_vert"), shader("rt_vertex_color_frag"))
        .addVertexBuffer({0, sizeof(ColorVertex), false})
        .addVertexBuffer({1, sizeof(Color), true})
        .addVertexAttribute({0, VertexFormat::Float4, 0, 0})
        .addVertexAttribute({1, VertexFormat::Float4, 1, 0})
        .addColorFormat(Format::RGBA8_UNORM);
    return device().createGraphicsPipeline(desc);
}

PipelineHandle BackendTest::fullscreenPipeline(std::string_view fragmentShader, Format colorFormat,
                                               const std::vector<DynamicUniformBuffer>& dynamic) {
    GraphicsPipelineDesc desc;
    desc.setShaders(shader("rt_fullscreen_vert"), shader(fragmentShader))
        .addColorFormat(colorFormat)
        .setDebugName(std::string(fragmentShader))
        .dynamicUniformBuffers = dynamic;
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

std::vector<Color> readColors(IDevice& device, const TextureHandle& texture, TextureSubresource sub) {
    const Format format = texture->desc().format;
    std::vector<std::byte> bytes = device.readTexture(texture, sub);
    const uint32_t bpp = formatInfo(format).bytesPerPixel;
    std::vector<Color> colors(bytes.size() / bpp, Color{0, 0, 0, 1});
    for (size_t i = 0; i < colors.size(); ++i) {
        const std::byte* texel = bytes.data() + i * bpp;
        Color& c = colors[i];
        switch (format) {
            case Format::RGBA8_UNORM:
            case Format::RGBA8_SRGB:
                for (int k = 0; k < 4; ++k) c[k] = float(uint8_t(texel[k])) / 255.0f;
                break;
            case Format::RGBA16_FLOAT:
                for (int k = 0; k < 4; ++k) {
                    uint16_t h;
                    std::memcpy(&h, texel + 2 * k, 2);
                    c[k] = fromHalf(h);
                }
                break;
            case Format::RGBA32_FLOAT: std::memcpy(c.data(), texel, 16); break;
            case Format::R32_FLOAT: std::memcpy(c.data(), texel, 4); break;
            case Format::R11G11B10_FLOAT: {
                uint32_t packed;
                std::memcpy(&packed, texel, 4);
                glm::vec3 v = glm::unpackF2x11_1x10(packed);
                c = {v.x, v.y, v.z, 1.0f};
                break;
            }
            default:
                ADD_FAILURE() << "readColors: " << toString(format) << " is not a colour format with float channels";
                return {};
        }
    }
    return colors;
}

Color quantize(Format format, Color c) {
    switch (format) {
        case Format::RGBA8_UNORM:
        case Format::RGBA8_SRGB: {
            Rgba8 q = toRgba8(c);
            return {q.r / 255.0f, q.g / 255.0f, q.b / 255.0f, q.a / 255.0f};
        }
        case Format::RGBA16_FLOAT: return {fromHalf(toHalf(c[0])), fromHalf(toHalf(c[1])), fromHalf(toHalf(c[2])), fromHalf(toHalf(c[3]))};
        case Format::R32_FLOAT: return {c[0], 0, 0, 1};
        case Format::R11G11B10_FLOAT: {
            glm::vec3 v = glm::unpackF2x11_1x10(glm::packF2x11_1x10(glm::vec3(c[0], c[1], c[2])));
            return {v.x, v.y, v.z, 1.0f};
        }
        default: return c;
    }
}

std::vector<Color> rasterize(const std::vector<ColorVertex>& vertices, uint32_t width, uint32_t height, Color background) {
    enum Coverage : uint8_t { Outside, Inside, OnEdge };
    const size_t triangles = vertices.size() / 3, pixels = size_t(width) * height;
    std::vector<Coverage> coverage(triangles * pixels, Outside);
    for (size_t t = 0; t < triangles; ++t) {
        // Pixel-space corners; row 0 is NDC y = -1.
        std::array<std::array<double, 2>, 3> p;
        for (int k = 0; k < 3; ++k)
            p[k] = {(vertices[3 * t + k].x + 1.0) * 0.5 * width, (vertices[3 * t + k].y + 1.0) * 0.5 * height};
        auto edge = [&](int a, int b, double x, double y) {
            return (p[b][0] - p[a][0]) * (y - p[a][1]) - (p[b][1] - p[a][1]) * (x - p[a][0]);
        };
        for (size_t i = 0; i < pixels; ++i) {
            double cx = double(i % width) + 0.5, cy = double(i / width) + 0.5;
            std::array<double, 3> e = {edge(0, 1, cx, cy), edge(1, 2, cx, cy), edge(2, 0, cx, cy)};
            bool allNonNegative = e[0] >= 0 && e[1] >= 0 && e[2] >= 0;
            bool allNonPositive = e[0] <= 0 && e[1] <= 0 && e[2] <= 0;
            if (!allNonNegative && !allNonPositive) continue;
            coverage[t * pixels + i] = (e[0] == 0 || e[1] == 0 || e[2] == 0) ? OnEdge : Inside;
        }
    }
    auto colorOf = [&](size_t t) { const ColorVertex& v = vertices[3 * t]; return Color{v.r, v.g, v.b, v.a}; };
    std::vector<Color> image(pixels, background);
    for (size_t i = 0; i < pixels; ++i)
        for (size_t t = 0; t < triangles; ++t) {
            if (coverage[t * pixels + i] == Outside) continue;
            image[i] = colorOf(t);
            if (coverage[t * pixels + i] != OnEdge) continue;
            // A centre on an edge shared with a same-coloured triangle (a rectangle's diagonal)
            // is covered whatever the tie-breaking rule; on any other edge the test is at fault.
            bool shared = false;
            for (size_t u = 0; u < triangles; ++u)
                shared |= u != t && coverage[u * pixels + i] != Outside && colorOf(u) == colorOf(t);
            if (!shared)
                ADD_FAILURE() << "test bug: pixel centre (" << i % width << ".5, " << i / width
                              << ".5) lies on an edge of triangle " << t << "; move the triangle";
        }
    return image;
}

std::vector<ColorVertex> orientationPattern() {
    // Edges lie on pixel boundaries or, for the hypotenuse (slope 3/4), avoid pixel centres for
    // target sizes that are multiples of 2.
    std::vector<ColorVertex> v = triangle({-1, -1, 0, -1, -1, -0.25f}, {1, 0, 0, 1});
    for (const auto& r : {rectangle(0.5f, -1, 1, -0.5f, {0, 1, 0, 1}), rectangle(-1, 0.5f, -0.5f, 1, {0, 0, 1, 1})})
        v.insert(v.end(), r.begin(), r.end());
    return v;
}

uint16_t toHalf(float value) { return glm::packHalf1x16(value); }
float fromHalf(uint16_t value) { return glm::unpackHalf1x16(value); }

testing::AssertionResult throwsRhiError(const std::function<void()>& body, ErrorCode code,
                                        std::vector<std::string> mentions) {
    return throwsRhiError(body, std::vector<ErrorCode>{code}, std::move(mentions));
}

testing::AssertionResult throwsRhiError(const std::function<void()>& body, std::vector<ErrorCode> codes,
                                        std::vector<std::string> mentions) {
    std::string expected;
    for (ErrorCode c : codes) expected += (expected.empty() ? "" : " or ") + std::string(toString(c));
    try {
        body();
    } catch (const Error& e) {
        if (std::find(codes.begin(), codes.end(), e.code()) == codes.end())
            return testing::AssertionFailure() << "threw " << toString(e.code()) << " instead of "
                                               << expected << ": " << e.what();
        std::string message = e.what();
        for (const std::string& word : mentions)
            if (message.find(word) == std::string::npos)
                return testing::AssertionFailure() << "the message does not mention '" << word << "': " << message;
        return testing::AssertionSuccess() << e.what();
    } catch (const std::exception& e) {
        return testing::AssertionFailure() << "threw a non-rhi::Error exception: " << e.what();
    }
    return testing::AssertionFailure() << "did not throw (expected rhi::Error " << expected << ")";
}

}  // namespace janus::rhi::test
