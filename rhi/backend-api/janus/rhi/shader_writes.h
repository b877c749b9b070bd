// Which storage bindings a shader may write, the one rule both backends' hazard tracking reads
// from their SPIR-V reflection: a storage buffer or image counts as written unless the shader
// declares it `readonly` (SPIR-V NonWritable). A read-only binding counted as written costs a
// barrier per draw or dispatch that reads it (GL did so until session 27); a written one counted
// as read would miss a barrier.
#pragma once

#include <spirv_cross/spirv_cross.hpp>

namespace janus::rhi::detail {

// `resource` is one of the compiler's storage_buffers (storageBuffer) or storage_images.
inline bool shaderMayWrite(const spirv_cross::Compiler& compiler, const spirv_cross::Resource& resource, bool storageBuffer) {
    return storageBuffer ? !compiler.get_buffer_block_flags(resource.id).get(spv::DecorationNonWritable)
                         : !compiler.has_decoration(resource.id, spv::DecorationNonWritable);
}

}  // namespace janus::rhi::detail
