# JANUS_FUZZ_LOADER_SOURCES: the loader's sources, which the fuzz build (fuzz/CMakeLists.txt) compiles
# without the GPU half of the renderer: the renderer's scene/ and io/ folders (loadScene, the
# built-in scenes and the image readers), the scene file's "quality" keys' checks
# (forward/lighting_settings.cpp, the settings' names in core/settings.cpp; CPU only), and the GI
# bake file's reader (gi/gi_bake_file.cpp: `janus render --gi-bake` reads files from anywhere). Loading
# needs no device, and the fuzz build stays small and has no GPU header. Globbed, so a file added to
# the loader cannot leave that build unlinked (a hand-kept list missed irradiance_volume_scene.cpp).
# The main build's test link.loader_without_gpu_headers (tests/check_loader_headers.py) holds
# these files to including no RHI header, so the fuzz build, which CI does not run, keeps compiling.
set(janus_loader_src ${PROJECT_SOURCE_DIR}/renderer/src)
file(GLOB JANUS_FUZZ_LOADER_SOURCES CONFIGURE_DEPENDS ${janus_loader_src}/scene/*.cpp ${janus_loader_src}/io/*.cpp
  ${janus_loader_src}/forward/lighting_settings.cpp ${janus_loader_src}/core/settings.cpp ${janus_loader_src}/gi/gi_bake_file.cpp)
# io/parity.cpp judges rendered images and names the RHI's DeviceInfo: not the loader (its
# inclusion broke the fuzz build from b12f212 until session 28).
list(FILTER JANUS_FUZZ_LOADER_SOURCES EXCLUDE REGEX "/io/parity\\.cpp$")
