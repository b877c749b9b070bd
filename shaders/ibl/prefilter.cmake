# IBL: equirectangular sky -> cube map, and the GGX-prefiltered mips (renderer/src/ibl/,
# docs/IBL.md). Compute path: one dispatch per cube mip; fallback: one fullscreen draw per face.
janus_add_shader(janus_shaders NAME equirect_to_cube_comp SOURCE ${CMAKE_CURRENT_LIST_DIR}/equirect_to_cube.comp)
janus_add_shader(janus_shaders NAME equirect_to_cube_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/equirect_to_cube.frag)
janus_add_shader(janus_shaders NAME ggx_prefilter_comp SOURCE ${CMAKE_CURRENT_LIST_DIR}/ggx_prefilter.comp)
janus_add_shader(janus_shaders NAME ggx_prefilter_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/ggx_prefilter.frag)
