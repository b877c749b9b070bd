# Shaders used by the renderer.
janus_add_shader(janus_shaders NAME fullscreen_vert SOURCE ${CMAKE_CURRENT_LIST_DIR}/fullscreen.vert)
janus_add_shader(janus_shaders NAME forward_vert SOURCE ${CMAKE_CURRENT_LIST_DIR}/forward.vert)
janus_add_shader(janus_shaders NAME forward_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/forward.frag)
janus_add_shader(janus_shaders NAME tonemap_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/tonemap.frag)
janus_add_shader(janus_shaders NAME tonemap_comp SOURCE ${CMAKE_CURRENT_LIST_DIR}/tonemap.comp)
# Forward+ light culling (light_cull.comp and its shared math) and the directional shadow map.
include(${CMAKE_CURRENT_LIST_DIR}/culling.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/shadows.cmake)
