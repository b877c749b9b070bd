# The sky background (renderer/src/ibl/sky_background.cpp): a far-plane triangle after forward.
janus_add_shader(janus_shaders NAME sky_vert SOURCE ${CMAKE_CURRENT_LIST_DIR}/sky.vert)
janus_add_shader(janus_shaders NAME sky_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/sky.frag)
