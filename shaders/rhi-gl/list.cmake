# Shaders the GL backend uses internally (rhi-gl/). Names start with gl_.
set(_gl ${CMAKE_CURRENT_LIST_DIR})
janus_add_shader(janus_shaders NAME gl_depth_copy_vert SOURCE ${_gl}/depth_copy.vert)
janus_add_shader(janus_shaders NAME gl_depth_copy_frag SOURCE ${_gl}/depth_copy.frag)
