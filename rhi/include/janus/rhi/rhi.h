// Janus RHI: the backend-neutral rendering interface.
//
// One section per resource kind (NVRHI style): a plain `XxxDesc` with defaults and chainable
// setters, an interface `IXxx`, and a ref-counted handle `XxxHandle`. No Vulkan or GL type is
// visible from here; backends live in rhi-vulkan/ and rhi-gl/ and are chosen at run time with
// createDevice().
//
// Conventions (see docs/ARCHITECTURE.md, "Conventions"). Every backend presents the same ones:
//  * Clip space is Vulkan's: NDC depth in [0, 1]; NDC y = -1 maps to row 0 of the render target.
//  * Row 0 of every texture and of every readback is the row at texture coordinate v = 0, which
//    images show at the top. No backend flips rows on upload, render or readback.
//  * FrontFace::CounterClockwise means counter-clockwise as seen in the image (row 0 on top).
//  * Cube faces are ordered +X, -X, +Y, -Y, +Z, -Z (layer 0..5), oriented as in the Vulkan/GL spec.
//    Cube arrays number their 2D layers "layer-faces": layer = 6 * cube + face.
//  * Binding model: shaders declare `layout(set = S, binding = B)`; binding numbers are unique
//    across all sets of one pipeline (so GL can use B as its binding point / texture unit / image
//    unit directly). Sampled textures are combined image samplers (`sampler2D`...).
//  * Work is ordered: the backend inserts the barriers needed between render passes, dispatches
//    and copies (conservative full barriers; correctness first).
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "janus/rhi/format.h"

namespace janus::rhi {

// ---------------------------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------------------------

enum class ErrorCode {
    BackendUnavailable,     // the backend (driver, platform layer, context) could not start
    UnsupportedCapability,  // the device lacks a Capability or a format capability the call needs
    InvalidDescription,     // a Desc has absurd or contradictory values; the message names the field
    InvalidUsage,           // a call in the wrong state or with bad arguments (draw outside a render pass, a range outside a buffer, ...)
    ShaderTranslation,      // SPIR-V could not be turned into code for this backend
    ShaderCompilation,      // the driver rejected a shader or program
    OutOfMemory,
    DeviceLost,
};
const char* toString(ErrorCode code);

// Every RHI failure throws this. what() says what went wrong and what to change.
class Error : public std::runtime_error {
public:
    Error(ErrorCode code, const std::string& message);
    ErrorCode code() const { return m_code; }

private:
    ErrorCode m_code;
};

// ---------------------------------------------------------------------------------------------
// Device creation and capabilities
// ---------------------------------------------------------------------------------------------

enum class Backend { Vulkan, GL, GLES };
const char* toString(Backend backend);            // "vulkan", "gl", "gles"
std::optional<Backend> parseBackend(std::string_view name);

// How the GL backends get a context. Vulkan ignores it. EGL picks its display itself (surfaceless,
// then an EGL device, then the default display; JANUS_EGL_PLATFORM / JANUS_EGL_DEVICE force one).
// OSMesa is loaded at run time: without it installed, OSMesa is BackendUnavailable.
enum class GLPlatform { EGL, OSMesa };
const char* toString(GLPlatform platform);        // "egl", "osmesa"
std::optional<GLPlatform> parseGLPlatform(std::string_view name);

// Error: the API was misused or behaviour is undefined (validation errors, GL errors). Warning:
// validation warnings and other driver complaints about what we do. Performance: the driver says
// something is slow (GL_DEBUG_TYPE_PERFORMANCE, Vulkan performance messages) - counted and shown,
// never a failure by itself (IDevice::takePerformanceMessages).
enum class MessageSeverity { Info, Performance, Warning, Error };

struct DebugMessage {
    MessageSeverity severity = MessageSeverity::Info;
    std::string text;
};

struct DeviceDesc {
    Backend backend = Backend::Vulkan;
    GLPlatform glPlatform = GLPlatform::EGL;
    // Vulkan validation layers / GL debug output. Warnings and errors are collected and can be
    // drained with IDevice::takeDebugMessages(); tests fail on any.
    bool enableValidation = false;
    // Vulkan: also the layer's synchronisation validation (hazards between commands that no
    // barrier orders: a missing or too narrow barrier). Slower; needs enableValidation. The GL
    // backends have no such tool and ignore it.
    bool enableSynchronizationValidation = false;
    // Called for every collected message as it arrives (optional). It runs inside the driver, so
    // it must not throw: an exception is caught there and printed on stderr, and the message is
    // still collected.
    std::function<void(const DebugMessage&)> messageCallback;

    DeviceDesc& setBackend(Backend v) { backend = v; return *this; }
    DeviceDesc& setGLPlatform(GLPlatform v) { glPlatform = v; return *this; }
    DeviceDesc& setEnableValidation(bool v) { enableValidation = v; return *this; }
    DeviceDesc& setEnableSynchronizationValidation(bool v) { enableSynchronizationValidation = v; return *this; }
};

enum class Capability {
    Compute,                 // compute pipelines and dispatch
    StorageBuffers,          // SSBOs (std430)
    StorageImages,           // image load/store
    RenderToVolumeSlice,     // a slice of a 3D texture as a colour attachment
    RenderToCubeFaceMip,     // any face and mip level of a cube map as an attachment
    FloatRenderTargets,      // RGBA16F / RGBA32F / R11G11B10F / R32F colour attachments
    FloatBlend,              // blending into 32-bit float attachments
    TimestampQueries,        // GPU timers
    IndependentBlend,        // a different blend state / write mask per colour attachment
    CubeArrays,              // TextureDimension::TextureCubeArray (samplerCubeArray / imageCubeArray)
    TextureViews,            // binding views with a layer/face subrange or another dimension than the
                             // texture's (one cube face as 2D, ...); mip ranges need no capability
    ConcurrentDeviceCalls,   // device calls from several threads at once (Vulkan); without it one
                             // thread at a time (GL: see IDevice::detachFromThread)
};
const char* toString(Capability cap);
inline constexpr std::array kAllCapabilities = {
    Capability::Compute,           Capability::StorageBuffers,     Capability::StorageImages,
    Capability::RenderToVolumeSlice, Capability::RenderToCubeFaceMip, Capability::FloatRenderTargets,
    Capability::FloatBlend,        Capability::TimestampQueries,   Capability::IndependentBlend,
    Capability::CubeArrays,        Capability::TextureViews,       Capability::ConcurrentDeviceCalls,
};

struct Limits {
    uint32_t maxTextureSize2D = 0;
    uint32_t maxTextureSize3D = 0;
    uint32_t maxTextureSizeCube = 0;
    uint32_t maxTextureArrayLayers = 0;   // TextureDesc::arrayLayers (layer-faces for cube arrays)
    uint32_t maxColorAttachments = 0;
    uint64_t maxUniformBufferRange = 0;
    uint64_t maxStorageBufferRange = 0;   // 0 without StorageBuffers
    std::array<uint32_t, 3> maxComputeWorkGroupCount{};
    std::array<uint32_t, 3> maxComputeWorkGroupSize{};
    uint32_t maxComputeWorkGroupInvocations = 0;
    uint32_t uniformBufferOffsetAlignment = 256;
    uint32_t storageBufferOffsetAlignment = 256;
    uint64_t maxBufferSize = 0;              // bytes of one buffer
    uint32_t maxVertexBuffers = 0;           // vertex buffer slots are 0 .. maxVertexBuffers - 1
    uint32_t maxVertexAttributes = 0;        // attribute locations are 0 .. maxVertexAttributes - 1
    uint32_t maxVertexStride = 0;            // VertexBufferLayout::stride
    uint32_t maxViewportSize = 0;            // Viewport::width / height
    // Where a viewport may lie: x, y >= [0] and x + width, y + height <= [1] (Vulkan's
    // viewportBoundsRange, GL's GL_VIEWPORT_BOUNDS_RANGE).
    std::array<float, 2> viewportBoundsRange{0.0f, 0.0f};
    float maxSamplerAnisotropy = 1.0f;       // 1 without anisotropic filtering
};

// What the native API does, and what the RHI presents (always Vulkan's, see the top of this
// file). Reported so users and tests can see the translation instead of assuming it.
struct Conventions {
    bool nativeClipDepthZeroToOne = true;    // false on GL/GLES: emulated in generated shaders
    bool nativeFramebufferOriginTopLeft = true;  // false on GL: rows are addressed bottom-up
};

struct DeviceInfo {
    Backend backend = Backend::Vulkan;
    std::string apiVersion;      // "Vulkan 1.3.230", "OpenGL 4.5 (Core Profile) Mesa 22.3.6"
    std::string deviceName;      // "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::string driverInfo;      // driver name / version string
    std::string platform;        // "headless" for Vulkan; GL: "osmesa", or "egl (<display>)" naming the
                                 // EGL display: "egl (surfaceless)", "egl (device 0: /dev/dri/card0)",
                                 // "egl (default display)" (docs/ARCHITECTURE.md, "GL context platforms")
    std::string shadingLanguage; // "SPIR-V 1.5", "GLSL 430", "ESSL 300"
    std::string driverSettings;  // driver settings that change results, and who chose them; empty
                                 // where none apply. NVIDIA GL: its texture filtering "image
                                 // settings" (docs/ARCHITECTURE.md, "Driver settings")
};

struct Capabilities {
    bool compute = false;
    bool storageBuffers = false;
    bool storageImages = false;
    bool renderToVolumeSlice = false;
    bool renderToCubeFaceMip = false;
    bool floatRenderTargets = false;
    bool floatBlend = false;
    bool timestampQueries = false;
    bool independentBlend = false;
    bool cubeArrays = false;
    bool textureViews = false;
    bool concurrentDeviceCalls = false;
    Limits limits;
    Conventions conventions;

    bool has(Capability cap) const;
};

// ---------------------------------------------------------------------------------------------
// Buffers
// ---------------------------------------------------------------------------------------------
// New resources read as zero until written (every backend guarantees it).

enum class BufferUsage : uint32_t {
    None = 0,
    Vertex = 1u << 0,
    Index = 1u << 1,
    Uniform = 1u << 2,
    Storage = 1u << 3,   // needs Capability::StorageBuffers
};
constexpr BufferUsage operator|(BufferUsage a, BufferUsage b) { return BufferUsage(uint32_t(a) | uint32_t(b)); }
constexpr bool any(BufferUsage a, BufferUsage b) { return (uint32_t(a) & uint32_t(b)) != 0; }

struct BufferDesc {
    uint64_t size = 0;                        // bytes, > 0
    BufferUsage usage = BufferUsage::None;    // buffers can always be copied to/from and read back
    std::string debugName;

    BufferDesc& setSize(uint64_t v) { size = v; return *this; }
    BufferDesc& setUsage(BufferUsage v) { usage = v; return *this; }
    BufferDesc& setDebugName(std::string v) { debugName = std::move(v); return *this; }
};

namespace detail {
class HostIndexContents;
class IndexValueLog;
struct FrontAccess;
struct BackendAccess;
// A backend's bookkeeping on an object a command list can hold: the recording that last held it
// and where that list holds it (rhi/backend-api/janus/rhi/keep_alive.h says how it is used).
struct KeepMark {
    std::atomic<uint64_t> recording{0};
    std::atomic<uint32_t> slot{0};
    // Not bookkeeping: a binding set's count of dynamic offsets (BindingItem::dynamicOffset), which
    // every setBindingSet checks. Here because that bind reads this line anyway and the field was
    // padding: IBindingSet does not grow (a GL set fits what a draw reads of it in one line).
    uint32_t dynamicOffsetCount = 0;
};
}  // namespace detail

class IBuffer {
public:
    virtual ~IBuffer() = default;
    virtual const BufferDesc& desc() const = 0;

private:
    friend class IDevice;
    friend struct detail::FrontAccess;
    // With validation on, the host's copy of an index buffer's contents (index_value_validation.h).
    std::shared_ptr<detail::HostIndexContents> m_hostIndexContents;
};
using BufferHandle = std::shared_ptr<IBuffer>;

// ---------------------------------------------------------------------------------------------
// Textures and samplers
// ---------------------------------------------------------------------------------------------
// New resources read as zero until written (every backend guarantees it).

// Layers: a cube has 6 (its faces); a 2D array has TextureDesc::arrayLayers; a cube array has
// arrayLayers = 6 x cubes "layer-faces", layer = 6 * cube + face (NVRHI's arraySize, Vulkan's
// arrayLayers, GL's layer-face). TextureCubeArray needs Capability::CubeArrays.
enum class TextureDimension { Texture2D, Texture3D, TextureCube, Texture2DArray, TextureCubeArray };
const char* toString(TextureDimension dim);

enum class TextureUsage : uint32_t {
    None = 0,
    Sampled = 1u << 0,
    RenderTarget = 1u << 1,   // colour or depth attachment (by format)
    Storage = 1u << 2,        // image load/store; needs Capability::StorageImages
    // Each usage also needs the format capability of the same name (IDevice::formatCapabilities).
};
constexpr TextureUsage operator|(TextureUsage a, TextureUsage b) { return TextureUsage(uint32_t(a) | uint32_t(b)); }
constexpr bool any(TextureUsage a, TextureUsage b) { return (uint32_t(a) & uint32_t(b)) != 0; }

struct TextureDesc {
    TextureDimension dimension = TextureDimension::Texture2D;
    Format format = Format::RGBA8_UNORM;
    uint32_t width = 1;
    uint32_t height = 1;          // cube maps: width == height
    uint32_t depth = 1;           // 3D textures only
    // Texture2DArray: layers (>= 1); TextureCubeArray: 6 x cubes (a multiple of 6); 1 otherwise
    // (a cube's 6 faces are implied). At most Limits::maxTextureArrayLayers.
    uint32_t arrayLayers = 1;
    uint32_t mipLevels = 1;       // 0 = full chain
    TextureUsage usage = TextureUsage::Sampled;   // copies and readback are always allowed
    // Multisampling (MSAA): 1, or a count in FormatCapabilities::sampleCounts (2, 4, 8, ...). A
    // multisampled texture is a Texture2D render target only (usage RenderTarget, one mip, one
    // layer): it is rendered to and resolved (Attachment::resolveTo) into a single-sampled
    // texture, which is what shaders sample, copies copy and readTexture reads.
    uint32_t sampleCount = 1;
    std::string debugName;

    TextureDesc& setDimension(TextureDimension v) { dimension = v; return *this; }
    TextureDesc& setFormat(Format v) { format = v; return *this; }
    TextureDesc& setSize(uint32_t w, uint32_t h, uint32_t d = 1) { width = w; height = h; depth = d; return *this; }
    TextureDesc& setArrayLayers(uint32_t v) { arrayLayers = v; return *this; }
    TextureDesc& setMipLevels(uint32_t v) { mipLevels = v; return *this; }
    TextureDesc& setUsage(TextureUsage v) { usage = v; return *this; }
    TextureDesc& setSampleCount(uint32_t v) { sampleCount = v; return *this; }
    TextureDesc& setDebugName(std::string v) { debugName = std::move(v); return *this; }
};

// The number of 2D layers of a non-3D texture (1, 6, arrayLayers); 3D: its depth at mip 0.
uint32_t textureLayerCount(const TextureDesc& desc);

// One 2D image of a texture: mip level plus cube face (0..5), array layer, cube-array
// layer-face (6 * cube + face) or 3D slice (at that mip's depth).
struct TextureSubresource {
    uint32_t mipLevel = 0;
    uint32_t layer = 0;
};

class ITexture {
public:
    virtual ~ITexture() = default;
    virtual const TextureDesc& desc() const = 0;   // mipLevels resolved (never 0)
};
using TextureHandle = std::shared_ptr<ITexture>;

enum class Filter { Nearest, Linear };
enum class AddressMode { Repeat, MirroredRepeat, ClampToEdge };
enum class CompareOp { Never, Less, Equal, LessOrEqual, Greater, NotEqual, GreaterOrEqual, Always };

struct SamplerDesc {
    Filter minFilter = Filter::Linear;
    Filter magFilter = Filter::Linear;
    Filter mipFilter = Filter::Linear;
    AddressMode addressU = AddressMode::Repeat;
    AddressMode addressV = AddressMode::Repeat;
    AddressMode addressW = AddressMode::Repeat;
    float minLod = 0.0f;
    float maxLod = 1000.0f;
    float maxAnisotropy = 1.0f;
    std::optional<CompareOp> compare;   // depth-comparison sampler (sampler2DShadow)

    SamplerDesc& setFilter(Filter f) { minFilter = magFilter = mipFilter = f; return *this; }
    SamplerDesc& setAddress(AddressMode m) { addressU = addressV = addressW = m; return *this; }
    SamplerDesc& setLodRange(float lo, float hi) { minLod = lo; maxLod = hi; return *this; }
    SamplerDesc& setCompare(CompareOp op) { compare = op; return *this; }
};

class ISampler {
public:
    virtual ~ISampler() = default;
    virtual const SamplerDesc& desc() const = 0;
};
using SamplerHandle = std::shared_ptr<ISampler>;

// ---------------------------------------------------------------------------------------------
// Shaders
// ---------------------------------------------------------------------------------------------

enum class ShaderStage : uint32_t { Vertex = 1, Fragment = 2, Compute = 4 };
const char* toString(ShaderStage stage);

// Every backend takes SPIR-V (compiled by glslang from shaders/). GL backends translate it with
// SPIRV-Cross to GLSL 430 / ESSL 300 and remap bindings from reflection.
struct ShaderDesc {
    ShaderStage stage = ShaderStage::Vertex;
    std::vector<uint32_t> spirv;
    std::string entryPoint = "main";
    std::string debugName;

    ShaderDesc& setStage(ShaderStage v) { stage = v; return *this; }
    ShaderDesc& setSpirv(std::span<const uint32_t> v) { spirv.assign(v.begin(), v.end()); return *this; }
    ShaderDesc& setDebugName(std::string v) { debugName = std::move(v); return *this; }
};

class IShader {
public:
    virtual ~IShader() = default;
    virtual const ShaderDesc& desc() const = 0;
    // The source the backend actually compiled (GLSL/ESSL on GL, empty on Vulkan). For debugging.
    virtual std::string translatedSource() const = 0;
};
using ShaderHandle = std::shared_ptr<IShader>;

// ---------------------------------------------------------------------------------------------
// Pipelines
// ---------------------------------------------------------------------------------------------

enum class VertexFormat { Float1, Float2, Float3, Float4, UByte4Norm, UInt1 };
uint32_t vertexFormatSize(VertexFormat f);

struct VertexAttribute {
    uint32_t location = 0;
    VertexFormat format = VertexFormat::Float3;
    uint32_t bufferSlot = 0;
    uint32_t offset = 0;
};

struct VertexBufferLayout {
    uint32_t slot = 0;
    uint32_t stride = 0;
    bool perInstance = false;
};

enum class PrimitiveTopology { TriangleList, TriangleStrip, LineList, PointList };
enum class CullMode { None, Front, Back };
enum class FrontFace { CounterClockwise, Clockwise };   // as seen in the image, row 0 on top

struct RasterState {
    CullMode cullMode = CullMode::None;
    FrontFace frontFace = FrontFace::CounterClockwise;
    // Polygon offset (depth bias): depth += slopeScale * max slope + constant * r.
    bool depthBiasEnable = false;
    float depthBiasConstant = 0.0f;
    float depthBiasSlope = 0.0f;
};

struct DepthState {
    bool testEnable = false;
    bool writeEnable = false;
    CompareOp compare = CompareOp::Less;
};

enum class BlendFactor { Zero, One, SrcColor, OneMinusSrcColor, SrcAlpha, OneMinusSrcAlpha, DstColor, OneMinusDstColor, DstAlpha, OneMinusDstAlpha };
enum class BlendOp { Add, Subtract, ReverseSubtract, Min, Max };

// A uniform buffer a pipeline reads through a dynamic offset (BindingItem::dynamicOffset): Vulkan
// bakes the binding's kind into the pipeline's layout, so the pipeline names it.
struct DynamicUniformBuffer {
    uint32_t set = 0;
    uint32_t binding = 0;
    bool operator==(const DynamicUniformBuffer&) const = default;
};

struct BlendAttachment {
    bool enable = false;
    BlendFactor srcColor = BlendFactor::One;
    BlendFactor dstColor = BlendFactor::Zero;
    BlendOp colorOp = BlendOp::Add;
    BlendFactor srcAlpha = BlendFactor::One;
    BlendFactor dstAlpha = BlendFactor::Zero;
    BlendOp alphaOp = BlendOp::Add;
    uint8_t writeMask = 0xF;   // RGBA bits

    static BlendAttachment additive() { return {true, BlendFactor::One, BlendFactor::One, BlendOp::Add, BlendFactor::One, BlendFactor::One, BlendOp::Add, 0xF}; }
    static BlendAttachment alpha() { return {true, BlendFactor::SrcAlpha, BlendFactor::OneMinusSrcAlpha, BlendOp::Add, BlendFactor::One, BlendFactor::OneMinusSrcAlpha, BlendOp::Add, 0xF}; }
};

struct GraphicsPipelineDesc {
    ShaderHandle vertexShader;
    ShaderHandle fragmentShader;
    std::vector<VertexBufferLayout> vertexBuffers;
    std::vector<VertexAttribute> vertexAttributes;
    PrimitiveTopology topology = PrimitiveTopology::TriangleList;
    RasterState raster;
    DepthState depth;
    std::vector<BlendAttachment> blend;   // one per colour attachment; missing = disabled
    // Formats of the attachments the pipeline renders into (must match the render pass).
    std::vector<Format> colorFormats;
    Format depthFormat = Format::Unknown;
    uint32_t sampleCount = 1;   // the attachments' TextureDesc::sampleCount (must match the render pass)
    // Alpha to coverage: each fragment covers only as many of its pixel's samples as the alpha of
    // its colour output 0 says (about alpha x sampleCount; which ones, and whether the pattern
    // varies between pixels, is the driver's), on top of the triangle's own coverage and the
    // depth test. Needs sampleCount > 1, a colour attachment (GL skips the step in a depth-only
    // pass, Vulkan does not, so the RHI refuses one) and a fragment shader writing a vec4 at
    // location 0.
    bool alphaToCoverage = false;
    std::vector<DynamicUniformBuffer> dynamicUniformBuffers;   // read with dynamic offsets
    std::string debugName;

    GraphicsPipelineDesc& setShaders(ShaderHandle vs, ShaderHandle fs) { vertexShader = std::move(vs); fragmentShader = std::move(fs); return *this; }
    GraphicsPipelineDesc& addVertexBuffer(VertexBufferLayout v) { vertexBuffers.push_back(v); return *this; }
    GraphicsPipelineDesc& addVertexAttribute(VertexAttribute v) { vertexAttributes.push_back(v); return *this; }
    GraphicsPipelineDesc& setTopology(PrimitiveTopology v) { topology = v; return *this; }
    GraphicsPipelineDesc& setRaster(RasterState v) { raster = v; return *this; }
    GraphicsPipelineDesc& setDepth(DepthState v) { depth = v; return *this; }
    GraphicsPipelineDesc& addColorFormat(Format f, BlendAttachment b = {}) { colorFormats.push_back(f); blend.push_back(b); return *this; }
    GraphicsPipelineDesc& setDepthFormat(Format f) { depthFormat = f; return *this; }
    GraphicsPipelineDesc& setSampleCount(uint32_t v) { sampleCount = v; return *this; }
    GraphicsPipelineDesc& setAlphaToCoverage(bool v) { alphaToCoverage = v; return *this; }
    GraphicsPipelineDesc& addDynamicUniformBuffer(uint32_t set, uint32_t binding) { dynamicUniformBuffers.push_back({set, binding}); return *this; }
    GraphicsPipelineDesc& setDebugName(std::string v) { debugName = std::move(v); return *this; }
};

struct ComputePipelineDesc {
    ShaderHandle computeShader;
    std::vector<DynamicUniformBuffer> dynamicUniformBuffers;   // read with dynamic offsets
    std::string debugName;

    ComputePipelineDesc& setShader(ShaderHandle v) { computeShader = std::move(v); return *this; }
    ComputePipelineDesc& addDynamicUniformBuffer(uint32_t set, uint32_t binding) { dynamicUniformBuffers.push_back({set, binding}); return *this; }
    ComputePipelineDesc& setDebugName(std::string v) { debugName = std::move(v); return *this; }
};

class IPipeline {
public:
    virtual ~IPipeline() = default;
    virtual bool isCompute() const = 0;
};
using PipelineHandle = std::shared_ptr<IPipeline>;

// ---------------------------------------------------------------------------------------------
// Binding sets: the resources one `set` of a shader sees
// ---------------------------------------------------------------------------------------------

enum class ResourceType {
    UniformBuffer,    // layout(std140) uniform Block
    StorageBuffer,    // layout(std430) buffer Block; needs StorageBuffers
    SampledTexture,   // sampler2D / sampler3D / samplerCube / sampler2DArray / samplerCubeArray /
                      // sampler2DShadow (texture + sampler)
    StorageImage,     // image2D / image3D / imageCube / image2DArray / imageCubeArray (one mip level;
                      // all layers, or one layer as image2D); needs StorageImages
};

inline constexpr uint32_t kAllMips = ~0u;     // a count meaning "to the last mip level"
inline constexpr uint32_t kAllLayers = ~0u;   // a count meaning "to the last layer"

// The part of a texture a SampledTexture / StorageImage binding sees (a "view"). The defaults
// view everything. Layers count 2D layers (faces, array layers, layer-faces; see
// TextureDimension); 3D textures are always viewed whole. The shader's declared type must match
// the view's dimension: viewDimension when set, otherwise the texture's.
//  * Mip ranges work everywhere (GLES emulates them with GL_TEXTURE_BASE_LEVEL/MAX_LEVEL, so
//    there one texture can be seen through only one mip range per draw). Level of detail 0 of a
//    view is its baseMip, as in Vulkan and GL texture views.
//  * A layer subrange or a viewDimension other than the texture's needs Capability::TextureViews
//    (not on GLES). Allowed: 2D/2D-array -> Texture2D (one layer) or Texture2DArray; cube and
//    cube array -> Texture2D (one layer), Texture2DArray, TextureCube (6 layers from a multiple
//    of 6), TextureCubeArray (multiples of 6; needs CubeArrays).
//  * Storage images bind one mip (BindingItem::mipLevel; leave the mip range at its default)
//    and all layers with the texture's dimension, or one layer as Texture2D.
//  * A view may not overlap a subresource the same draw / dispatch writes: an attachment of the
//    current render pass, or a storage image of the bound sets (InvalidUsage on every backend).
struct TextureViewRange {
    uint32_t baseMip = 0;
    uint32_t mipCount = kAllMips;
    uint32_t baseLayer = 0;
    uint32_t layerCount = kAllLayers;
};

struct BindingItem {
    uint32_t binding = 0;
    ResourceType type = ResourceType::UniformBuffer;
    BufferHandle buffer;
    uint64_t offset = 0;
    uint64_t range = 0;               // 0 = to the end of the buffer
    TextureHandle texture;
    SamplerHandle sampler;
    uint32_t mipLevel = 0;            // StorageImage: which level
    TextureViewRange view;            // textures: which mips / layers the binding sees
    std::optional<TextureDimension> viewDimension;   // textures: view as another dimension
    // Uniform buffers: the bound window [offset + d, offset + d + range) moves with the offset d
    // given to each setBindingSet (one per dynamic item, in binding order), so one set serves many
    // draws, each with its own slice (Vulkan's UNIFORM_BUFFER_DYNAMIC, WebGPU's hasDynamicOffset).
    // Needs a non-zero range, and pipelines that read the binding declare it dynamic
    // (GraphicsPipelineDesc::addDynamicUniformBuffer).
    bool dynamicOffset = false;

    static BindingItem uniformBuffer(uint32_t b, BufferHandle buf, uint64_t off = 0, uint64_t rng = 0) { BindingItem i; i.binding = b; i.type = ResourceType::UniformBuffer; i.buffer = std::move(buf); i.offset = off; i.range = rng; return i; }
    static BindingItem storageBuffer(uint32_t b, BufferHandle buf, uint64_t off = 0, uint64_t rng = 0) { BindingItem i; i.binding = b; i.type = ResourceType::StorageBuffer; i.buffer = std::move(buf); i.offset = off; i.range = rng; return i; }
    static BindingItem sampledTexture(uint32_t b, TextureHandle tex, SamplerHandle smp) { BindingItem i; i.binding = b; i.type = ResourceType::SampledTexture; i.texture = std::move(tex); i.sampler = std::move(smp); return i; }
    static BindingItem storageImage(uint32_t b, TextureHandle tex, uint32_t mip = 0) { BindingItem i; i.binding = b; i.type = ResourceType::StorageImage; i.texture = std::move(tex); i.mipLevel = mip; return i; }
    // Views (see TextureViewRange): BindingItem::sampledTexture(1, cube, s).setMips(2, 1).setLayers(4, 1)
    //     .setViewDimension(TextureDimension::Texture2D) samples face +Z of mip 2 as a sampler2D.
    BindingItem& setMips(uint32_t base, uint32_t count = 1) { view.baseMip = base; view.mipCount = count; return *this; }
    BindingItem& setLayers(uint32_t base, uint32_t count = 1) { view.baseLayer = base; view.layerCount = count; return *this; }
    BindingItem& setViewDimension(TextureDimension d) { viewDimension = d; return *this; }
    BindingItem& setDynamicOffset(bool v = true) { dynamicOffset = v; return *this; }
};

// Sets a pipeline may use: `layout(set = 0 .. kMaxBindingSets - 1)`.
inline constexpr uint32_t kMaxBindingSets = 4;
// Dynamic uniform buffers (BindingItem::dynamicOffset): at most this many items of a set, and this
// many bindings a pipeline declares (Vulkan's guaranteed maxDescriptorSetUniformBuffersDynamic).
inline constexpr uint32_t kMaxDynamicOffsetsPerSet = 4;
inline constexpr uint32_t kMaxDynamicUniformBuffersPerPipeline = 8;

struct BindingSetDesc {
    std::vector<BindingItem> items;
    BindingSetDesc& add(BindingItem item) { items.push_back(std::move(item)); return *this; }
};

class IBindingSet {
public:
    virtual ~IBindingSet() = default;
    virtual const BindingSetDesc& desc() const = 0;

private:
    friend struct detail::BackendAccess;
    friend class IDevice;        // sets the dynamic offset count
    friend class ICommandList;   // checks it
    // Here rather than in each backend's class: a command list finds out whether it holds a set
    // before it knows the set's type, and one it holds had its type checked when it first held it,
    // so a per-draw bind of a held set checks nothing else.
    mutable detail::KeepMark m_keepMark;   // bookkeeping, not the set's state
};
using BindingSetHandle = std::shared_ptr<IBindingSet>;

// ---------------------------------------------------------------------------------------------
// Timers
// ---------------------------------------------------------------------------------------------

class ITimerQuery {
public:
    virtual ~ITimerQuery() = default;
};
using TimerQueryHandle = std::shared_ptr<ITimerQuery>;

// ---------------------------------------------------------------------------------------------
// Render passes
// ---------------------------------------------------------------------------------------------

enum class LoadOp { Load, Clear, DontCare };
enum class StoreOp { Store, DontCare };

// An attachment is any 2D subresource: a 2D mip, a cube face + mip, an array layer (cube arrays:
// layer-face 6 * cube + face) + mip, or a 3D slice at a mip.
struct Attachment {
    TextureHandle texture;
    TextureSubresource subresource;
    LoadOp loadOp = LoadOp::Clear;
    StoreOp storeOp = StoreOp::Store;
    std::array<float, 4> clearColor{0, 0, 0, 0};
    float clearDepth = 1.0f;
    // Colour attachments of a multisampled texture: at the end of the pass its samples are
    // averaged into this single-sampled texture of the same format and size (its subresource
    // resolveSubresource), which is written whole. Null: no resolve.
    TextureHandle resolveTexture;
    TextureSubresource resolveSubresource;

    Attachment& resolveTo(TextureHandle t, TextureSubresource s = {}) { resolveTexture = std::move(t); resolveSubresource = s; return *this; }

    static Attachment clear(TextureHandle t, std::array<float, 4> c = {0, 0, 0, 0}, TextureSubresource s = {}) { Attachment a; a.texture = std::move(t); a.clearColor = c; a.subresource = s; return a; }
    static Attachment clearDepthTo(TextureHandle t, float d = 1.0f, TextureSubresource s = {}) { Attachment a; a.texture = std::move(t); a.clearDepth = d; a.subresource = s; return a; }
    static Attachment load(TextureHandle t, TextureSubresource s = {}) { Attachment a; a.texture = std::move(t); a.loadOp = LoadOp::Load; a.subresource = s; return a; }
};

struct RenderPassDesc {
    std::vector<Attachment> colors;
    std::optional<Attachment> depth;

    RenderPassDesc& addColor(Attachment a) { colors.push_back(std::move(a)); return *this; }
    RenderPassDesc& setDepth(Attachment a) { depth = std::move(a); return *this; }
};

// Checked against Limits::maxViewportSize and viewportBoundsRange: width and height in
// (0, maxViewportSize], the rectangle inside the bounds range, depths in [0, 1] (minDepth may be
// above maxDepth); no value may be NaN. x, y, width and height are whole pixels (GL and ES take
// no fractions, so a fractional viewport is refused on every backend).
struct Viewport {
    float x = 0, y = 0, width = 0, height = 0;   // y counts rows from row 0 (top)
    float minDepth = 0, maxDepth = 1;
};

// x, y >= 0; x + width and y + height at most INT32_MAX.
struct ScissorRect {
    int32_t x = 0, y = 0;
    uint32_t width = 0, height = 0;
};

enum class IndexType { UInt16, UInt32 };

// ---------------------------------------------------------------------------------------------
// Command lists
// ---------------------------------------------------------------------------------------------

// What the validation layer checks calls against; fixed when the device starts. Backends fill
// it once (IDevice::setProperties); the device and its command lists share it.
struct DeviceProperties {
    DeviceInfo info;
    Capabilities capabilities;
    std::vector<FormatCapabilities> formats;   // indexed by Format (Unknown: none)
    bool validation = false;                   // DeviceDesc::enableValidation: the front's own checks report too
};

// Records work; IDevice::execute() runs it. Barriers between passes, dispatches and copies are
// inserted by the backend. Resources referenced by a command list are kept alive until it has
// executed.
//
// The non-virtual calls validate their arguments (rhi/src/validation.cpp) and then call the
// backend's protected ...Impl; the per-draw calls (pipeline, draws) go to the backend directly,
// and setBindingSet and dispatch check inline first.
class ICommandList {
public:
    virtual ~ICommandList() = default;

    void begin();   // resets and starts recording
    virtual void end() = 0;

    // Render passes. Viewport and scissor default to the full attachment; they are set inside a
    // render pass (InvalidUsage outside one: the next pass would reset them).
    void beginRenderPass(const RenderPassDesc& desc);
    virtual void endRenderPass() = 0;
    void setViewport(const Viewport& viewport);
    void setScissor(const ScissorRect& scissor);
    virtual void setPipeline(const PipelineHandle& pipeline) = 0;
    void setBindingSet(uint32_t set, const BindingSetHandle& bindings) {
        if (set >= kMaxBindingSets || !bindings || bindings->m_keepMark.dynamicOffsetCount) [[unlikely]]
            throwInvalidSetBinding(set, bindings.get());
        setBindingSetImpl(set, bindings);
    }
    // A set with dynamic uniform buffers (BindingItem::dynamicOffset): one offset per such item, in
    // binding order, each a multiple of Limits::uniformBufferOffsetAlignment and keeping its window
    // inside the buffer. Binding the set again with other offsets moves its windows.
    void setBindingSet(uint32_t set, const BindingSetHandle& bindings, std::span<const uint32_t> dynamicOffsets) {
        // Per draw, so inline: the count, and the alignment by a mask (a power of two, else every
        // offset but 0 takes the checked path, which divides).
        uint32_t misaligned = 0;
        for (const uint32_t offset : dynamicOffsets) misaligned |= offset & m_dynamicOffsetMask;
        if (set >= kMaxBindingSets || !bindings || misaligned ||
            dynamicOffsets.size() != bindings->m_keepMark.dynamicOffsetCount || dynamicOffsets.empty()) [[unlikely]]
            return setBindingSetChecked(set, bindings, dynamicOffsets);
        setBindingSetImpl(set, bindings, dynamicOffsets);
    }
    void setVertexBuffer(uint32_t slot, const BufferHandle& buffer, uint64_t offset = 0);
    void setIndexBuffer(const BufferHandle& buffer, IndexType type, uint64_t offset = 0);
    // Draws read only inside their buffers: firstVertex + vertexCount vertices must fit in every
    // per-vertex slot (from its offset), firstInstance + instanceCount in every per-instance slot,
    // firstIndex + indexCount in the index buffer (InvalidUsage otherwise). With validation on,
    // IDevice::execute also checks the index values against the per-vertex buffers, where the host
    // wrote them (rhi/backend-api/janus/rhi/index_value_validation.h).
    virtual void draw(uint32_t vertexCount, uint32_t instanceCount = 1, uint32_t firstVertex = 0, uint32_t firstInstance = 0) = 0;
    virtual void drawIndexed(uint32_t indexCount, uint32_t instanceCount = 1, uint32_t firstIndex = 0, int32_t vertexOffset = 0, uint32_t firstInstance = 0) = 0;

    // Compute (outside render passes). Throws UnsupportedCapability without Capability::Compute.
    void dispatch(uint32_t groupsX, uint32_t groupsY = 1, uint32_t groupsZ = 1) {
        const Capabilities& caps = m_properties->capabilities;
        const auto& most = caps.limits.maxComputeWorkGroupCount;
        if (!caps.compute || groupsX > most[0] || groupsY > most[1] || groupsZ > most[2]) [[unlikely]]
            throwInvalidDispatch(groupsX, groupsY, groupsZ);
        dispatchImpl(groupsX, groupsY, groupsZ);
    }

    // Transfers (outside render passes). Sizes are whole subresources, rows tightly packed.
    void writeBuffer(const BufferHandle& dst, const void* data, uint64_t size, uint64_t dstOffset = 0);
    void copyBuffer(const BufferHandle& dst, uint64_t dstOffset, const BufferHandle& src, uint64_t srcOffset, uint64_t size);
    void copyBufferToTexture(const TextureHandle& dst, TextureSubresource dstSub, const BufferHandle& src, uint64_t srcOffset = 0);
    void copyTextureToBuffer(const BufferHandle& dst, uint64_t dstOffset, const TextureHandle& src, TextureSubresource srcSub);
    void copyTexture(const TextureHandle& dst, TextureSubresource dstSub, const TextureHandle& src, TextureSubresource srcSub);
    void generateMips(const TextureHandle& texture);   // from mip 0, every face/layer/slice

    // GPU timers: the time between begin and end on the GPU.
    virtual void beginTimer(const TimerQueryHandle& timer) = 0;
    virtual void endTimer(const TimerQueryHandle& timer) = 0;

    virtual void pushDebugGroup(std::string_view name) = 0;
    virtual void popDebugGroup() = 0;

    // Vulkan: the hazard tracker leaves out the next barrier it would record, so a test can show
    // that synchronisation validation catches a missing one. GL: nothing (no tool reports a
    // missing glMemoryBarrier; tests/rhi/gl_barriers_test.cpp watches the calls instead).
    virtual void omitNextBarrierForTesting() = 0;

protected:
    // Called with validated arguments only.
    virtual void beginImpl() = 0;
    virtual void beginRenderPassImpl(const RenderPassDesc& desc) = 0;
    virtual void setViewportImpl(const Viewport& viewport) = 0;
    virtual void setScissorImpl(const ScissorRect& scissor) = 0;
    virtual void setBindingSetImpl(uint32_t set, const BindingSetHandle& bindings) = 0;
    // A set with dynamic offsets (count and alignment checked; the backend checks the windows
    // with takeDynamicOffsets, rhi/backend-api/janus/rhi/dynamic_offsets.h).
    virtual void setBindingSetImpl(uint32_t set, const BindingSetHandle& bindings,
                                   std::span<const uint32_t> dynamicOffsets) = 0;
    virtual void setVertexBufferImpl(uint32_t slot, const BufferHandle& buffer, uint64_t offset) = 0;
    virtual void setIndexBufferImpl(const BufferHandle& buffer, IndexType type, uint64_t offset) = 0;
    virtual void dispatchImpl(uint32_t groupsX, uint32_t groupsY, uint32_t groupsZ) = 0;
    virtual void writeBufferImpl(const BufferHandle& dst, const void* data, uint64_t size, uint64_t dstOffset) = 0;
    virtual void copyBufferImpl(const BufferHandle& dst, uint64_t dstOffset, const BufferHandle& src, uint64_t srcOffset, uint64_t size) = 0;
    virtual void copyBufferToTextureImpl(const TextureHandle& dst, TextureSubresource dstSub, const BufferHandle& src, uint64_t srcOffset) = 0;
    virtual void copyTextureToBufferImpl(const BufferHandle& dst, uint64_t dstOffset, const TextureHandle& src, TextureSubresource srcSub) = 0;
    virtual void copyTextureImpl(const TextureHandle& dst, TextureSubresource dstSub, const TextureHandle& src, TextureSubresource srcSub) = 0;
    virtual void generateMipsImpl(const TextureHandle& texture) = 0;

    const DeviceProperties& properties() const { return *m_properties; }
    // With validation on: where backends note each indexed draw for IDevice::execute's check of
    // its index values (index_value_validation.h). Null otherwise.
    detail::IndexValueLog* indexValueLog() const { return m_indexValueLog.get(); }

private:
    friend class IDevice;
    [[noreturn]] void throwInvalidSetBinding(uint32_t set, const IBindingSet* bindings) const;
    void setBindingSetChecked(uint32_t set, const BindingSetHandle& bindings, std::span<const uint32_t> dynamicOffsets);
    // Limits::uniformBufferOffsetAlignment - 1 where that is a power of two, else ~0 (set with m_properties).
    uint32_t m_dynamicOffsetMask = ~0u;
    [[noreturn]] void throwInvalidDispatch(uint32_t groupsX, uint32_t groupsY, uint32_t groupsZ) const;
    std::shared_ptr<const DeviceProperties> m_properties;   // set by IDevice::createCommandList
    std::shared_ptr<detail::IndexValueLog> m_indexValueLog;   // likewise, with validation on
};
using CommandListHandle = std::shared_ptr<ICommandList>;

// ---------------------------------------------------------------------------------------------
// Device
// ---------------------------------------------------------------------------------------------

// The non-virtual calls validate descriptions and arguments once, the same way for every
// backend (rhi/src/validation.cpp), and then call the backend's protected ...Impl.
class IDevice {
public:
    virtual ~IDevice() = default;

    const DeviceInfo& info() const { return m_properties->info; }
    const Capabilities& capabilities() const { return m_properties->capabilities; }
    // What this device can do with `format` (queried from the driver at start-up).
    FormatCapabilities formatCapabilities(Format format) const;
    const DeviceProperties& properties() const { return *m_properties; }
    // Throws Error(UnsupportedCapability) naming `cap` and `what` when the device lacks it.
    void require(Capability cap, std::string_view what) const;
    // Expires when the device is destroyed. What keeps an IDevice& (a renderer) can tell that its
    // device is gone and refuse work instead of calling into freed memory.
    std::weak_ptr<const void> lifetime() const { return m_lifetime; }

    BufferHandle createBuffer(const BufferDesc& desc);
    TextureHandle createTexture(const TextureDesc& desc);
    SamplerHandle createSampler(const SamplerDesc& desc);
    ShaderHandle createShader(const ShaderDesc& desc);
    PipelineHandle createGraphicsPipeline(const GraphicsPipelineDesc& desc);
    PipelineHandle createComputePipeline(const ComputePipelineDesc& desc);
    BindingSetHandle createBindingSet(const BindingSetDesc& desc);
    TimerQueryHandle createTimerQuery();
    CommandListHandle createCommandList();

    // Submits recorded work. Work runs in submission order. With validation on, first checks the
    // index values of the list's indexed draws (ICommandList::drawIndexed).
    void execute(const CommandListHandle& commandList);
    virtual void waitIdle() = 0;

    // Threads (docs/ARCHITECTURE.md, "Threads"). Recording a command list and releasing handles
    // are fine on any thread. Device calls: from several threads at once where
    // Capability::ConcurrentDeviceCalls (Vulkan), else one thread at a time (GL: its context
    // stays current on the thread that used the device last, and a call from another thread
    // throws InvalidUsage until that thread calls detachFromThread() or exits). Vulkan: nothing.
    virtual void detachFromThread() = 0;

    // Immediate transfers: wait for all executed work, then act. Rows tightly packed; row 0 is
    // the row at v = 0 (see Conventions).
    void writeBuffer(const BufferHandle& buffer, const void* data, uint64_t size, uint64_t offset = 0);
    std::vector<std::byte> readBuffer(const BufferHandle& buffer, uint64_t offset = 0, uint64_t size = 0);  // size 0 = to the end
    void writeTexture(const TextureHandle& texture, TextureSubresource sub, const void* data, uint64_t size);
    std::vector<std::byte> readTexture(const TextureHandle& texture, TextureSubresource sub);

    // GPU time in seconds between the timer's begin and end; waits for the result. nullopt when
    // the timer never ran.
    virtual std::optional<double> timerSeconds(const TimerQueryHandle& timer) = 0;

    // Validation-layer / GL debug messages of severity Warning or Error collected since the last
    // call: what tests fail on.
    virtual std::vector<DebugMessage> takeDebugMessages() = 0;
    // The driver's performance messages (severity Performance) collected since the last call, kept
    // apart from takeDebugMessages(): a renderer counts them in its frame report and a tool prints
    // them; a test fails on them only where it says so. Needs enableValidation, like the others.
    virtual std::vector<DebugMessage> takePerformanceMessages() = 0;
    // Sends one performance message through the API's own debug channel (GL: glDebugMessageInsert;
    // Vulkan: vkSubmitDebugUtilsMessageEXT), so tests can prove such messages are routed as above.
    virtual void insertPerformanceMessageForTesting(const std::string& text) = 0;

    // Makes one deliberately invalid raw API call (Vulkan: through the validation layer; GL: one
    // that raises a GL error) so tests can prove the debug-message hook really catches errors.
    virtual void provokeValidationErrorForTesting() = 0;

protected:
    // Backends call this once, from their constructor, before the device is used.
    void setProperties(DeviceProperties properties);

    // Called with validated descriptions and arguments only (TextureDesc::mipLevels resolved).
    virtual BufferHandle createBufferImpl(const BufferDesc& desc) = 0;
    virtual TextureHandle createTextureImpl(const TextureDesc& desc) = 0;
    virtual SamplerHandle createSamplerImpl(const SamplerDesc& desc) = 0;
    virtual ShaderHandle createShaderImpl(const ShaderDesc& desc) = 0;
    virtual PipelineHandle createGraphicsPipelineImpl(const GraphicsPipelineDesc& desc) = 0;
    virtual PipelineHandle createComputePipelineImpl(const ComputePipelineDesc& desc) = 0;
    virtual BindingSetHandle createBindingSetImpl(const BindingSetDesc& desc) = 0;
    virtual TimerQueryHandle createTimerQueryImpl() = 0;
    virtual CommandListHandle createCommandListImpl() = 0;
    virtual void executeImpl(const CommandListHandle& commandList) = 0;
    virtual void writeBufferImpl(const BufferHandle& buffer, const void* data, uint64_t size, uint64_t offset) = 0;
    virtual std::vector<std::byte> readBufferImpl(const BufferHandle& buffer, uint64_t offset, uint64_t size) = 0;  // size resolved
    virtual void writeTextureImpl(const TextureHandle& texture, TextureSubresource sub, const void* data, uint64_t size) = 0;
    virtual std::vector<std::byte> readTextureImpl(const TextureHandle& texture, TextureSubresource sub) = 0;
    // A message from the front's own checks (with validation on: a fragment shader's implicit
    // derivatives where the quad may be incomplete, rhi/backend-api/janus/rhi/derivative_lint.h):
    // collected with the driver's, returned by takeDebugMessages() and passed to
    // DeviceDesc::messageCallback. Keeps the message before calling the callback, and lets what the
    // callback throws through (the front catches and prints it).
    virtual void collectFrontMessage(const DebugMessage& message) = 0;

private:
    std::shared_ptr<const DeviceProperties> m_properties;
    std::shared_ptr<const void> m_lifetime = std::make_shared<int>(0);
};

// Creates a device for desc.backend. Throws Error(BackendUnavailable) with the reason when the
// backend cannot start (no driver, no EGL platform, ...).
std::unique_ptr<IDevice> createDevice(const DeviceDesc& desc);

// Which backends start on this machine, with the reason for those that do not.
struct BackendProbe {
    Backend backend;
    bool available = false;
    std::string reason;   // empty when available
};
std::vector<BackendProbe> probeBackends(GLPlatform glPlatform = GLPlatform::EGL);

// The EGL devices the GL backends can be pointed at (JANUS_EGL_DEVICE takes the index or any of
// the names: the DRM device file and render node, whole or without their folder, "software" for
// Mesa's software renderer). Empty where EGL cannot enumerate devices. Starts no device.
struct EglDeviceListing {
    uint32_t index = 0;
    std::vector<std::string> names;   // may be empty: choose such a device by its index
};
std::vector<EglDeviceListing> listEglDevices();

}  // namespace janus::rhi
