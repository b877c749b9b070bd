# Shaders used by the renderer.
janus_add_shader(janus_shaders NAME fullscreen_vert SOURCE ${CMAKE_CURRENT_LIST_DIR}/fullscreen.vert)
