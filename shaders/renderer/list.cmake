# Shaders used by the renderer.
set(JANUS_RENDERER_SHADER_INCLUDES
  ${CMAKE_CURRENT_LIST_DIR}/forward_common.glsl ${CMAKE_CURRENT_LIST_DIR}/tonemap_common.glsl)
janus_add_shader(janus_shaders NAME fullscreen_vert SOURCE ${CMAKE_CURRENT_LIST_DIR}/fullscreen.vert)
janus_add_shader(janus_shaders NAME forward_vert SOURCE ${CMAKE_CURRENT_LIST_DIR}/forward.vert)
janus_add_shader(janus_shaders NAME forward_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/forward.frag)
janus_add_shader(janus_shaders NAME tonemap_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/tonemap.frag)
janus_add_shader(janus_shaders NAME tonemap_comp SOURCE ${CMAKE_CURRENT_LIST_DIR}/tonemap.comp)
