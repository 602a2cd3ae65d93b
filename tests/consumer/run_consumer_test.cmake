# The test `consumer_package`: installs the build tree to a fresh prefix, builds docs/ray-queries.md's example
# program with the CMakeLists.txt shown beside it (both extracted word for word, so the doc cannot drift from what
# works), runs it on every backend the installed `prism info` reports available, and runs the installed `prism`
# from a folder outside the source and build trees. Only the one-file consumer is compiled: the libraries are the
# ones already built.
#   cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... [-DGENERATOR=...] [-DCXX_COMPILER=...]
#         [-DCXX_COMPILER_LAUNCHER=...] [-DBUILD_TYPE=...] -P run_consumer_test.cmake
cmake_minimum_required(VERSION 3.25)
foreach(required BUILD_DIR SOURCE_DIR WORK_DIR)
  if(NOT ${required})
    message(FATAL_ERROR "run_consumer_test.cmake: -D${required}=... is required")
  endif()
endforeach()

# Runs a command; on failure prints its output and fails the test with `what`.
function(run_checked what)
  cmake_parse_arguments(ARG "" "WORKING_DIRECTORY;OUTPUT" "COMMAND" ${ARGN})
  if(NOT ARG_WORKING_DIRECTORY)
    set(ARG_WORKING_DIRECTORY ${WORK_DIR})
  endif()
  execute_process(COMMAND ${ARG_COMMAND} WORKING_DIRECTORY ${ARG_WORKING_DIRECTORY}
                  OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    string(REPLACE ";" " " shown "${ARG_COMMAND}")
    message(FATAL_ERROR "${what} failed (${result}): ${shown}\n${out}${err}")
  endif()
  if(ARG_OUTPUT)
    set(${ARG_OUTPUT} "${out}" PARENT_SCOPE)
  endif()
endfunction()

# The body of the one ```<language> block of `text` (the doc shows one program and one CMakeLists.txt).
function(extract_block text language out_var)
  string(REGEX MATCHALL "```${language}\n" openings "${text}")
  list(LENGTH openings count)
  if(NOT count EQUAL 1)
    message(FATAL_ERROR "docs/ray-queries.md: expected one ```${language} block, found ${count}")
  endif()
  string(FIND "${text}" "```${language}\n" start)
  string(LENGTH "```${language}\n" skip)
  math(EXPR start "${start} + ${skip}")
  string(SUBSTRING "${text}" ${start} -1 rest)
  string(FIND "${rest}" "\n```" end)
  if(end EQUAL -1)
    message(FATAL_ERROR "docs/ray-queries.md: the ```${language} block is not closed")
  endif()
  math(EXPR end "${end} + 1")
  string(SUBSTRING "${rest}" 0 ${end} body)
  set(${out_var} "${body}" PARENT_SCOPE)
endfunction()

set(prefix ${WORK_DIR}/prefix)
set(project ${WORK_DIR}/ray_query)
# A folder outside the source and build trees, for the installed prism to run in.
set(temp_root "$ENV{TMPDIR}")
if(NOT temp_root)
  set(temp_root /tmp)
endif()
string(RANDOM LENGTH 8 suffix)
set(elsewhere ${temp_root}/prism-consumer-${suffix})
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR} ${project} ${elsewhere})

run_checked("installing the build tree" COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(installed bin/prism include/prism/core/render/render_engine.h include/prism/kernels/types.h
                  include/prism/backends/backend_list.h lib/cmake/Prism/PrismConfig.cmake
                  lib/cmake/Prism/PrismConfigVersion.cmake lib/cmake/Prism/PrismTargets.cmake)
  if(NOT EXISTS ${prefix}/${installed})
    message(FATAL_ERROR "cmake --install wrote no ${installed} under ${prefix}")
  endif()
endforeach()

file(READ ${SOURCE_DIR}/docs/ray-queries.md doc)
extract_block("${doc}" cpp program)
extract_block("${doc}" cmake lists)
file(WRITE ${project}/ray_query.cpp "${program}")
# One line more than the doc shows, to check the list of backends the package announces.
file(WRITE ${project}/CMakeLists.txt "${lists}" "message(STATUS \"Prism_BACKENDS: \${Prism_BACKENDS}\")\n")

set(configure ${CMAKE_COMMAND} -S ${project} -B ${project}/build -DCMAKE_PREFIX_PATH=${prefix})
if(GENERATOR)
  list(APPEND configure -G ${GENERATOR})
endif()
foreach(variable CXX_COMPILER CXX_COMPILER_LAUNCHER BUILD_TYPE)
  if(${variable})
    list(APPEND configure -DCMAKE_${variable}=${${variable}})
  endif()
endforeach()
run_checked("configuring the consumer (find_package(Prism))" COMMAND ${configure} OUTPUT configured)
string(REGEX MATCH "Prism_BACKENDS: ([^\n]*)" announced "${configured}")
set(announced "${CMAKE_MATCH_1}")
run_checked("building the consumer" COMMAND ${CMAKE_COMMAND} --build ${project}/build)

# The installed prism, run outside the source and build trees.
run_checked("prism info from ${elsewhere}" COMMAND ${prefix}/bin/prism info --json WORKING_DIRECTORY ${elsewhere}
            OUTPUT info)
run_checked("prism render from ${elsewhere}"
            COMMAND ${prefix}/bin/prism render --scene builtin:sphere --backend cpu --width 32 --height 18 --depth 3
                    --out sphere.png
            WORKING_DIRECTORY ${elsewhere})
if(NOT EXISTS ${elsewhere}/sphere.png)
  message(FATAL_ERROR "the installed prism render wrote no ${elsewhere}/sphere.png")
endif()

# One triangle in the plane z = 0 around the origin: the example's ray, down the z axis from z = 100, hits it at
# t = 100 where the weights of its vertices are 0.25, 0.25 and 0.5.
file(WRITE ${WORK_DIR}/triangle.ply "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
           "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
           "-1 -1 0\n1 -1 0\n0 1 0\n3 0 1 2\n")
set(expected "t 100 instance 0 primitive 0 u 0.25 v 0.5\n")
string(JSON backend_count LENGTH "${info}" backends)
math(EXPR last "${backend_count} - 1")
set(ran "")
foreach(i RANGE ${last})
  string(JSON name GET "${info}" backends ${i} name)
  string(JSON available GET "${info}" backends ${i} available)
  if(NOT available)
    string(JSON detail GET "${info}" backends ${i} detail)
    message(STATUS "not run on ${name}: ${detail}")
    continue()
  endif()
  if(NOT name IN_LIST announced)
    message(FATAL_ERROR "prism info has backend ${name}, but the package's Prism_BACKENDS is '${announced}'")
  endif()
  run_checked("the example on ${name}" COMMAND ${project}/build/ray_query ${WORK_DIR}/triangle.ply ${name}
              OUTPUT output)
  string(FIND "${output}" "${expected}" at)
  if(NOT at EQUAL 0)
    message(FATAL_ERROR "the example on ${name} printed\n${output}instead of starting with\n${expected}")
  endif()
  list(APPEND ran ${name})
endforeach()
if(NOT "cpu" IN_LIST ran OR NOT "cpu-ref" IN_LIST ran)
  message(FATAL_ERROR "the example did not run on cpu and cpu-ref (ran on: ${ran})")
endif()
message(STATUS "consumer of the installed package (Prism_BACKENDS ${announced}) ran on: ${ran}")
# The prefix holds a copy of every library; kept only when the test fails, to look at.
file(REMOVE_RECURSE ${prefix} ${elsewhere})
