// Backend-neutral parts of the RHI: names, errors, capability checks.
#include "janus/rhi/rhi.h"

#include <fmt/format.h>

namespace janus::rhi {

const char* toString(ErrorCode code) {
    switch (code) {
        case ErrorCode::BackendUnavailable: return "BackendUnavailable";
        case ErrorCode::UnsupportedCapability: return "UnsupportedCapability";
        case ErrorCode::InvalidDescription: return "InvalidDescription";
        case ErrorCode::InvalidUsage: return "InvalidUsage";
        case ErrorCode::ShaderTranslation: return "ShaderTranslation";
        case ErrorCode::ShaderCompilation: return "ShaderCompilation";
        case ErrorCode::OutOfMemory: return "OutOfMemory";
        case ErrorCode::DeviceLost: return "DeviceLost";
    }
    return "Unknown";
}

Error::Error(ErrorCode code, const std::string& message)
    : std::runtime_error(std::string(toString(code)) + ": " + message), m_code(code) {}

const char* toString(Backend backend) {
    switch (backend) {
        case Backend::Vulkan: return "vulkan";
        case Backend::GL: return "gl";
        case Backend::GLES: return "gles";
    }
    return "unknown";
}

std::optional<Backend> parseBackend(std::string_view name) {
    for (Backend b : {Backend::Vulkan, Backend::GL, Backend::GLES})
        if (name == toString(b)) return b;
    return std::nullopt;
}

const char* toString(GLPlatform platform) {
    return platform == GLPlatform::EGL ? "egl" : "osmesa";
}

std::optional<GLPlatform> parseGLPlatform(std::string_view name) {
    if (name == "egl") return GLPlatform::EGL;
    if (name == "osmesa") return GLPlatform::OSMesa;
    return std::nullopt;
}

const char* toString(Capability cap) {
    switch (cap) {
        case Capability::Compute: return "compute";
        case Capability::StorageBuffers: return "storage-buffers";
        case Capability::StorageImages: return "storage-images";
        case Capability::RenderToVolumeSlice: return "render-to-3d-slice";
        case Capability::RenderToCubeFaceMip: return "render-to-cube-face-mip";
        case Capability::FloatRenderTargets: return "float-render-targets";
        case Capability::FloatBlend: return "float32-blend";
        case Capability::TimestampQueries: return "timestamp-queries";
        case Capability::IndependentBlend: return "independent-blend";
        case Capability::CubeArrays: return "cube-arrays";
        case Capability::TextureViews: return "texture-views";
        case Capability::ConcurrentDeviceCalls: return "concurrent-device-calls";
    }
    return "unknown";
}

bool Capabilities::has(Capability cap) const {
    switch (cap) {
        case Capability::Compute: return compute;
        case Capability::StorageBuffers: return storageBuffers;
        case Capability::StorageImages: return storageImages;
        case Capability::RenderToVolumeSlice: return renderToVolumeSlice;
        case Capability::RenderToCubeFaceMip: return renderToCubeFaceMip;
        case Capability::FloatRenderTargets: return floatRenderTargets;
        case Capability::FloatBlend: return floatBlend;
        case Capability::TimestampQueries: return timestampQueries;
        case Capability::IndependentBlend: return independentBlend;
        case Capability::CubeArrays: return cubeArrays;
        case Capability::TextureViews: return textureViews;
        case Capability::ConcurrentDeviceCalls: return concurrentDeviceCalls;
    }
    return false;
}

void IDevice::require(Capability cap, std::string_view what) const {
    if (!capabilities().has(cap))
        throw Error(ErrorCode::UnsupportedCapability,
                    fmt::format("{} needs capability '{}', which the {} backend does not have; "
                                "use the fallback path or another backend",
                                what, toString(cap), toString(info().backend)));
}

const char* toString(TextureDimension dim) {
    switch (dim) {
        case TextureDimension::Texture2D: return "2d";
        case TextureDimension::Texture3D: return "3d";
        case TextureDimension::TextureCube: return "cube";
        case TextureDimension::Texture2DArray: return "2d-array";
        case TextureDimension::TextureCubeArray: return "cube-array";
    }
    return "unknown";
}

uint32_t textureLayerCount(const TextureDesc& desc) {
    switch (desc.dimension) {
        case TextureDimension::Texture2D: return 1;
        case TextureDimension::Texture3D: return desc.depth;
        case TextureDimension::TextureCube: return 6;
        case TextureDimension::Texture2DArray:
        case TextureDimension::TextureCubeArray: return desc.arrayLayers;
    }
    return 1;
}

const char* toString(ShaderStage stage) {
    switch (stage) {
        case ShaderStage::Vertex: return "vertex";
        case ShaderStage::Fragment: return "fragment";
        case ShaderStage::Compute: return "compute";
    }
    return "unknown";
}

uint32_t vertexFormatSize(VertexFormat f) {
    switch (f) {
        case VertexFormat::Float1: return 4;
        case VertexFormat::Float2: return 8;
        case VertexFormat::Float3: return 12;
        case VertexFormat::Float4: return 16;
        case VertexFormat::UByte4Norm: return 4;
        case VertexFormat::UInt1: return 4;
    }
    return 0;
}

}  // namespace janus::rhi
