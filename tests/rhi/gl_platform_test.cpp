// How the GL backend gets its context (rhi-gl/src/gl_platform.h): OSMesa loaded at run time and
// a clear error when it is missing; the EGL displays (surfaceless, device, default) and the
// JANUS_EGL_PLATFORM / JANUS_EGL_DEVICE choice. The platforms are driven directly, through the
// backend's internal Device constructor, so a test can ask for one display without the
// environment and for a library name that does not exist.
#include <EGL/egl.h>
#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <memory>
#include <regex>
#include <string>
#include <string_view>
#include <vector>

#include "backend_test.h"
#include "gl_device.h"
#include "gl_platform.h"

namespace janus::rhi::gl {
namespace {

using test::throwsRhiError;

bool clientExtension(std::string_view name) {
    const char* list = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!list) return false;
    std::string padded = " " + std::string(list) + " ";
    return padded.find(" " + std::string(name) + " ") != std::string::npos;
}

bool configurationSelected(const char* name) {
    for (const test::BackendConfig& config : test::allBackendConfigs())
        if (std::string_view(config.name) == name) return test::backendSelected(config);
    return false;
}

// Clears a 4x4 RGBA8 target through a render pass and reads it back: the context renders.
std::vector<std::byte> clearAndRead(IDevice& device, std::array<float, 4> color) {
    TextureHandle target = device.createTexture(
        TextureDesc().setFormat(Format::RGBA8_UNORM).setSize(4, 4).setUsage(TextureUsage::RenderTarget));
    CommandListHandle commands = device.createCommandList();
    commands->begin();
    commands->beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target, color)));
    commands->endRenderPass();
    commands->end();
    device.execute(commands);
    return device.readTexture(target, {});
}

// A GL or GLES device on the given EGL display, with debug output: it must start, render a clear
// exactly and report no debug message. Returns its DeviceInfo::platform.
std::string renderOnEglDisplay(Backend backend, const EglOptions& options) {
    const GLApi api = backend == Backend::GLES ? GLApi::ES30 : GLApi::DesktopCore43;
    DeviceDesc desc;
    desc.setBackend(backend).setEnableValidation(true);
    Device device(desc, createEglPlatform(api, true, options));
    const std::vector<std::byte> pixels = clearAndRead(device, {1.0f, 0.0f, 0.0f, 1.0f});
    EXPECT_EQ(pixels.size(), 4u * 4u * 4u);
    for (size_t i = 0; i + 3 < pixels.size(); i += 4) {
        EXPECT_EQ(uint8_t(pixels[i]), 255u);
        EXPECT_EQ(uint8_t(pixels[i + 1]), 0u);
        EXPECT_EQ(uint8_t(pixels[i + 3]), 255u);
    }
    for (const DebugMessage& message : device.takeDebugMessages()) ADD_FAILURE() << message.text;
    return device.info().platform;
}

// --- OSMesa --------------------------------------------------------------------------------------

TEST(OsmesaLoading, AMissingLibraryIsBackendUnavailableSayingWhatToInstall) {
    constexpr const char* kNames[] = {"libjanus-no-such-osmesa.so.8", "libjanus-no-such-osmesa.so"};
    EXPECT_TRUE(throwsRhiError([&] { loadOsmesa(kNames); }, ErrorCode::BackendUnavailable,
                               {"OSMesa is not installed", "libjanus-no-such-osmesa.so.8", "libjanus-no-such-osmesa.so:",
                                "install libosmesa6", "--gl-platform egl"}));
}

TEST(OsmesaLoading, ALibraryWithoutTheEntryPointsIsBackendUnavailable) {
    // libc loads, but is no OSMesa.
    constexpr const char* kNames[] = {"libc.so.6"};
    EXPECT_TRUE(throwsRhiError([&] { loadOsmesa(kNames); }, ErrorCode::BackendUnavailable,
                               {"libc.so.6 does not export OSMesaCreateContextAttribs", "install libosmesa6"}));
}

TEST(OsmesaLoading, TheInstalledLibraryLoadsAtRunTime) {
    if (!configurationSelected("gl_osmesa")) GTEST_SKIP() << "gl_osmesa is not in JANUS_TEST_BACKENDS";
    const OsmesaEntryPoints osmesa = loadOsmesa(kOsmesaLibraryNames);
    EXPECT_EQ(osmesa.libraryName, "libOSMesa.so.8");
    EXPECT_TRUE(osmesa.createContextAttribs && osmesa.destroyContext && osmesa.makeCurrent && osmesa.getCurrentContext &&
                osmesa.getProcAddress);
}

TEST(OsmesaLoading, GlesIsRefusedBeforeLookingForTheLibrary) {
    EXPECT_TRUE(throwsRhiError([] { createOsmesaPlatform(GLApi::ES30, false); }, ErrorCode::BackendUnavailable,
                               {"OpenGL ES"}));
}

// --- choosing the EGL display ------------------------------------------------------------------

TEST(EglOptions, EnvironmentValuesPickTheDisplay) {
    EXPECT_EQ(parseEglOptions(nullptr, nullptr).display, EglDisplayKind::Automatic);
    EXPECT_EQ(parseEglOptions("", "").display, EglDisplayKind::Automatic);
    EXPECT_EQ(parseEglOptions("surfaceless", nullptr).display, EglDisplayKind::Surfaceless);
    EXPECT_EQ(parseEglOptions("device", nullptr).display, EglDisplayKind::Device);
    EXPECT_FALSE(parseEglOptions("device", nullptr).deviceIndex.has_value());
    EXPECT_EQ(parseEglOptions("default", nullptr).display, EglDisplayKind::Default);

    // An index alone implies the device display.
    const EglOptions second = parseEglOptions(nullptr, "1");
    EXPECT_EQ(second.display, EglDisplayKind::Device);
    EXPECT_EQ(second.deviceIndex, 1u);
    EXPECT_EQ(parseEglOptions("device", "0").deviceIndex, 0u);
}

TEST(EglOptions, UnknownValuesAreBackendUnavailableNamingTheVariable) {
    EXPECT_TRUE(throwsRhiError([] { parseEglOptions("wayland", nullptr); }, ErrorCode::BackendUnavailable,
                               {"JANUS_EGL_PLATFORM='wayland'", "surfaceless, device or default"}));
    EXPECT_TRUE(throwsRhiError([] { parseEglOptions(nullptr, "99999999999"); }, ErrorCode::BackendUnavailable,
                               {"JANUS_EGL_DEVICE='99999999999'", "not a device index"}));
    EXPECT_TRUE(throwsRhiError([] { parseEglOptions("surfaceless", "0"); }, ErrorCode::BackendUnavailable,
                               {"JANUS_EGL_DEVICE=0", "JANUS_EGL_PLATFORM=surfaceless", "unset one"}));
    EXPECT_TRUE(throwsRhiError([] { parseEglOptions("default", "renderD128"); }, ErrorCode::BackendUnavailable,
                               {"JANUS_EGL_DEVICE=renderD128", "JANUS_EGL_PLATFORM=default", "unset one"}));
}

// Anything but digits is a name: which device has it, only EGL's device list can say.
TEST(EglOptions, ANameImpliesTheDeviceDisplay) {
    for (const char* name : {"renderD128", "/dev/dri/card1", "software", "first", "-1", "1x"}) {
        const EglOptions options = parseEglOptions(nullptr, name);
        EXPECT_EQ(options.display, EglDisplayKind::Device) << name;
        EXPECT_EQ(options.deviceName, name);
        EXPECT_FALSE(options.deviceIndex.has_value()) << name;
    }
    EXPECT_EQ(parseEglOptions("device", "card0").deviceName, "card0");
    EXPECT_EQ(parseEglOptions(nullptr, "2").deviceName, "") << "digits are an index";
}

TEST(EglOptions, ADeviceIsFoundByAnyOfItsNames) {
    const std::vector<std::vector<std::string>> devices = {
        {"/dev/dri/card0", "card0", "/dev/dri/renderD128", "renderD128"},
        {"/dev/dri/card1", "card1", "/dev/dri/renderD129", "renderD129"},
        {"software"}};
    EXPECT_EQ(eglDeviceNamed(devices, "/dev/dri/card1"), 1u);
    EXPECT_EQ(eglDeviceNamed(devices, "card1"), 1u);
    EXPECT_EQ(eglDeviceNamed(devices, "renderD128"), 0u);
    EXPECT_EQ(eglDeviceNamed(devices, "/dev/dri/renderD129"), 1u);
    EXPECT_EQ(eglDeviceNamed(devices, "software"), 2u);
    EXPECT_EQ(eglDeviceNamed(devices, "card2"), std::nullopt);
    EXPECT_EQ(eglDeviceNamed(devices, "card"), std::nullopt) << "whole names only";
    EXPECT_EQ(eglDeviceNamed(devices, "dri/card0"), std::nullopt) << "a path whole or a file name";
}

// --- the EGL displays, each forced ----------------------------------------------------------------

class EglDisplayTest : public testing::TestWithParam<Backend> {
protected:
    void SetUp() override {
        const char* configuration = GetParam() == Backend::GLES ? "gles" : "gl_egl";
        if (!configurationSelected(configuration)) GTEST_SKIP() << configuration << " is not in JANUS_TEST_BACKENDS";
    }
};

TEST_P(EglDisplayTest, SurfacelessDisplayRenders) {
    if (!clientExtension("EGL_MESA_platform_surfaceless"))
        GTEST_SKIP() << "this EGL does not offer EGL_MESA_platform_surfaceless";
    EXPECT_EQ(renderOnEglDisplay(GetParam(), {EglDisplayKind::Surfaceless, std::nullopt}), "egl (surfaceless)");
}

// Mesa lists a software device (EGL_MESA_device_software) even without a GPU, so this runs in CI.
TEST_P(EglDisplayTest, DeviceDisplayRendersAndIsNamed) {
    if (!(clientExtension("EGL_EXT_device_enumeration") || clientExtension("EGL_EXT_device_base")) ||
        !clientExtension("EGL_EXT_platform_device"))
        GTEST_SKIP() << "this EGL does not offer EGL_EXT_device_enumeration and EGL_EXT_platform_device";
    const std::string first = renderOnEglDisplay(GetParam(), {EglDisplayKind::Device, std::nullopt});
    EXPECT_TRUE(std::regex_match(first, std::regex(R"(egl \(device [0-9]+: .+\))"))) << first;
    // Asked for by index: device 0 is the first the automatic device search tries.
    const std::string byIndex = renderOnEglDisplay(GetParam(), {EglDisplayKind::Device, 0u});
    EXPECT_TRUE(byIndex.starts_with("egl (device 0: ")) << byIndex;
}

// Mesa's software device answers to "software" (the device list here has no other).
TEST_P(EglDisplayTest, ADeviceChosenByNameRendersOrIsUnavailableListingTheNames) {
    if (!(clientExtension("EGL_EXT_device_enumeration") || clientExtension("EGL_EXT_device_base")) ||
        !clientExtension("EGL_EXT_platform_device"))
        GTEST_SKIP() << "this EGL does not offer EGL_EXT_device_enumeration and EGL_EXT_platform_device";
    const GLApi api = GetParam() == Backend::GLES ? GLApi::ES30 : GLApi::DesktopCore43;
    EglOptions bogus{EglDisplayKind::Device, std::nullopt, "renderD999"};
    EXPECT_TRUE(throwsRhiError([&] { createEglPlatform(api, false, bogus); }, ErrorCode::BackendUnavailable,
                               {"JANUS_EGL_DEVICE='renderD999' names no EGL device", "by index and names: 0 ("}));
    const std::string first = renderOnEglDisplay(GetParam(), {EglDisplayKind::Device, 0u});
    if (first.find("software renderer") == std::string::npos) GTEST_SKIP() << "device 0 is " << first << ", not Mesa's software one";
    const std::string bySoftware = renderOnEglDisplay(GetParam(), {EglDisplayKind::Device, std::nullopt, "software"});
    EXPECT_TRUE(bySoftware.starts_with("egl (device ")) << bySoftware;
    EXPECT_NE(bySoftware.find("software renderer"), std::string::npos) << bySoftware;
}

// rhi::listEglDevices (what `janus info` shows): every device it lists is chosen by its index and
// by each of its names (a name two devices share chooses the first of them). A device whose
// driver gives this API no context (a display-only one) is unavailable either way.
TEST_P(EglDisplayTest, EveryListedDeviceIsChosenByItsIndexAndEachOfItsNames) {
    if (!(clientExtension("EGL_EXT_device_enumeration") || clientExtension("EGL_EXT_device_base")) ||
        !clientExtension("EGL_EXT_platform_device")) {
        EXPECT_TRUE(listEglDevices().empty()) << "devices listed where EGL cannot enumerate them";
        GTEST_SKIP() << "this EGL does not offer EGL_EXT_device_enumeration and EGL_EXT_platform_device";
    }
    const std::vector<EglDeviceListing> listed = listEglDevices();
    ASSERT_FALSE(listed.empty()) << "EGL enumerates devices but none is listed";
    std::vector<std::vector<std::string>> names;
    for (const EglDeviceListing& device : listed) names.push_back(device.names);
    const GLApi api = GetParam() == Backend::GLES ? GLApi::ES30 : GLApi::DesktopCore43;
    for (size_t i = 0; i < listed.size(); ++i) {
        SCOPED_TRACE(fmt::format("device {}", i));
        EXPECT_EQ(listed[i].index, i);
        bool starts = true;
        try {
            createEglPlatform(api, false, {EglDisplayKind::Device, uint32_t(i)});
        } catch (const Error& e) {
            starts = false;
            EXPECT_EQ(e.code(), ErrorCode::BackendUnavailable) << e.what();
        }
        const std::string prefix = fmt::format("egl (device {}: ", i);
        if (starts) {
            const std::string byIndex = renderOnEglDisplay(GetParam(), {EglDisplayKind::Device, uint32_t(i)});
            EXPECT_TRUE(byIndex.starts_with(prefix)) << byIndex;
        }
        for (const std::string& name : listed[i].names) {
            if (eglDeviceNamed(names, name) != uint32_t(i)) continue;   // an earlier device has it too
            if (starts) {
                const std::string byName = renderOnEglDisplay(GetParam(), {EglDisplayKind::Device, std::nullopt, name});
                EXPECT_TRUE(byName.starts_with(prefix)) << name << " started " << byName;
            } else {
                EXPECT_TRUE(throwsRhiError([&] { createEglPlatform(api, false, {EglDisplayKind::Device, std::nullopt, name}); },
                                           ErrorCode::BackendUnavailable, {}))
                    << name;
            }
        }
    }
}

TEST_P(EglDisplayTest, ADeviceIndexPastTheListIsBackendUnavailableSayingHowManyThereAre) {
    if (!(clientExtension("EGL_EXT_device_enumeration") || clientExtension("EGL_EXT_device_base")) ||
        !clientExtension("EGL_EXT_platform_device"))
        GTEST_SKIP() << "this EGL does not offer EGL_EXT_device_enumeration and EGL_EXT_platform_device";
    const GLApi api = GetParam() == Backend::GLES ? GLApi::ES30 : GLApi::DesktopCore43;
    EXPECT_TRUE(throwsRhiError([&] { createEglPlatform(api, false, {EglDisplayKind::Device, 4096u}); },
                               ErrorCode::BackendUnavailable, {"JANUS_EGL_DEVICE=4096", "EGL lists"}));
}

// The default display needs a window system on Mesa (none here), so it may or may not start;
// either it renders, or it says which display failed.
TEST_P(EglDisplayTest, DefaultDisplayRendersOrSaysWhy) {
    const GLApi api = GetParam() == Backend::GLES ? GLApi::ES30 : GLApi::DesktopCore43;
    try {
        createEglPlatform(api, false, {EglDisplayKind::Default, std::nullopt});
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::BackendUnavailable) << e.what();
        EXPECT_NE(std::string(e.what()).find("default display"), std::string::npos) << e.what();
        return;
    }
    EXPECT_EQ(renderOnEglDisplay(GetParam(), {EglDisplayKind::Default, std::nullopt}), "egl (default display)");
}

// Without a choice, Mesa's surfaceless display stays first, as it always was.
TEST_P(EglDisplayTest, AutomaticChoiceTakesSurfacelessWhereOffered) {
    if (!clientExtension("EGL_MESA_platform_surfaceless"))
        GTEST_SKIP() << "this EGL does not offer EGL_MESA_platform_surfaceless";
    EXPECT_EQ(renderOnEglDisplay(GetParam(), {}), "egl (surfaceless)");
}

INSTANTIATE_TEST_SUITE_P(GL, EglDisplayTest, testing::Values(Backend::GL, Backend::GLES),
                         [](const testing::TestParamInfo<Backend>& info) { return std::string(toString(info.param)); });

}  // namespace
}  // namespace janus::rhi::gl
