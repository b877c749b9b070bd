# Shaders used by the renderer.
janus_add_shader(janus_shaders NAME fullscreen_vert SOURCE ${CMAKE_CURRENT_LIST_DIR}/fullscreen.vert)
janus_add_shader(janus_shaders NAME forward_vert SOURCE ${CMAKE_CURRENT_LIST_DIR}/forward.vert)
# Compute path: light array and tile lists in storage buffers (no SSBOs on ES 3.0).
janus_add_shader(janus_shaders NAME forward_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/forward.frag NO_ES)
# The same for a compute-capable device without cube arrays: two probe cubes (probe_access.glsl).
janus_add_shader(janus_shaders NAME forward_cubes_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/forward.frag DEFINES PROBES_AS_CUBES=1 NO_ES)
# Fallback path: the same words in integer textures (docs/LIGHTING.md).
# Both sample reflection probes from a cube array (no cube arrays on ES 3.0: NO_ES)...
janus_add_shader(janus_shaders NAME forward_textures_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/forward.frag DEFINES LIGHTS_IN_TEXTURES=1 NO_ES)
# ...and devices without cube arrays (GLES 3.0) bind two probe cubes (probe_access.glsl).
janus_add_shader(janus_shaders NAME forward_textures_cubes_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/forward.frag
                 DEFINES LIGHTS_IN_TEXTURES=1 PROBES_AS_CUBES=1)
janus_add_shader(janus_shaders NAME depth_prepass_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/depth_prepass.frag)
janus_add_shader(janus_shaders NAME tile_heatmap_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/tile_heatmap.frag NO_ES)
janus_add_shader(janus_shaders NAME tile_heatmap_textures_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/tile_heatmap.frag DEFINES LIGHTS_IN_TEXTURES=1)
janus_add_shader(janus_shaders NAME tonemap_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/tonemap.frag)
janus_add_shader(janus_shaders NAME tonemap_comp SOURCE ${CMAKE_CURRENT_LIST_DIR}/tonemap.comp)
# Forward+ light culling (light_cull.comp and its shared math) and the directional shadow map.
include(${CMAKE_CURRENT_LIST_DIR}/culling.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/shadows.cmake)
# Mesh deformation (skins, morph targets): compute path, and the fallback's point pass.
janus_add_shader(janus_shaders NAME deform_comp SOURCE ${CMAKE_CURRENT_LIST_DIR}/deform.comp NO_ES)
janus_add_shader(janus_shaders NAME deform_points_vert SOURCE ${CMAKE_CURRENT_LIST_DIR}/deform_points.vert)
janus_add_shader(janus_shaders NAME deform_points_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/deform_points.frag)
