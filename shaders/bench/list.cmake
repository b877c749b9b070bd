# Shaders of the RHI overhead benchmark (bench/). Names start with bench_.
set(_bench ${CMAKE_CURRENT_LIST_DIR})
janus_add_shader(janus_shaders NAME bench_triangle_vert SOURCE ${_bench}/triangle.vert)
janus_add_shader(janus_shaders NAME bench_uniform_color_frag SOURCE ${_bench}/uniform_color.frag)
janus_add_shader(janus_shaders NAME bench_increment_comp SOURCE ${_bench}/increment.comp)
