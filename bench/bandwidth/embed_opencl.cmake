# Turns an OpenCL C source into a C++ string constant with every `#include "..."` inlined, so the program builds
# its kernels at run time without looking for files. <system> includes are left alone (OpenCL has none); a
# header is inlined each time it is included (include guards do their usual job, X-macro lists still work).
#   cmake -DSOURCE=a.cl -DOUTPUT=a_source.cpp -DNAME=identifier -DINCLUDE_DIRS="d1;d2" [-DROOT=dir] [-DDEPFILE=a.d]
#         -P embed_opencl.cmake
# #line directives name files relative to ROOT so compiler messages point at the sources.
# The generated file defines `extern const char* const prism::opencl_source::<NAME>;`.
cmake_minimum_required(VERSION 3.25)

set(all_files)
# CMake lists split on ';' and treat '[' ']' specially: hide them while the text is handled line by line.
set(semicolon "<prism-semicolon>")
set(open_bracket "<prism-open-bracket>")
set(close_bracket "<prism-close-bracket>")

function(inline_file path stack result)
  list(FIND stack "${path}" on_stack)
  if(NOT on_stack EQUAL -1)
    message(FATAL_ERROR "${path}: #include cycle (${stack})")
  endif()
  list(APPEND stack "${path}")
  list(APPEND all_files "${path}")
  get_filename_component(dir "${path}" DIRECTORY)
  set(shown "${path}")
  if(DEFINED ROOT)
    file(RELATIVE_PATH shown "${ROOT}" "${path}")
  endif()
  file(READ "${path}" content)
  string(REPLACE ";" "${semicolon}" content "${content}")
  string(REPLACE "[" "${open_bracket}" content "${content}")
  string(REPLACE "]" "${close_bracket}" content "${content}")
  string(REPLACE "\n" ";" lines "${content}")
  set(text "#line 1 \"${shown}\"\n")
  set(number 0)
  foreach(line IN LISTS lines)
    math(EXPR number "${number} + 1")
    if(line MATCHES "^[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\"")
      set(name "${CMAKE_MATCH_1}")
      set(found)
      foreach(candidate_dir IN LISTS dir INCLUDE_DIRS)
        if(EXISTS "${candidate_dir}/${name}")
          get_filename_component(found "${candidate_dir}/${name}" ABSOLUTE)
          break()
        endif()
      endforeach()
      if(NOT found)
        message(FATAL_ERROR "${path}:${number}: cannot find \"${name}\" (searched ${dir};${INCLUDE_DIRS})")
      endif()
      inline_file("${found}" "${stack}" included)
      math(EXPR next "${number} + 1")
      string(APPEND text "${included}#line ${next} \"${shown}\"\n")
    else()
      string(APPEND text "${line}\n")
    endif()
  endforeach()
  set(all_files "${all_files}" PARENT_SCOPE)
  set(${result} "${text}" PARENT_SCOPE)
endfunction()

get_filename_component(SOURCE "${SOURCE}" ABSOLUTE)
inline_file("${SOURCE}" "" text)
string(REPLACE "${semicolon}" ";" text "${text}")
string(REPLACE "${open_bracket}" "[" text "${text}")
string(REPLACE "${close_bracket}" "]" text "${text}")
# A raw string cannot hold its own delimiter; the kernels never contain this one.
if(text MATCHES "\\)prism_opencl\"")
  message(FATAL_ERROR "${SOURCE}: contains the raw-string delimiter )prism_opencl\"")
endif()
string(CONCAT generated "// Generated from ${SOURCE} by embed_opencl.cmake (includes inlined). Do not edit.\n"
              "namespace prism::opencl_source {\n"
              "extern const char* const ${NAME};\n"
              "const char* const ${NAME} = R\"prism_opencl(${text})prism_opencl\";\n"
              "}  // namespace prism::opencl_source\n")
# Rewrite only on change so dependents are not rebuilt needlessly.
set(old)
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" old)
endif()
if(NOT old STREQUAL generated)
  file(WRITE "${OUTPUT}" "${generated}")
endif()
if(DEFINED DEPFILE)
  list(REMOVE_DUPLICATES all_files)
  string(REPLACE ";" " \\\n  " deps "${all_files}")
  file(WRITE "${DEPFILE}" "${OUTPUT}: \\\n  ${deps}\n")
endif()
