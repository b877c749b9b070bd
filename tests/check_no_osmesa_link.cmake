# Fails when a binary needs libOSMesa at load time (a NEEDED entry in its dynamic section). The GL
# backend opens OSMesa with dlopen only when --gl-platform osmesa asks for it, so that janus starts
# on machines without OSMesa (and the LLVM it pulls in): issue 10, rhi-gl/src/gl_platform_osmesa.cpp.
#   cmake -DREADELF=<readelf> -DBINARIES="<file>;<file>..." -P check_no_osmesa_link.cmake
if(NOT READELF OR NOT BINARIES)
  message(FATAL_ERROR "usage: cmake -DREADELF=<readelf> -DBINARIES=<files> -P check_no_osmesa_link.cmake")
endif()
foreach(binary IN LISTS BINARIES)
  execute_process(COMMAND ${READELF} --dynamic ${binary} OUTPUT_VARIABLE dynamic RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${READELF} --dynamic ${binary} failed (${rc})")
  endif()
  string(REGEX MATCHALL "\\(NEEDED\\)[^\n]*" needed "${dynamic}")
  # The check must see the dynamic section: every binary links EGL (janus_rhi_gl) directly.
  if(NOT needed MATCHES "libEGL")
    message(FATAL_ERROR "${binary}: no NEEDED entry for libEGL found, so this check reads nothing:\n${dynamic}")
  endif()
  if(needed MATCHES "libOSMesa")
    string(REPLACE ";" "\n" lines "${needed}")
    message(FATAL_ERROR "${binary} needs libOSMesa at load time; it must be opened with dlopen only "
                        "(rhi-gl/src/gl_platform_osmesa.cpp):\n${lines}")
  endif()
  message(STATUS "${binary}: no libOSMesa among its NEEDED libraries")
endforeach()
