# IBL: equirectangular sky -> cube map, and the GGX-prefiltered mips (renderer/src/ibl/,
# docs/IBL.md). Compute path: one dispatch per cube mip; fallback: one fullscreen draw per face.
janus_add_shader(janus_shaders NAME equirect_to_cube_comp SOURCE ${CMAKE_CURRENT_LIST_DIR}/equirect_to_cube.comp)
janus_add_shader(janus_shaders NAME equirect_to_cube_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/equirect_to_cube.frag)
janus_add_shader(janus_shaders NAME ggx_prefilter_comp SOURCE ${CMAKE_CURRENT_LIST_DIR}/ggx_prefilter.comp)
janus_add_shader(janus_shaders NAME ggx_prefilter_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/ggx_prefilter.frag)
# The bright-texel variant of the prefilter (reads the rest cube and adds the listed texels), and its
# two passes: the split (one dispatch | one draw per face) and the list (one dispatch | one draw).
janus_add_shader(janus_shaders NAME ggx_prefilter_bright_comp SOURCE ${CMAKE_CURRENT_LIST_DIR}/ggx_prefilter.comp DEFINES JANUS_IBL_PREFILTER_BRIGHT=1)
janus_add_shader(janus_shaders NAME ggx_prefilter_bright_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/ggx_prefilter.frag DEFINES JANUS_IBL_PREFILTER_BRIGHT=1)
janus_add_shader(janus_shaders NAME ggx_bright_split_comp SOURCE ${CMAKE_CURRENT_LIST_DIR}/ggx_bright_split.comp)
janus_add_shader(janus_shaders NAME ggx_bright_split_vert SOURCE ${CMAKE_CURRENT_LIST_DIR}/ggx_bright_split.vert)
janus_add_shader(janus_shaders NAME ggx_bright_split_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/ggx_bright_split.frag)
janus_add_shader(janus_shaders NAME ggx_bright_list_comp SOURCE ${CMAKE_CURRENT_LIST_DIR}/ggx_bright_list.comp)
janus_add_shader(janus_shaders NAME ggx_bright_list_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/ggx_bright_list.frag)
