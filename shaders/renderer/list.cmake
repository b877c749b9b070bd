# Shaders used by the renderer.
janus_add_shader(janus_shaders NAME fullscreen_vert SOURCE ${CMAKE_CURRENT_LIST_DIR}/fullscreen.vert)
janus_add_shader(janus_shaders NAME forward_vert SOURCE ${CMAKE_CURRENT_LIST_DIR}/forward.vert)
# Compute path: light array and tile lists in storage buffers (no SSBOs on ES 3.0).
janus_add_shader(janus_shaders NAME forward_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/forward.frag NO_ES)
# Fallback path: the same words in integer textures (docs/LIGHTING.md).
janus_add_shader(janus_shaders NAME forward_textures_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/forward.frag DEFINES LIGHTS_IN_TEXTURES=1)
janus_add_shader(janus_shaders NAME depth_prepass_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/depth_prepass.frag)
janus_add_shader(janus_shaders NAME tile_heatmap_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/tile_heatmap.frag NO_ES)
janus_add_shader(janus_shaders NAME tile_heatmap_textures_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/tile_heatmap.frag DEFINES LIGHTS_IN_TEXTURES=1)
janus_add_shader(janus_shaders NAME tonemap_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/tonemap.frag)
janus_add_shader(janus_shaders NAME tonemap_comp SOURCE ${CMAKE_CURRENT_LIST_DIR}/tonemap.comp)
# Forward+ light culling (light_cull.comp and its shared math) and the directional shadow map.
include(${CMAKE_CURRENT_LIST_DIR}/culling.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/shadows.cmake)
