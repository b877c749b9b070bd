// The driver settings Janus asks for before any device starts (rhi/src/driver_settings.cpp).
#include <cstdlib>
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "janus/rhi/driver_settings.h"
#include "janus/rhi/rhi.h"

namespace janus::rhi {
namespace {

TEST(DriverSettingsTest, AsksForHighQualityFilteringWhenTheEnvironmentDidNotChoose) {
    for (const char* unset : {static_cast<const char*>(nullptr), ""}) {
        const detail::GLImageSettings chosen = detail::chooseGLImageSettings(unset);
        EXPECT_EQ(chosen.value, "0");
        EXPECT_TRUE(chosen.setByJanus);
    }
}

TEST(DriverSettingsTest, LeavesAUsersChoiceAlone) {
    const detail::GLImageSettings chosen = detail::chooseGLImageSettings("3");
    EXPECT_EQ(chosen.value, "3");
    EXPECT_FALSE(chosen.setByJanus);
}

// The variable as the process started, before any test made a device.
const char* const kAtStart = [] {
    const char* value = std::getenv("__GL_OpenGLImageSettings");
    return value ? strdup(value) : nullptr;   // kept for the process's life
}();

// After a device of any backend, the variable holds what was chosen: the driver reads it when it
// starts, which may be with the first device of any backend. rhi.DriverSettingsKeepTheEnvironments
// runs this with the variable set.
TEST(DriverSettingsTest, TheEnvironmentHoldsTheChoiceOnceADeviceWasMade) {
    try {
        createDevice(DeviceDesc().setBackend(Backend::Vulkan));
    } catch (const Error&) {
        // No Vulkan here: the factory asked before trying the backend, which is what is checked.
    }
    const char* environment = std::getenv("__GL_OpenGLImageSettings");   // before asking again below
    ASSERT_NE(environment, nullptr) << "createDevice() did not set the variable before the backend started";
    const detail::GLImageSettings& settings = detail::requestDriverSettings();
    EXPECT_EQ(settings.value, environment);
    if (kAtStart && *kAtStart) {
        EXPECT_EQ(settings.value, kAtStart);
        EXPECT_FALSE(settings.setByJanus);
    } else {
        EXPECT_EQ(settings.value, "0");
        EXPECT_TRUE(settings.setByJanus);
    }
}

TEST(DriverSettingsTest, OnlyNvidiasGLDriverGetsANote) {
    EXPECT_EQ(detail::glDriverSettingsNote("Mesa"), "");
    const std::string note = detail::glDriverSettingsNote("NVIDIA Corporation");
    EXPECT_NE(note.find("image settings " + detail::requestDriverSettings().value), std::string::npos) << note;
    EXPECT_NE(note.find("__GL_OpenGLImageSettings"), std::string::npos) << note;
}

}  // namespace
}  // namespace janus::rhi
