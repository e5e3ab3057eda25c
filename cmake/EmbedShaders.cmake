# shapespline_embed_shader(TARGET name SOURCE file.comp [DEFINES A=1 ...] [VARNAME var])
# Compiles GLSL to SPIR-V with glslangValidator at build time and writes a header
# (uint32_t array named VARNAME) into the build tree; never into the source tree.
function(shapespline_embed_shader)
  cmake_parse_arguments(ARG "" "TARGET;SOURCE;VARNAME;OUTPUT_NAME" "DEFINES;DEPENDS;INCLUDES" ${ARGN})
  get_filename_component(src "${ARG_SOURCE}" ABSOLUTE)
  if(NOT ARG_OUTPUT_NAME)
    get_filename_component(ARG_OUTPUT_NAME "${src}" NAME_WE)
  endif()
  if(NOT ARG_VARNAME)
    set(ARG_VARNAME "${ARG_OUTPUT_NAME}_spv")
  endif()
  set(out_dir "${CMAKE_BINARY_DIR}/gen/shaders")
  set(out "${out_dir}/${ARG_OUTPUT_NAME}.h")
  set(defs "")
  foreach(d IN LISTS ARG_DEFINES)
    list(APPEND defs "-D${d}")
  endforeach()
  foreach(d IN LISTS ARG_INCLUDES)
    list(APPEND defs "-I${d}")
  endforeach()
  add_custom_command(
    OUTPUT "${out}"
    COMMAND ${CMAKE_COMMAND} -E make_directory "${out_dir}"
    COMMAND ${GLSLANG_VALIDATOR} -V --target-env vulkan1.1 ${defs}
            -I${CMAKE_SOURCE_DIR}/shaders --vn ${ARG_VARNAME} -o "${out}" "${src}"
    DEPENDS "${src}" ${ARG_DEPENDS}
    COMMENT "glslang: ${ARG_OUTPUT_NAME}"
    VERBATIM)
  target_sources(${ARG_TARGET} PRIVATE "${out}")
  # Build tree only: the generated headers are private to the .cpp files of gpu/ and render/.
  target_include_directories(${ARG_TARGET} PUBLIC "$<BUILD_INTERFACE:${CMAKE_BINARY_DIR}/gen>")
endfunction()
