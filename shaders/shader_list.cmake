# Every shader Janus embeds. Each folder keeps its own list.
include(${CMAKE_CURRENT_LIST_DIR}/rhi-tests/list.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/renderer/list.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/rhi-gl/list.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/bench/list.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/ibl/sh.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/ibl/prefilter.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/ibl/sky.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/gi/list.cmake)
