# cmake -P script: install the build tree into WORK_DIR/prefix, configure + build + run the consumer,
# then build the examples (EXAMPLES_SOURCE_DIR) against the install as a user's project and run
# them, and build a project with a shader ES cannot compile, whose build must fail naming it.
file(REMOVE_RECURSE "${WORK_DIR}")
function(run_step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "step failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endfunction()
run_step(${CMAKE_COMMAND} --install "${JANUS_BUILD_DIR}" --prefix "${WORK_DIR}/prefix")
run_step(${CMAKE_COMMAND} -S "${CONSUMER_SOURCE_DIR}" -B "${WORK_DIR}/build" -G Ninja
         -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release)
run_step(${CMAKE_COMMAND} --build "${WORK_DIR}/build")
run_step("${WORK_DIR}/build/consumer")

# The examples, on their own against the install: janus_embed_shaders() and the installed
# janus_check_gl_shaders compile and check their shaders.
run_step(${CMAKE_COMMAND} -S "${EXAMPLES_SOURCE_DIR}" -B "${WORK_DIR}/examples" -G Ninja
         -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release)
run_step(${CMAKE_COMMAND} --build "${WORK_DIR}/examples")
run_step("${WORK_DIR}/examples/hello_rhi/hello_rhi" --validation)
run_step("${WORK_DIR}/examples/hello_rhi/hello_rhi" --path fallback --validation)
run_step("${WORK_DIR}/examples/render_scene/render_scene" --size 32 --out "${WORK_DIR}/render_scene")

# A shader the GL check rejects fails the user's build, saying which shader and why.
run_step(${CMAKE_COMMAND} -S "${CONSUMER_SOURCE_DIR}/bad_shader" -B "${WORK_DIR}/bad_shader" -G Ninja
         -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release)
execute_process(COMMAND ${CMAKE_COMMAND} --build "${WORK_DIR}/bad_shader" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0)
  message(FATAL_ERROR "bad_shader built, but its fragment shader reads a storage buffer, which ES 3.0 cannot:\n${out}\n${err}")
endif()
if(NOT "${out}${err}" MATCHES "reads_storage_frag \\(es300\\): glslang rejects")
  message(FATAL_ERROR "bad_shader failed to build, but not in the GL check naming its shader:\n${out}\n${err}")
endif()
message(STATUS "bad_shader: its build failed in the GL check, as it must")
