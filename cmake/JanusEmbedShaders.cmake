# janus_embed_shaders(): your own GLSL shaders, compiled to SPIR-V and embedded in your program, for
# ShaderDesc::setSpirv. find_package(janus) provides it; so does Janus's own build (examples/).
#
#   janus_embed_shaders(<target>
#       SOURCES <file.vert|.frag|.comp>...   GLSL 450, Vulkan dialect (layout(set, binding))
#       [NAMESPACE <ns>]                     C++ namespace of the arrays (default: <target>_shaders)
#       [HEADER <name.h>]                    the header to include (default: <target>_shaders.h)
#       [DEFINES <NAME[=value]>...]          passed to glslang as -D
#       [INCLUDE_DIRS <dir>...]              #include search folders (the source's own is searched)
#       [NO_ES])                             not for GLES: skip the ESSL 300 check (compute never has it)
#
# Each SOURCE becomes `const uint32_t <ns>::<name>[]`, <name> being the file name with '.' as
# '_' (triangle.vert -> triangle_vert):
#
#   #include "app_shaders.h"
#   device.createShader(ShaderDesc().setStage(ShaderStage::Vertex).setSpirv(app_shaders::triangle_vert));
#
# The build checks what a GL driver would be given, as Janus checks its own shaders: every module is
# translated exactly as the GL backends translate it (GLSL 430, ESSL 300 unless NO_ES or compute,
# vertex shaders with and without clip control) and glslang's GLSL front end must parse and link
# each translation (janus_check_gl_shaders). A shader SPIRV-Cross cannot express for GL or ES, or
# whose translation another compiler would reject, fails your build instead of a user's run.
# Fragment shaders also get the derivative check (implicit derivatives after a discard or in
# divergent flow), as warnings in the build log. The translations are kept in
# <binary dir>/janus_shaders/<target>/<header name>/gl/ for reading.
#
# Variants: call it again for the same target with other DEFINES and another NAMESPACE and HEADER.
#
# Needs glslangValidator (Debian: glslang-tools).
#
# This file is also a script (cmake -P) that writes the header of one compiled module, so that each
# shader is compiled once: janus_add_shader (cmake/JanusShaders.cmake, Janus's own shaders) uses
# the same step.

# The header declaring `spirv_file`'s words as `const uint32_t <array>[]`. The file is read as
# little-endian words, as glslang writes it on the hosts Janus builds on (a module of the other
# endianness fails on its magic number here). Written under another name and renamed, so a build
# that stops half-way never leaves a truncated header behind.
function(_janus_write_spirv_header spirv_file header array)
  file(READ "${spirv_file}" hex HEX)
  string(LENGTH "${hex}" digits)
  math(EXPR remainder "${digits} % 8")
  if(digits EQUAL 0 OR NOT remainder EQUAL 0)
    message(FATAL_ERROR "${spirv_file}: not a SPIR-V module (${digits} hex digits, not whole 32-bit words)")
  endif()
  string(REGEX REPLACE "(..)(..)(..)(..)" "0x\\4\\3\\2\\1," words "${hex}")
  string(SUBSTRING "${words}" 0 10 magic)
  if(NOT magic STREQUAL "0x07230203")
    message(FATAL_ERROR "${spirv_file}: not a little-endian SPIR-V module (first word ${magic}, not 0x07230203)")
  endif()
  set(w "0x........,")   # eight words a line (CMake's regular expressions have no {8})
  string(REGEX REPLACE "(${w}${w}${w}${w}${w}${w}${w}${w})" "\\1\n" words "${words}")
  get_filename_component(spirv_name "${spirv_file}" NAME)
  file(WRITE "${header}.tmp" "// Generated from ${spirv_name} by JanusEmbedShaders.cmake. Do not edit.\n#pragma once\nconst uint32_t ${array}[] = {\n${words}\n};\n")
  file(RENAME "${header}.tmp" "${header}")
endfunction()

if(CMAKE_SCRIPT_MODE_FILE AND DEFINED JANUS_SPIRV_FILE)
  _janus_write_spirv_header("${JANUS_SPIRV_FILE}" "${JANUS_SPIRV_HEADER}" "${JANUS_SPIRV_ARRAY}")
  return()
endif()

include_guard(GLOBAL)

# Sets `out_var` to the custom-command steps that compile `src` once with glslang (its flags after
# `header array`) into `spv`, with a depfile of the files it #includes (`spv`.d), and write
# `header` from it, declaring `const uint32_t <array>[]`; and `out_var`_DEPENDS to what the command
# should also depend on (this file, which writes the header).
function(janus_glslang_steps out_var src spv header array)
  if(NOT JANUS_GLSLANG_VALIDATOR)
    find_program(JANUS_GLSLANG_VALIDATOR NAMES glslangValidator)
    if(NOT JANUS_GLSLANG_VALIDATOR)
      message(FATAL_ERROR "glslangValidator not found; install it (Debian: apt install glslang-tools) or set JANUS_GLSLANG_VALIDATOR")
    endif()
  endif()
  set(${out_var}
      COMMAND "${JANUS_GLSLANG_VALIDATOR}" -V --target-env vulkan1.2 ${ARGN} --depfile "${spv}.d" -o "${spv}" "${src}"
      COMMAND "${CMAKE_COMMAND}" "-DJANUS_SPIRV_FILE=${spv}" "-DJANUS_SPIRV_HEADER=${header}"
              "-DJANUS_SPIRV_ARRAY=${array}" -P "${CMAKE_CURRENT_FUNCTION_LIST_FILE}"
      PARENT_SCOPE)
  set(${out_var}_DEPENDS "${CMAKE_CURRENT_FUNCTION_LIST_FILE}" PARENT_SCOPE)
endfunction()

function(janus_embed_shaders target)
  cmake_parse_arguments(ARG "NO_ES" "NAMESPACE;HEADER" "SOURCES;DEFINES;INCLUDE_DIRS" ${ARGN})
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "janus_embed_shaders(${target}): unknown arguments ${ARG_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT TARGET ${target})
    message(FATAL_ERROR "janus_embed_shaders(${target}): no target named ${target}; call it after add_executable/add_library")
  endif()
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "janus_embed_shaders(${target}): no SOURCES given")
  endif()
  if(NOT ARG_NAMESPACE)
    set(ARG_NAMESPACE "${target}_shaders")
  endif()
  if(NOT ARG_HEADER)
    set(ARG_HEADER "${target}_shaders.h")
  endif()
  # The check tool: Janus's own target in its build tree, the installed one after find_package.
  if(TARGET janus_check_gl_shaders)
    set(check_tool janus_check_gl_shaders)
  elseif(TARGET janus::check_gl_shaders)
    set(check_tool janus::check_gl_shaders)
  else()
    message(FATAL_ERROR "janus_embed_shaders(${target}): janus::check_gl_shaders is missing; call find_package(janus) first")
  endif()

  # One folder per header: a second call with other DEFINES, NAMESPACE and HEADER embeds variants
  # of the same sources beside the first.
  get_filename_component(header_stem "${ARG_HEADER}" NAME_WE)
  set(outdir "${CMAKE_CURRENT_BINARY_DIR}/janus_shaders/${target}/${header_stem}")
  set(gldir "${outdir}/gl")
  set(flags "")
  foreach(d IN LISTS ARG_DEFINES)
    list(APPEND flags "-D${d}")
  endforeach()
  foreach(dir IN LISTS ARG_INCLUDE_DIRS)
    get_filename_component(dir "${dir}" ABSOLUTE)
    list(APPEND flags "-I${dir}")
  endforeach()
  set(es_flag "")
  if(ARG_NO_ES)
    set(es_flag "--no-es")
  endif()

  set(names "")
  set(outputs "")
  foreach(source IN LISTS ARG_SOURCES)
    get_filename_component(src "${source}" ABSOLUTE)
    get_filename_component(file_name "${src}" NAME)
    string(REPLACE "." "_" name "${file_name}")
    if(NOT name MATCHES "^[A-Za-z_][A-Za-z0-9_]*$")
      message(FATAL_ERROR "janus_embed_shaders(${target}): '${file_name}' does not make a C++ name (${name}); rename the file")
    endif()
    if(name IN_LIST names)
      message(FATAL_ERROR "janus_embed_shaders(${target}): two sources are named ${file_name}; their arrays would clash")
    endif()
    list(APPEND names "${name}")
    set(spv "${outdir}/${name}.spv")
    set(header "${outdir}/${name}.spv.h")
    set(checked "${gldir}/${name}.checked")
    janus_glslang_steps(compile "${src}" "${spv}" "${header}" "${name}" ${flags})
    add_custom_command(
      OUTPUT "${spv}" "${header}" "${checked}"
      COMMAND ${CMAKE_COMMAND} -E make_directory "${outdir}" "${gldir}"
      ${compile}
      COMMAND ${check_tool} --out "${gldir}" ${es_flag} "${spv}"
      COMMAND ${CMAKE_COMMAND} -E touch "${checked}"
      DEPENDS "${src}" "$<TARGET_FILE:${check_tool}>" ${compile_DEPENDS}
      # glslang's depfile lists the #included files, so editing one rebuilds its users.
      DEPFILE "${spv}.d"
      COMMENT "janus_embed_shaders: ${file_name} -> SPIR-V, GL translations checked"
      VERBATIM)
    list(APPEND outputs "${header}" "${checked}")
  endforeach()

  set(content "// Generated by janus_embed_shaders() for ${target}. Do not edit.\n")
  string(APPEND content "// SPIR-V for janus::rhi::ShaderDesc::setSpirv, one array per shader source.\n")
  string(APPEND content "#pragma once\n\n#include <cstdint>\n\nnamespace ${ARG_NAMESPACE} {\n")
  foreach(name IN LISTS names)
    string(APPEND content "#include \"${name}.spv.h\"\n")
  endforeach()
  string(APPEND content "}  // namespace ${ARG_NAMESPACE}\n")
  file(GENERATE OUTPUT "${outdir}/${ARG_HEADER}" CONTENT "${content}")

  target_sources(${target} PRIVATE ${outputs})
  target_include_directories(${target} PRIVATE "${outdir}")
endfunction()
