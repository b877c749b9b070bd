// NVIDIA's GL driver applies its "image settings" to every texture lookup: 1 "quality" by
// default, whose filtering optimisations shorten the blend between mip levels, or 0 "high
// quality" without them; its Vulkan driver filters as the lookup asks. On an H200 (driver 580)
// gl and gles then differed from vulkan only in minified texture detail (docs/TESTING.md, "On a
// GPU machine"). Janus's promise is that the backends agree, so it asks for high quality, unless
// the environment already chose: a user's value is left as it is, and DeviceInfo::driverSettings
// says which it was.
//
// The driver reads the variable when it starts, which can be when the process's first device of
// any backend does (NVIDIA's Vulkan driver loads the same core library as its GL driver), so the
// device factory calls requestDriverSettings() before any backend. setenv() is not safe while
// another thread reads the environment: the first device should be made before such threads run.
#include "janus/rhi/driver_settings.h"

#include <cstdlib>

#include <fmt/format.h>

namespace janus::rhi::detail {

namespace {
constexpr const char* kImageSettingsVariable = "__GL_OpenGLImageSettings";
constexpr const char* kHighQuality = "0";

const char* describeImageSettings(const std::string& value) {
    if (value == "0") return "high quality";
    if (value == "1") return "quality, the driver's default";
    if (value == "2") return "performance";
    if (value == "3") return "high performance";
    return "not a value the driver documents";
}
}  // namespace

GLImageSettings chooseGLImageSettings(const char* environmentValue) {
    if (environmentValue && *environmentValue) return {environmentValue, false};
    return {kHighQuality, true};
}

const GLImageSettings& requestDriverSettings() {
    static const GLImageSettings settings = [] {
        GLImageSettings chosen = chooseGLImageSettings(std::getenv(kImageSettingsVariable));
        if (chosen.setByJanus) ::setenv(kImageSettingsVariable, chosen.value.c_str(), /*overwrite=*/0);
        return chosen;
    }();   // thread-safe once: a static's initialisation
    return settings;
}

std::string glDriverSettingsNote(const std::string& vendor) {
    if (vendor.find("NVIDIA") == std::string::npos) return {};
    const GLImageSettings& settings = requestDriverSettings();
    return fmt::format("image settings {} ({}; {}={}, {})", settings.value, describeImageSettings(settings.value),
                       kImageSettingsVariable, settings.value,
                       settings.setByJanus ? "set by Janus so that GL filters as Vulkan does" : "from the environment");
}

}  // namespace janus::rhi::detail
