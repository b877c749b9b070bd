// The fixture every RHI conformance test uses, and the helpers the tests share.
//
// One test body runs on every backend configuration (Dawn/LLGL style):
//   TEST_P(TextureTest, RoundTrip) { ... device() ... }
//   JANUS_INSTANTIATE_BACKEND_TESTS(TextureTest);
// gives Backends/TextureTest.RoundTrip/vulkan, .../gl_egl, .../gl_osmesa and .../gles.
// See docs/TESTING.md for selecting backends (--gtest_filter, JANUS_TEST_BACKENDS).
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <ostream>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "janus/rhi/rhi.h"
#include "janus/shaders/shaders.h"

namespace janus::rhi::test {

struct BackendConfig {
    Backend backend;
    GLPlatform glPlatform;
    const char* name;   // the instance name: vulkan, gl_egl, gl_osmesa, gles
};

inline void PrintTo(const BackendConfig& config, std::ostream* os) { *os << config.name; }

const std::vector<BackendConfig>& allBackendConfigs();
std::string backendConfigName(const testing::TestParamInfo<BackendConfig>& info);

// True unless JANUS_TEST_BACKENDS is set and does not list this configuration.
bool backendSelected(const BackendConfig& config);

// A vertex of the "vertex colour" pipeline: clip-space position and a flat colour.
struct ColorVertex {
    float x, y, z, w;
    float r, g, b, a;
};

// A triangle with one colour, given in NDC (x, y) at depth z.
std::vector<ColorVertex> triangle(std::array<float, 6> xy, std::array<float, 4> color, float z = 0.0f);
// An axis-aligned rectangle in NDC from (x0, y0) to (x1, y1), as two triangles.
std::vector<ColorVertex> rectangle(float x0, float y0, float x1, float y1, std::array<float, 4> color, float z = 0.0f);

class BackendTest : public testing::TestWithParam<BackendConfig> {
protected:
    void SetUp() override;
    void TearDown() override;
    // Lets a suite adjust the DeviceDesc before SetUp creates the device.
    virtual void customizeDeviceDesc(DeviceDesc&) {}

    IDevice& device() { return *m_device; }
    const Capabilities& caps() const { return m_device->capabilities(); }
    Backend backend() const { return GetParam().backend; }
    bool isGLES() const { return backend() == Backend::GLES; }

    // Debug messages collected so far are dropped (for tests that provoke them on purpose).
    void discardDebugMessages() { m_device->takeDebugMessages(); }

    // --- resources ---------------------------------------------------------------------------
    // A shader from shaders/rhi-tests by its registered name; the stage comes from the suffix.
    ShaderHandle shader(std::string_view name);
    BufferHandle createBuffer(BufferUsage usage, uint64_t size);
    BufferHandle createBuffer(BufferUsage usage, std::span<const std::byte> contents);
    template <class T>
    BufferHandle createBufferFrom(BufferUsage usage, const std::vector<T>& contents) {
        return createBuffer(usage, std::as_bytes(std::span(contents)));
    }
    TextureHandle createTexture2D(Format format, uint32_t width, uint32_t height,
                                  TextureUsage usage = TextureUsage::Sampled, uint32_t mips = 1);
    SamplerHandle nearestClampSampler();

    // --- pipelines and drawing ---------------------------------------------------------------
    // The vertex colour pipeline (rt_vertex_color_*) with one colour attachment.
    PipelineHandle colorPipeline(Format colorFormat, Format depthFormat = Format::Unknown,
                                 RasterState raster = {}, DepthState depth = {},
                                 BlendAttachment blend = {}, PrimitiveTopology topology = PrimitiveTopology::TriangleList);
    // rt_instanced_vert + rt_vertex_color_frag into RGBA8: slot 0 per vertex (ColorVertex, the
    // position read), slot 1 per instance (a Color each, the instance's colour).
    PipelineHandle instancedPipeline();
    // rt_fullscreen_vert plus `fragmentShader` into one attachment of `colorFormat`, reading the
    // uniform buffers `dynamic` names with dynamic offsets.
    PipelineHandle fullscreenPipeline(std::string_view fragmentShader, Format colorFormat,
                                      const std::vector<DynamicUniformBuffer>& dynamic = {});
    // A compute pipeline of the embedded shader `name` (debug name the same), likewise.
    PipelineHandle computePipeline(const char* name, const std::vector<DynamicUniformBuffer>& dynamic = {}) {
        ComputePipelineDesc desc;
        desc.setShader(shader(name)).setDebugName(name).dynamicUniformBuffers = dynamic;
        return device().createComputePipeline(desc);
    }
    // A storage-buffer slice offset every backend accepts, at least `bytes` past the previous one.
    uint64_t storageSliceStride(uint64_t bytes) const {
        const uint64_t alignment = std::max<uint64_t>(caps().limits.storageBufferOffsetAlignment, 4);
        return (bytes + alignment - 1) / alignment * alignment;
    }
    // A binding set with `range` bytes of `buffer` from `offset` as storage buffer 0.
    BindingSetHandle storageSlice(const BufferHandle& buffer, uint64_t offset, uint64_t range) {
        return device().createBindingSet(BindingSetDesc().add(BindingItem::storageBuffer(0, buffer, offset, range)));
    }

    // Records `body` into a fresh command list and executes it.
    void submit(const std::function<void(ICommandList&)>& body);
    // One render pass into `color` (and `depth` when given) drawing `vertices` with `pipeline`.
    void drawVertices(const RenderPassDesc& pass, const PipelineHandle& pipeline,
                      const std::vector<ColorVertex>& vertices);
    // One render pass into `pass` drawing the fullscreen triangle with `bindings` at set 0.
    void drawFullscreen(const RenderPassDesc& pass, const PipelineHandle& pipeline,
                        std::vector<BindingSetHandle> sets = {});

    // --- readback ----------------------------------------------------------------------------
    template <class T>
    std::vector<T> readTextureAs(const TextureHandle& texture, TextureSubresource sub = {}) {
        return bytesAs<T>(device().readTexture(texture, sub));
    }
    template <class T>
    std::vector<T> readBufferAs(const BufferHandle& buffer, uint64_t offset = 0, uint64_t size = 0) {
        return bytesAs<T>(device().readBuffer(buffer, offset, size));
    }

public:
    template <class T>
    static std::vector<T> bytesAs(const std::vector<std::byte>& bytes) {
        static_assert(std::is_trivially_copyable_v<T>);
        std::vector<T> values(bytes.size() / sizeof(T));
        if (!values.empty()) std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
        return values;
    }

private:
    // Every message the device reports, also the ones that arrive while it is destroyed (after
    // the last takeDebugMessages()): TearDown checks those too.
    struct MessageSink {
        std::mutex mutex;
        std::vector<DebugMessage> messages;
    };
    std::shared_ptr<MessageSink> m_sink = std::make_shared<MessageSink>();
    std::unique_ptr<IDevice> m_device;
};

// --- pixels ----------------------------------------------------------------------------------

struct Rgba8 {
    uint8_t r = 0, g = 0, b = 0, a = 0;
    bool operator==(const Rgba8&) const = default;
};
void PrintTo(const Rgba8& c, std::ostream* os);
Rgba8 toRgba8(std::array<float, 4> c);   // unorm conversion, round to nearest

// Compares two images of `width` pixels per row element by element; on mismatch the message
// names the first differing pixel (x, y) and how many differ.
template <class T>
testing::AssertionResult imagesEqual(const std::vector<T>& actual, const std::vector<T>& expected,
                                     uint32_t width) {
    if (actual.size() != expected.size())
        return testing::AssertionFailure() << "size " << actual.size() << " != expected " << expected.size();
    size_t mismatches = 0, first = 0;
    for (size_t i = 0; i < actual.size(); ++i)
        if (!(actual[i] == expected[i]) && mismatches++ == 0) first = i;
    if (mismatches == 0) return testing::AssertionSuccess();
    return testing::AssertionFailure()
           << mismatches << " of " << actual.size() << " pixels differ; first at (x " << first % width
           << ", y " << first / width << "): got " << testing::PrintToString(actual[first])
           << ", expected " << testing::PrintToString(expected[first]);
}

using Color = std::array<float, 4>;

// Reads a colour subresource of any colour format as RGBA floats (missing channels: 0, alpha 1;
// sRGB values are returned encoded, as stored).
std::vector<Color> readColors(IDevice& device, const TextureHandle& texture, TextureSubresource sub = {});
// What storing `color` in `format` gives back through readColors (CPU reference conversion).
Color quantize(Format format, Color color);

// CPU reference rasteriser: paints `vertices` (a triangle list, one colour per triangle) over
// `background` in a width x height image, row 0 = NDC y -1, covering pixels whose centre lies
// inside. Tests choose vertices so no pixel centre lies on an edge (that would leave the result
// to the tie-breaking rule); such a centre is reported as a test failure.
std::vector<Color> rasterize(const std::vector<ColorVertex>& vertices, uint32_t width, uint32_t height,
                             Color background);

// The asymmetric orientation pattern for a square target: a red triangle in the top-left
// quadrant (right angle at the top-left corner), a green square at the top-right corner and a
// blue square at the bottom-left corner. Any flip or transpose moves something.
std::vector<ColorVertex> orientationPattern();

// IEEE half <-> float (glm's packing functions).
uint16_t toHalf(float value);
float fromHalf(uint16_t value);

// Throws unless `body` throws rhi::Error with `code` whose message contains every `mentions`.
testing::AssertionResult throwsRhiError(const std::function<void()>& body, ErrorCode code,
                                        std::vector<std::string> mentions = {});
// The same, where the interface allows any one of `codes`.
testing::AssertionResult throwsRhiError(const std::function<void()>& body, std::vector<ErrorCode> codes,
                                        std::vector<std::string> mentions = {});

}  // namespace janus::rhi::test

// GTEST_SKIPs the current test when the device lacks `cap`, naming the capability.
#define JANUS_REQUIRE_CAPABILITY(cap)                                                     \
    do {                                                                                  \
        if (!caps().has(cap))                                                             \
            GTEST_SKIP() << "the device lacks capability '" << ::janus::rhi::toString(cap) \
                         << "'";                                                          \
    } while (0)

#define JANUS_INSTANTIATE_BACKEND_TESTS(Fixture)                                          \
    INSTANTIATE_TEST_SUITE_P(Backends, Fixture,                                          \
                             ::testing::ValuesIn(::janus::rhi::test::allBackendConfigs()), \
                             ::janus::rhi::test::backendConfigName)
