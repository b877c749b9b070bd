// The validation layer (rhi/src/validation.cpp): the same mistake gives the same ErrorCode on
// every backend, and the message names what to change. One table of mistakes, one or more per
// description kind and per validated call; each runs on every backend.
#include "backend_test.h"

namespace janus::rhi::test {
namespace {

class ValidationTest : public BackendTest {};
JANUS_INSTANTIATE_BACKEND_TESTS(ValidationTest);

struct Mistake {
    const char* what;
    ErrorCode code;
    std::vector<std::string> mentions;   // words the message must contain
    std::function<void()> make;
    std::optional<Capability> needs = std::nullopt;   // skipped on devices without it
};

TEST_P(ValidationTest, SameMistakeSameErrorCodeOnEveryBackend) {
    constexpr ErrorCode kDesc = ErrorCode::InvalidDescription;
    constexpr ErrorCode kUsage = ErrorCode::InvalidUsage;
    constexpr ErrorCode kUnsupported = ErrorCode::UnsupportedCapability;
    const Limits& limits = caps().limits;
    IDevice& dev = device();

    // Shared valid pieces.
    ShaderHandle vs = shader("rt_vertex_color_vert"), fs = shader("rt_vertex_color_frag");
    auto pipelineDesc = [&] {
        GraphicsPipelineDesc d;
        d.setShaders(vs, fs)
            .addVertexBuffer({0, sizeof(ColorVertex), false})
            .addVertexAttribute({0, VertexFormat::Float4, 0, offsetof(ColorVertex, x)})
            .addVertexAttribute({1, VertexFormat::Float4, 0, offsetof(ColorVertex, r)})
            .addColorFormat(Format::RGBA8_UNORM)
            .setDebugName("mistake");
        return d;
    };
    TextureHandle color = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::Sampled | TextureUsage::RenderTarget);
    TextureHandle small = createTexture2D(Format::RGBA8_UNORM, 2, 2, TextureUsage::RenderTarget);
    TextureHandle sampledOnly = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::Sampled);
    TextureHandle other = createTexture2D(Format::RGBA16_FLOAT, 4, 4, TextureUsage::Sampled);
    TextureHandle depth = createTexture2D(Format::D32_FLOAT, 4, 4, TextureUsage::RenderTarget);
    TextureHandle uintTexture = createTexture2D(Format::R32_UINT, 4, 4, TextureUsage::Sampled);
    TextureHandle uintTarget = createTexture2D(Format::R32_UINT, 4, 4, TextureUsage::RenderTarget);
    TextureHandle array = dev.createTexture(TextureDesc()
                                                .setDimension(TextureDimension::Texture2DArray)
                                                .setSize(4, 4)
                                                .setArrayLayers(3)
                                                .setUsage(TextureUsage::Sampled | TextureUsage::RenderTarget));
    BufferHandle uniforms = createBuffer(BufferUsage::Uniform, 1024);
    BufferHandle vertices = createBuffer(BufferUsage::Vertex, 256);
    SamplerHandle nearest = nearestClampSampler();
    SamplerHandle linear = dev.createSampler(SamplerDesc());
    SamplerHandle compare = dev.createSampler(SamplerDesc().setFilter(Filter::Nearest).setCompare(CompareOp::Less));
    std::vector<std::byte> bytes(4096);
    auto record = [&](const std::function<void(ICommandList&)>& body) { submit(body); };
    auto bindings = [&](BindingItem item) { dev.createBindingSet(BindingSetDesc().add(std::move(item))); };
    auto pass = [&](RenderPassDesc desc) { record([&](ICommandList& cmd) { cmd.beginRenderPass(desc); cmd.endRenderPass(); }); };
    auto inPass = [&](const std::function<void(ICommandList&)>& body) {
        record([&](ICommandList& cmd) { cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(color))); body(cmd); cmd.endRenderPass(); });
    };

    const std::vector<Mistake> mistakes = {
        // BufferDesc
        {"buffer of size 0", kDesc, {"BufferDesc", "size"}, [&] { dev.createBuffer(BufferDesc().setUsage(BufferUsage::Vertex)); }},
        {"buffer above maxBufferSize", kDesc, {"maxBufferSize"},
         [&] { dev.createBuffer(BufferDesc().setSize(limits.maxBufferSize + 1).setUsage(BufferUsage::Vertex)); }},
        // TextureDesc
        {"texture of width 0", kDesc, {"TextureDesc", "width"}, [&] { dev.createTexture(TextureDesc().setSize(0, 4)); }},
        {"2D texture with depth 2", kDesc, {"depth"}, [&] { dev.createTexture(TextureDesc().setSize(4, 4, 2)); }},
        {"cube 8x4", kDesc, {"cube"}, [&] { dev.createTexture(TextureDesc().setDimension(TextureDimension::TextureCube).setSize(8, 4)); }},
        {"3D depth texture", kDesc, {"depth formats"},
         [&] { dev.createTexture(TextureDesc().setDimension(TextureDimension::Texture3D).setFormat(Format::D32_FLOAT).setSize(4, 4, 4)); }},
        {"too many mips", kDesc, {"mipLevels"}, [&] { dev.createTexture(TextureDesc().setSize(4, 4).setMipLevels(4)); }},
        {"texture usage None", kDesc, {"usage"}, [&] { dev.createTexture(TextureDesc().setSize(4, 4).setUsage(TextureUsage::None)); }},
        // Values outside the enums (GL raised GL_INVALID_ENUM for the dimension, Vulkan made an image).
        {"texture dimension outside the enum", kDesc, {"dimension 77"}, [&] {
             dev.createTexture(TextureDesc().setDimension(TextureDimension(77)).setSize(4, 4)); }},
        {"texture usage bit outside the enum", kDesc, {"TextureUsage"}, [&] {
             dev.createTexture(TextureDesc().setSize(4, 4).setUsage(TextureUsage::Sampled | TextureUsage(0x100))); }},
        {"buffer usage bit outside the enum", kDesc, {"BufferUsage"}, [&] {
             dev.createBuffer(BufferDesc().setSize(16).setUsage(BufferUsage::Vertex | BufferUsage(0x100))); }},
        // The other enums: each backend's switch fell back to its own default (CullMode 77 culled
        // every triangle on GL and none on Vulkan; LoadOp 77 loaded on GL, DONT_CARE on Vulkan).
        {"topology outside the enum", kDesc, {"topology", "77"}, [&] {
             dev.createGraphicsPipeline(pipelineDesc().setTopology(PrimitiveTopology(77))); }},
        {"cull mode outside the enum", kDesc, {"raster.cullMode", "77"}, [&] {
             auto d = pipelineDesc(); d.raster.cullMode = CullMode(77); dev.createGraphicsPipeline(d); }},
        {"front face outside the enum", kDesc, {"raster.frontFace"}, [&] {
             auto d = pipelineDesc(); d.raster.frontFace = FrontFace(77); dev.createGraphicsPipeline(d); }},
        {"depth compare outside the enum", kDesc, {"depth.compare"}, [&] {
             dev.createGraphicsPipeline(pipelineDesc().setDepthFormat(Format::D32_FLOAT).setDepth({true, true, CompareOp(77)})); }},
        {"blend factor outside the enum", kDesc, {"blend[0].dstColor"}, [&] {
             auto d = pipelineDesc(); d.blend[0] = BlendAttachment::alpha(); d.blend[0].dstColor = BlendFactor(77); dev.createGraphicsPipeline(d); }},
        {"blend op outside the enum, blending off", kDesc, {"blend[0].alphaOp"}, [&] {
             auto d = pipelineDesc(); d.blend[0].alphaOp = BlendOp(-1); dev.createGraphicsPipeline(d); }},
        {"write mask above RGBA", kDesc, {"writeMask", "0xff"}, [&] {
             auto d = pipelineDesc(); d.blend[0].writeMask = 0xFF; dev.createGraphicsPipeline(d); }},
        {"vertex format outside the enum", kDesc, {"vertex attribute location 0", "77"}, [&] {
             auto d = pipelineDesc(); d.vertexAttributes[0].format = VertexFormat(77); dev.createGraphicsPipeline(d); }},
        {"sampler filter outside the enum", kDesc, {"magFilter"}, [&] { SamplerDesc d; d.magFilter = Filter(77); dev.createSampler(d); }},
        {"sampler address mode outside the enum", kDesc, {"addressW"}, [&] { SamplerDesc d; d.addressW = AddressMode(77); dev.createSampler(d); }},
        {"sampler compare outside the enum", kDesc, {"compare"}, [&] {
             dev.createSampler(SamplerDesc().setFilter(Filter::Nearest).setCompare(CompareOp(77))); }},
        {"shader stage outside the enum", kDesc, {"stage 3"}, [&] {
             dev.createShader(ShaderDesc().setStage(ShaderStage(3)).setSpirv(janus::shaders::get("rt_vertex_color_vert"))); }},
        {"binding type outside the enum", kDesc, {"binding 0", "type"}, [&] {
             BindingItem item = BindingItem::uniformBuffer(0, uniforms); item.type = ResourceType(77); bindings(item); }},
        {"load op outside the enum", kDesc, {"loadOp"}, [&] {
             Attachment a = Attachment::clear(color); a.loadOp = LoadOp(77); pass(RenderPassDesc().addColor(a)); }},
        {"store op outside the enum", kDesc, {"storeOp"}, [&] {
             Attachment a = Attachment::clear(color); a.storeOp = StoreOp(77); pass(RenderPassDesc().addColor(a)); }},
        {"index type outside the enum", kUsage, {"index type 77"}, [&] {
             BufferHandle indices = createBuffer(BufferUsage::Index, 64);
             record([&](ICommandList& c) { c.setIndexBuffer(indices, IndexType(77)); }); }},
        {"texture format Unknown", kDesc, {"format"}, [&] { dev.createTexture(TextureDesc().setFormat(Format::Unknown).setSize(4, 4)); }},
        {"2D texture above maxTextureSize2D", kDesc, {"maxTextureSize2D"},
         [&] { dev.createTexture(TextureDesc().setSize(limits.maxTextureSize2D + 1, 1)); }},
        {"2D array with depth 2", kDesc, {"depth"}, [&] {
             dev.createTexture(TextureDesc().setDimension(TextureDimension::Texture2DArray).setSize(4, 4, 2).setArrayLayers(2)); }},
        {"2D array above maxTextureArrayLayers", kDesc, {"maxTextureArrayLayers"}, [&] {
             dev.createTexture(TextureDesc().setDimension(TextureDimension::Texture2DArray).setArrayLayers(limits.maxTextureArrayLayers + 1)); }},
        {"arrayLayers on a 2D texture", kDesc, {"arrayLayers", "Texture2DArray"},
         [&] { dev.createTexture(TextureDesc().setSize(4, 4).setArrayLayers(2)); }},
        {"sRGB storage texture", kUnsupported, {"rgba8_srgb", "storage"},
         [&] { dev.createTexture(TextureDesc().setFormat(Format::RGBA8_SRGB).setSize(4, 4).setUsage(TextureUsage::Storage)); },
         Capability::StorageImages},
        // SamplerDesc
        {"minLod above maxLod", kDesc, {"minLod"}, [&] { dev.createSampler(SamplerDesc().setLodRange(2, 1)); }},
        {"maxAnisotropy below 1", kDesc, {"maxAnisotropy"}, [&] { SamplerDesc d; d.maxAnisotropy = 0.5f; dev.createSampler(d); }},
        {"maxAnisotropy above the limit", kDesc, {"maxSamplerAnisotropy"},
         [&] { SamplerDesc d; d.maxAnisotropy = limits.maxSamplerAnisotropy * 2; dev.createSampler(d); }},
        // ShaderDesc
        {"empty SPIR-V", kDesc, {"spirv"}, [&] { dev.createShader(ShaderDesc().setStage(ShaderStage::Vertex)); }},
        {"wrong entry point", kDesc, {"entry point", "nope"}, [&] {
             ShaderDesc d = ShaderDesc().setStage(ShaderStage::Vertex).setSpirv(janus::shaders::get("rt_vertex_color_vert"));
             d.entryPoint = "nope";
             dev.createShader(d);
         }},
        {"vertex SPIR-V declared a fragment shader", kDesc, {"entry point"},
         [&] { dev.createShader(ShaderDesc().setStage(ShaderStage::Fragment).setSpirv(janus::shaders::get("rt_vertex_color_vert"))); }},
        // GraphicsPipelineDesc
        {"pipeline without vertex shader", kDesc, {"vertexShader"}, [&] { auto d = pipelineDesc(); d.vertexShader = nullptr; dev.createGraphicsPipeline(d); }},
        {"pipeline without fragment shader", kDesc, {"fragmentShader"}, [&] { auto d = pipelineDesc(); d.fragmentShader = nullptr; dev.createGraphicsPipeline(d); }},
        {"shaders swapped", kDesc, {"vertexShader"}, [&] { auto d = pipelineDesc(); std::swap(d.vertexShader, d.fragmentShader); dev.createGraphicsPipeline(d); }},
        {"no colour and no depth format", kDesc, {"colorFormats"}, [&] {
             auto d = pipelineDesc(); d.colorFormats.clear(); d.blend.clear(); dev.createGraphicsPipeline(d); }},
        {"depthFormat that is a colour format", kDesc, {"depthFormat"}, [&] { dev.createGraphicsPipeline(pipelineDesc().setDepthFormat(Format::RGBA8_UNORM)); }},
        {"colour format that is a depth format", kDesc, {"colorFormats[1]"}, [&] { dev.createGraphicsPipeline(pipelineDesc().addColorFormat(Format::D32_FLOAT)); }},
        {"depth test without depthFormat", kDesc, {"depthFormat"}, [&] { dev.createGraphicsPipeline(pipelineDesc().setDepth({true, true, CompareOp::Less})); }},
        {"more blend states than colour formats", kDesc, {"blend"}, [&] { auto d = pipelineDesc(); d.blend.push_back({}); dev.createGraphicsPipeline(d); }},
        {"more colour formats than maxColorAttachments", kDesc, {"maxColorAttachments"}, [&] {
             auto d = pipelineDesc();
             for (uint32_t i = 0; i < limits.maxColorAttachments; ++i) d.addColorFormat(Format::RGBA8_UNORM);
             dev.createGraphicsPipeline(d);
         }},
        {"vertex attribute without a buffer layout", kDesc, {"slot 3"}, [&] {
             dev.createGraphicsPipeline(pipelineDesc().addVertexAttribute({2, VertexFormat::Float1, 3, 0})); }},
        {"vertex attribute outside the stride", kDesc, {"stride"}, [&] {
             auto d = pipelineDesc(); d.vertexAttributes[1].offset = sizeof(ColorVertex) - 4; dev.createGraphicsPipeline(d); }},
        {"vertex attribute location above the limit", kDesc, {"maxVertexAttributes"}, [&] {
             dev.createGraphicsPipeline(pipelineDesc().addVertexAttribute({limits.maxVertexAttributes, VertexFormat::Float1, 0, 0})); }},
        {"two attributes at one location", kDesc, {"location 1"}, [&] {
             dev.createGraphicsPipeline(pipelineDesc().addVertexAttribute({1, VertexFormat::Float1, 0, 0})); }},
        {"vertex buffer stride 0", kDesc, {"stride"}, [&] { auto d = pipelineDesc(); d.vertexBuffers[0].stride = 0; dev.createGraphicsPipeline(d); }},
        {"vertex buffer stride not a multiple of 4", kDesc, {"stride 34", "multiple of 4"}, [&] { auto d = pipelineDesc(); d.vertexBuffers[0].stride = 34; dev.createGraphicsPipeline(d); }},
        {"vertex attribute offset not a multiple of 4", kDesc, {"location 1", "offset 18", "multiple of 4"}, [&] {
             auto d = pipelineDesc(); d.vertexBuffers[0].stride = 36; d.vertexAttributes[1].offset = 18; dev.createGraphicsPipeline(d); }},
        {"vertex buffer slot twice", kDesc, {"slot 0"}, [&] { dev.createGraphicsPipeline(pipelineDesc().addVertexBuffer({0, 16, false})); }},
        {"shader input without attribute", kDesc, {"location 1"}, [&] {
             auto d = pipelineDesc(); d.vertexAttributes.pop_back(); dev.createGraphicsPipeline(d); }},
        {"integer attribute for a float input", kDesc, {"location 1"}, [&] {
             auto d = pipelineDesc(); d.vertexAttributes[1].format = VertexFormat::UInt1; dev.createGraphicsPipeline(d); }},
        {"blending an integer format", kUnsupported, {"r32ui", "blendable"}, [&] {
             auto d = pipelineDesc(); d.colorFormats[0] = Format::R32_UINT; d.blend[0] = BlendAttachment::additive(); dev.createGraphicsPipeline(d); }},
        // ComputePipelineDesc
        {"compute pipeline without shader", kDesc, {"computeShader"}, [&] { dev.createComputePipeline(ComputePipelineDesc()); }, Capability::Compute},
        {"compute pipeline with a vertex shader", kDesc, {"computeShader"},
         [&] { dev.createComputePipeline(ComputePipelineDesc().setShader(vs)); }, Capability::Compute},
        // BindingSetDesc
        {"binding twice", kDesc, {"twice"}, [&] {
             dev.createBindingSet(BindingSetDesc().add(BindingItem::uniformBuffer(0, uniforms)).add(BindingItem::uniformBuffer(0, uniforms))); }},
        {"uniform binding without buffer", kDesc, {"null"}, [&] { bindings(BindingItem::uniformBuffer(0, nullptr)); }},
        {"buffer without Uniform usage", kDesc, {"BufferUsage::Uniform"}, [&] { bindings(BindingItem::uniformBuffer(0, vertices)); }},
        {"uniform range outside the buffer", kDesc, {"outside"}, [&] { bindings(BindingItem::uniformBuffer(0, uniforms, 512, 1024)); }},
        {"misaligned uniform offset", kDesc, {"alignment"}, [&] { bindings(BindingItem::uniformBuffer(0, uniforms, 4, 16)); }},
        {"uniform range above maxUniformBufferRange", kDesc, {"range"}, [&] {
             bindings(BindingItem::uniformBuffer(0, createBuffer(BufferUsage::Uniform, limits.maxUniformBufferRange + 256))); }},
        {"texture without Sampled usage", kDesc, {"TextureUsage::Sampled"}, [&] { bindings(BindingItem::sampledTexture(0, small, nearest)); }},
        {"sampled texture without sampler", kDesc, {"sampler"}, [&] { bindings(BindingItem::sampledTexture(0, color, nullptr)); }},
        {"comparison sampler over a colour texture", kDesc, {"compare"}, [&] { bindings(BindingItem::sampledTexture(0, color, compare)); }},
        {"linear sampler over an integer texture", kUnsupported, {"r32ui", "filterable"},
         [&] { bindings(BindingItem::sampledTexture(0, uintTexture, linear)); }},
        {"view of a mip that does not exist", kDesc, {"binding 0", "baseMip 1"},
         [&] { bindings(BindingItem::sampledTexture(0, color, nearest).setMips(1, 1)); }},
        {"view of a 2D texture as a cube", kDesc, {"cannot be viewed as cube"},
         [&] { bindings(BindingItem::sampledTexture(0, color, nearest).setViewDimension(TextureDimension::TextureCube)); }},
        {"view of layers past an array's last", kDesc, {"count 3"},
         [&] { bindings(BindingItem::sampledTexture(0, array, nearest).setLayers(1, 3)); }},
        {"storage image without Storage usage", kDesc, {"TextureUsage::Storage"},
         [&] { bindings(BindingItem::storageImage(0, color)); }, Capability::StorageImages},
        // RenderPassDesc (messages name the attachment: colors[i] or depth)
        {"render pass without attachments", kDesc, {"RenderPassDesc"}, [&] { pass(RenderPassDesc()); }},
        {"attachment without RenderTarget usage", kDesc, {"RenderPassDesc colors[0]: ", "RenderTarget"}, [&] { pass(RenderPassDesc().addColor(Attachment::clear(sampledOnly))); }},
        {"depth texture as colour attachment", kDesc, {"depth"}, [&] { pass(RenderPassDesc().addColor(Attachment::clear(depth))); }},
        {"colour texture as depth attachment", kDesc, {"RenderPassDesc depth: ", "depth"}, [&] { pass(RenderPassDesc().setDepth(Attachment::clearDepthTo(color))); }},
        {"attachments of different sizes", kDesc, {"RenderPassDesc colors[1]: ", "same size"}, [&] {
             pass(RenderPassDesc().addColor(Attachment::clear(color)).addColor(Attachment::clear(small))); }},
        {"attachment mip that does not exist", kDesc, {"mip 1"}, [&] { pass(RenderPassDesc().addColor(Attachment::clear(color, {}, {1, 0}))); }},
        {"attachment layer past an array's last", kDesc, {"layer 3"},
         [&] { pass(RenderPassDesc().addColor(Attachment::clear(array, {}, {0, 3}))); }},
        // Clear values (Vulkan stored a depth of 2 or NaN, which it may not without
        // VK_EXT_depth_range_unrestricted; the backends converted -3 to an unsigned integer differently).
        {"clearDepth above 1", kDesc, {"RenderPassDesc depth: clearDepth"}, [&] { pass(RenderPassDesc().setDepth(Attachment::clearDepthTo(depth, 2.0f))); }},
        {"clearDepth NaN", kDesc, {"clearDepth"}, [&] { pass(RenderPassDesc().setDepth(Attachment::clearDepthTo(depth, NAN))); }},
        {"negative clear value of an unsigned integer texture", kDesc, {"clearColor", "r32ui"}, [&] {
             pass(RenderPassDesc().addColor(Attachment::clear(uintTarget, {-3, 0, 0, 0}))); }},
        {"clear value of an unsigned integer texture above 2^32", kDesc, {"clearColor"}, [&] {
             pass(RenderPassDesc().addColor(Attachment::clear(uintTarget, {5e9f, 0, 0, 0}))); }},
        {"attachment without texture", kDesc, {"RenderPassDesc colors[0]: ", "null"}, [&] { pass(RenderPassDesc().addColor(Attachment::clear(nullptr))); }},
        {"one subresource as two colour attachments", kDesc, {"colors[1]", "is colors[0] too"},
         [&] { pass(RenderPassDesc().addColor(Attachment::clear(array, {}, {0, 2})).addColor(Attachment::clear(array, {}, {0, 2}))); }},
        // Immediate transfers
        {"writeBuffer past the end", kUsage, {"writeBuffer"}, [&] { dev.writeBuffer(uniforms, bytes.data(), 64, 1000); }},
        {"writeBuffer without data", kUsage, {"null"}, [&] { dev.writeBuffer(uniforms, nullptr, 64); }},
        {"readBuffer from past the end", kUsage, {"readBuffer"}, [&] { dev.readBuffer(uniforms, 2048); }},
        {"writeTexture of the wrong size", kUsage, {"size"}, [&] { dev.writeTexture(color, {}, bytes.data(), 60); }},
        // Vulkan kept a depth of 2 (which it may not store without VK_EXT_depth_range_unrestricted), GL clamped it to 1.
        {"writeTexture of a depth above 1", kUsage, {"depth 2", "[0, 1]"}, [&] {
             std::vector<float> depths(16, 0.5f);
             depths[5] = 2.0f;
             dev.writeTexture(depth, {}, depths.data(), depths.size() * sizeof(float)); }},
        {"readTexture of a missing mip", kUsage, {"mip level 1"}, [&] { dev.readTexture(color, {1, 0}); }},
        {"readTexture of a missing layer", kUsage, {"layer 1"}, [&] { dev.readTexture(color, {0, 1}); }},
        {"readTexture of a missing array layer", kUsage, {"layer 3"}, [&] { dev.readTexture(array, {0, 3}); }},
        // Command list calls
        {"copyBuffer between overlapping ranges", kUsage, {"overlap"}, [&] { record([&](ICommandList& c) { c.copyBuffer(uniforms, 0, uniforms, 32, 64); }); }},
        {"copyBufferToTexture from a too small buffer", kUsage, {"copyBufferToTexture"}, [&] {
             BufferHandle tiny = createBuffer(BufferUsage::None, 16);   // the 4x4 rgba8 image needs 64
             record([&](ICommandList& c) { c.copyBufferToTexture(color, {}, tiny, 0); }); }},
        {"copyBufferToTexture at an unaligned offset", kUsage, {"texel size"}, [&] {
             record([&](ICommandList& c) { c.copyBufferToTexture(color, {}, uniforms, 2); }); }},
        {"copyTextureToBuffer of a missing layer", kUsage, {"layer"}, [&] {
             record([&](ICommandList& c) { c.copyTextureToBuffer(uniforms, 0, color, {0, 3}); }); }},
        {"copyTexture between formats", kUsage, {"rgba16f"}, [&] { record([&](ICommandList& c) { c.copyTexture(color, {}, other, {}); }); }},
        {"copyTexture between sizes", kUsage, {"sizes"}, [&] { record([&](ICommandList& c) { c.copyTexture(small, {}, color, {}); }); }},
        {"copyTexture onto itself", kUsage, {"same subresource"}, [&] { record([&](ICommandList& c) { c.copyTexture(color, {}, color, {}); }); }},
        {"generateMips of an integer format", kUnsupported, {"r32ui", "generate-mips"}, [&] {
             record([&](ICommandList& c) { c.generateMips(uintTexture); }); }},
        {"setBindingSet above the sets", kUsage, {"set 4"}, [&] {
             BindingSetHandle set = dev.createBindingSet(BindingSetDesc());
             record([&](ICommandList& c) { c.setBindingSet(kMaxBindingSets, set); }); }},
        {"setBindingSet with null", kUsage, {"null"}, [&] { record([&](ICommandList& c) { c.setBindingSet(0, nullptr); }); }},
        // Viewport and scissor (Vulkan used to pass NaN and out-of-range values to the driver and
        // accept them outside a pass; GL to reject only some of them).
        {"viewport minDepth NaN", kUsage, {"minDepth"}, [&] { inPass([&](ICommandList& c) { c.setViewport({0, 0, 4, 4, NAN, 1}); }); }},
        {"viewport maxDepth above 1", kUsage, {"maxDepth"}, [&] { inPass([&](ICommandList& c) { c.setViewport({0, 0, 4, 4, 0, 2}); }); }},
        {"viewport x NaN", kUsage, {"viewportBoundsRange"}, [&] { inPass([&](ICommandList& c) { c.setViewport({NAN, 0, 4, 4, 0, 1}); }); }},
        {"viewport past the bounds range", kUsage, {"viewportBoundsRange"}, [&] {
             inPass([&](ICommandList& c) { c.setViewport({limits.viewportBoundsRange[1], 0, 4, 4, 0, 1}); }); }},
        {"viewport wider than maxViewportSize", kUsage, {"maxViewportSize"}, [&] {
             inPass([&](ICommandList& c) { c.setViewport({0, 0, float(limits.maxViewportSize) * 2, 4, 0, 1}); }); }},
        {"viewport of infinite height", kUsage, {"maxViewportSize"}, [&] { inPass([&](ICommandList& c) { c.setViewport({0, 0, 4, INFINITY, 0, 1}); }); }},
        // GL (glViewport) and ES take whole pixels; Vulkan would keep the fraction: silently different images.
        {"viewport at a fractional x", kUsage, {"whole pixels"}, [&] { inPass([&](ICommandList& c) { c.setViewport({0.5f, 0, 4, 4, 0, 1}); }); }},
        {"viewport of fractional height", kUsage, {"whole pixels"}, [&] { inPass([&](ICommandList& c) { c.setViewport({0, 0, 4, 3.25f, 0, 1}); }); }},
        {"viewport outside a render pass", kUsage, {"setViewport", "beginRenderPass"}, [&] { record([&](ICommandList& c) { c.setViewport({0, 0, 4, 4, 0, 1}); }); }},
        {"scissor past INT32_MAX", kUsage, {"INT32_MAX"}, [&] { inPass([&](ICommandList& c) { c.setScissor({1, 0, 0x7fffffffu, 4}); }); }},
        {"scissor at a negative offset", kUsage, {"negative"}, [&] { inPass([&](ICommandList& c) { c.setScissor({-1, 0, 4, 4}); }); }},
        {"scissor outside a render pass", kUsage, {"setScissor", "beginRenderPass"}, [&] { record([&](ICommandList& c) { c.setScissor({0, 0, 4, 4}); }); }},
        // Vertex buffer slots (GL used to record any slot).
        {"setVertexBuffer above maxVertexBuffers", kUsage, {"slot"}, [&] {
             BufferHandle vb = createBuffer(BufferUsage::Vertex, 64);
             record([&](ICommandList& c) { c.setVertexBuffer(limits.maxVertexBuffers, vb); }); }},
        {"setVertexBuffer of a buffer without Vertex usage", kUsage, {"BufferUsage::Vertex"}, [&] {
             BufferHandle ib = createBuffer(BufferUsage::Index, 64);
             record([&](ICommandList& c) { c.setVertexBuffer(0, ib); }); }},
        {"setVertexBuffer past the buffer's end", kUsage, {"offset 64", "past the end"}, [&] {
             BufferHandle vb = createBuffer(BufferUsage::Vertex, 64);
             record([&](ICommandList& c) { c.setVertexBuffer(0, vb, 64); }); }},
        {"setVertexBuffer at an offset not a multiple of 4", kUsage, {"offset 6", "multiple of 4"}, [&] {
             BufferHandle vb = createBuffer(BufferUsage::Vertex, 64);
             record([&](ICommandList& c) { c.setVertexBuffer(0, vb, 6); }); }},
        {"setIndexBuffer of a buffer without Index usage", kUsage, {"BufferUsage::Index"}, [&] {
             BufferHandle vb = createBuffer(BufferUsage::Vertex, 64);
             record([&](ICommandList& c) { c.setIndexBuffer(vb, IndexType::UInt32); }); }},
        {"setIndexBuffer at a misaligned offset", kUsage, {"offset 2", "multiple of 4"}, [&] {
             BufferHandle ib = createBuffer(BufferUsage::Index, 64);
             record([&](ICommandList& c) { c.setIndexBuffer(ib, IndexType::UInt32, 2); }); }},
        // Timers: begun and ended once in one command list (GL used to accept each of these).
        {"endTimer without beginTimer", kUsage, {"beginTimer"}, [&] {
             TimerQueryHandle t = dev.createTimerQuery(); record([&](ICommandList& c) { c.endTimer(t); }); }, Capability::TimestampQueries},
        {"beginTimer twice", kUsage, {"already begun"}, [&] {
             TimerQueryHandle t = dev.createTimerQuery();
             record([&](ICommandList& c) { c.beginTimer(t); c.beginTimer(t); c.endTimer(t); }); }, Capability::TimestampQueries},
        {"endTimer twice", kUsage, {"already ended"}, [&] {
             TimerQueryHandle t = dev.createTimerQuery();
             record([&](ICommandList& c) { c.beginTimer(t); c.endTimer(t); c.endTimer(t); }); }, Capability::TimestampQueries},
        {"a timer begun in one list and ended in another", kUsage, {"beginTimer"}, [&] {
             TimerQueryHandle t = dev.createTimerQuery();
             record([&](ICommandList& c) { c.beginTimer(t); });
             record([&](ICommandList& c) { c.endTimer(t); }); }, Capability::TimestampQueries},
        {"dispatch above maxComputeWorkGroupCount", kUsage, {"maxComputeWorkGroupCount"}, [&] {
             record([&](ICommandList& c) { c.dispatch(limits.maxComputeWorkGroupCount[0] + 1); }); }, Capability::Compute},
    };

    size_t checked = 0;
    for (const Mistake& m : mistakes) {
        if (m.needs && !caps().has(*m.needs)) continue;
        ++checked;
        EXPECT_TRUE(throwsRhiError(m.make, m.code, m.mentions)) << m.what;
    }
    EXPECT_GE(checked, mistakes.size() - 5);
}

// Without a capability, the validation layer says which one, whatever the backend.
TEST_P(ValidationTest, IndependentBlendNeedsTheCapability) {
    GraphicsPipelineDesc desc;
    desc.setShaders(shader("rt_vertex_color_vert"), shader("rt_two_outputs_frag"))
        .addVertexBuffer({0, sizeof(ColorVertex), false})
        .addVertexAttribute({0, VertexFormat::Float4, 0, offsetof(ColorVertex, x)})
        .addVertexAttribute({1, VertexFormat::Float4, 0, offsetof(ColorVertex, r)})
        .addColorFormat(Format::RGBA8_UNORM, BlendAttachment::additive())
        .addColorFormat(Format::RGBA8_UNORM);
    if (caps().independentBlend) {
        EXPECT_TRUE(device().createGraphicsPipeline(desc));
        return;
    }
    EXPECT_TRUE(throwsRhiError([&] { device().createGraphicsPipeline(desc); }, ErrorCode::UnsupportedCapability,
                               {toString(Capability::IndependentBlend)}));
}

// Cube arrays and texture views: the validation layer names the missing capability for the
// texture, the shader and the binding alike, whatever the backend (gles has neither).
TEST_P(ValidationTest, CubeArraysAndTextureViewsNeedTheirCapabilities) {
    SamplerHandle sampler = nearestClampSampler();
    TextureHandle cube = device().createTexture(TextureDesc().setDimension(TextureDimension::TextureCube).setSize(4, 4));
    const std::vector<std::pair<Capability, std::function<void()>>> uses = {
        {Capability::CubeArrays, [&] {
             device().createTexture(TextureDesc().setDimension(TextureDimension::TextureCubeArray).setSize(4, 4).setArrayLayers(6)); }},
        {Capability::CubeArrays, [&] { shader("rt_sample_lookup_cube_array_frag"); }},
        {Capability::CubeArrays, [&] {
             device().createBindingSet(BindingSetDesc().add(
                 BindingItem::sampledTexture(1, cube, sampler).setViewDimension(TextureDimension::TextureCubeArray))); }},
        {Capability::TextureViews, [&] {
             device().createBindingSet(BindingSetDesc().add(
                 BindingItem::sampledTexture(1, cube, sampler).setLayers(2, 1).setViewDimension(TextureDimension::Texture2D))); }},
    };
    for (const auto& [cap, use] : uses) {
        if (caps().has(cap))
            EXPECT_NO_THROW(use()) << toString(cap);
        else
            EXPECT_TRUE(throwsRhiError(use, ErrorCode::UnsupportedCapability, {toString(cap)})) << toString(cap);
    }
}

}  // namespace
}  // namespace janus::rhi::test
