# Probe GI (renderer/src/gi/, docs/GI.md): the bake's G-buffer and the two relight passes.
janus_add_shader(janus_shaders NAME gi_gbuffer_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/gi_gbuffer.frag)
janus_add_shader(janus_shaders NAME gi_brick_radiance_comp SOURCE ${CMAKE_CURRENT_LIST_DIR}/gi_brick_radiance.comp NO_ES)
janus_add_shader(janus_shaders NAME gi_brick_radiance_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/gi_brick_radiance.frag DEFINES LIGHTS_IN_TEXTURES=1)
janus_add_shader(janus_shaders NAME gi_probe_sh_comp SOURCE ${CMAKE_CURRENT_LIST_DIR}/gi_probe_sh.comp NO_ES)
janus_add_shader(janus_shaders NAME gi_probe_sh_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/gi_probe_sh.frag)
# --debug gi: the probes as spheres (renderer/src/debug_views/gi_probe_view.*).
janus_add_shader(janus_shaders NAME gi_probe_view_vert SOURCE ${CMAKE_CURRENT_LIST_DIR}/gi_probe_view.vert)
janus_add_shader(janus_shaders NAME gi_probe_view_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/gi_probe_view.frag)
