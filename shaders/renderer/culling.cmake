# Light culling shaders (see docs/LIGHTING.md). Compute only: never built for ES.
janus_add_shader(janus_shaders NAME light_cull_comp SOURCE ${CMAKE_CURRENT_LIST_DIR}/light_cull.comp)
