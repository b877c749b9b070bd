# L2 spherical-harmonic irradiance (renderer/src/ibl/sh_irradiance.cpp; basis in sh_common.glsl).
# Compute path: per-tile projection with a shared-memory reduction, then the sum of the partials.
janus_add_shader(janus_shaders NAME sh_project_comp SOURCE ${CMAKE_CURRENT_LIST_DIR}/sh_project.comp)
janus_add_shader(janus_shaders NAME sh_reduce_comp SOURCE ${CMAKE_CURRENT_LIST_DIR}/sh_reduce.comp)
# Fallback path (GLES: no compute): a two-level fragment-shader gather into RGBA32F targets.
janus_add_shader(janus_shaders NAME sh_gather_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/sh_gather.frag)
janus_add_shader(janus_shaders NAME sh_gather_final_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/sh_gather_final.frag)
