// Runtime backend choice.
#include "janus/rhi/backends.h"
#include "janus/rhi/driver_settings.h"

#include <fmt/format.h>

namespace janus::rhi {

std::unique_ptr<IDevice> createDevice(const DeviceDesc& desc) {
    if (desc.enableSynchronizationValidation && !desc.enableValidation)
        throw Error(ErrorCode::InvalidDescription,
                    "DeviceDesc::enableSynchronizationValidation needs enableValidation: synchronisation "
                    "validation is part of the validation layer; set both");
    // Checked on every backend, though only GL uses it: a GLPlatform(77) became EGL without a word.
    if (desc.glPlatform != GLPlatform::EGL && desc.glPlatform != GLPlatform::OSMesa)
        throw Error(ErrorCode::InvalidDescription,
                    fmt::format("DeviceDesc::glPlatform is {}, not a GLPlatform; use GLPlatform::EGL or GLPlatform::OSMesa",
                                int(desc.glPlatform)));
    detail::requestDriverSettings();   // before any driver starts: see driver_settings.cpp
    switch (desc.backend) {
        case Backend::Vulkan: return vulkan::createDevice(desc);
        case Backend::GL:
        case Backend::GLES: return gl::createDevice(desc);
    }
    throw Error(ErrorCode::InvalidDescription,
                fmt::format("DeviceDesc::backend is {}, not a known backend; use Backend::Vulkan, GL or GLES", int(desc.backend)));
}

std::vector<BackendProbe> probeBackends(GLPlatform glPlatform) {
    std::vector<BackendProbe> result;
    for (Backend b : {Backend::Vulkan, Backend::GL, Backend::GLES}) {
        BackendProbe probe{b};
        try {
            DeviceDesc desc;
            desc.backend = b;
            desc.glPlatform = glPlatform;
            createDevice(desc);
            probe.available = true;
        } catch (const std::exception& e) {
            probe.reason = e.what();
        }
        result.push_back(std::move(probe));
    }
    return result;
}

std::vector<EglDeviceListing> listEglDevices() { return gl::listEglDevices(); }

}  // namespace janus::rhi
