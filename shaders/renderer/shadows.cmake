# Directional shadow map shaders (renderer/src/shadows/shadow_map.cpp; lookups in shadow_sampling.glsl).
janus_add_shader(janus_shaders NAME shadow_vert SOURCE ${CMAKE_CURRENT_LIST_DIR}/shadow.vert)
janus_add_shader(janus_shaders NAME shadow_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/shadow.frag)
# Only for tests/renderer/shadow_map_test.cpp: runs sampleShadowPCF on chosen world points.
janus_add_shader(janus_shaders NAME shadow_sampling_test_frag SOURCE ${CMAKE_CURRENT_LIST_DIR}/shadow_sampling_test.frag)
