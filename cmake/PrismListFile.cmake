# prism_list_lines(<file> <regex> <out>): sets <out> in the caller's scope to the lines of <file> (a list kept in
# kernels/, such as stage_list.h or layout_table.h) that match <regex>. Editing the file re-runs the configure step,
# so what CMake generates from the list follows it.
include_guard(GLOBAL)

function(prism_list_lines file regex out)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${file})
  file(STRINGS ${file} lines REGEX "${regex}")
  set(${out} "${lines}" PARENT_SCOPE)
endfunction()
