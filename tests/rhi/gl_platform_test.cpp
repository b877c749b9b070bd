// How the GL backend gets its context (rhi-gl/src/gl_platform.h): OSMesa loaded at run time and
// a clear error when it is missing. The loader is called directly, so a test can ask for a
// library name that does not exist.
#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "backend_test.h"
#include "gl_platform.h"

namespace janus::rhi::gl {
namespace {

using test::throwsRhiError;

bool configurationSelected(const char* name) {
    for (const test::BackendConfig& config : test::allBackendConfigs())
        if (std::string_view(config.name) == name) return test::backendSelected(config);
    return false;
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
    EXPECT_TRUE(osmesa.createContextAttribs && osmesa.destroyContext && osmesa.makeCurrent && osmesa.getProcAddress);
}

TEST(OsmesaLoading, GlesIsRefusedBeforeLookingForTheLibrary) {
    EXPECT_TRUE(throwsRhiError([] { createOsmesaPlatform(GLApi::ES30, false); }, ErrorCode::BackendUnavailable,
                               {"OpenGL ES"}));
}

}  // namespace
}  // namespace janus::rhi::gl
