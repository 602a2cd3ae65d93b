# prism_stage_list(<prefix>): reads kernels/stage_list.h, the one list of wavefront stages, and sets in the
# caller's scope <prefix>_NAMES (the stage names in list order) and <prefix>_LAUNCH_<name> (its launch column).
# Editing the list re-runs the configure step, so the backends that generate files from it (the OpenCL entry
# points, the Vulkan shaders) follow it.
include_guard(GLOBAL)
include(PrismListFile)

function(prism_stage_list prefix)
  set(list_file ${PROJECT_SOURCE_DIR}/kernels/stage_list.h)
  prism_list_lines(${list_file} "^RT_STAGE\\(" lines)
  set(names)
  foreach(line IN LISTS lines)
    if(NOT line MATCHES "^RT_STAGE\\(([a-z][a-z0-9_]*), *([A-Za-z0-9]+), *(Before|Bounce|After), *(Grid|GridSizesQueue|Queue|QueueGrows), *(0|RT_FLAG_[A-Z0-9_]+)\\)")
      message(FATAL_ERROR "${list_file}: cannot read the stage line '${line}' (RT_STAGE(name, Name, pass, launch, needs))")
    endif()
    list(APPEND names ${CMAKE_MATCH_1})
    set(${prefix}_LAUNCH_${CMAKE_MATCH_1} ${CMAKE_MATCH_4} PARENT_SCOPE)
  endforeach()
  if(NOT names)
    message(FATAL_ERROR "${list_file}: no RT_STAGE lines")
  endif()
  set(${prefix}_NAMES ${names} PARENT_SCOPE)
endfunction()
