# `cmake --install <build> --prefix P`: bin/prism, the static libraries, the headers of the C++ API under
# include/prism/, and the CMake package (lib/cmake/Prism) exporting Prism::prism. A consumer writes only
#   find_package(Prism CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE Prism::prism)
# and gets the include folder, RT_CPU, GLM_FORCE_XYZW_ONLY, C++20 and every library Prism links (the package finds
# them again with find_dependency). tests/consumer/ builds such a program in CI.
include(CMakePackageConfigHelpers)
set(PRISM_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/Prism)

install(TARGETS prism RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

# builtin:bunny and builtin:dragon read the Stanford models from the data folder; an installed prism looks in
# <prefix>/share/prism/scenes (apps/data_dir.cpp). Naming a scenes folder laid out like ../shared/scenes here
# installs its stanford/ models there, so the installed command renders every builtin scene from any folder.
set(PRISM_INSTALL_SCENES "" CACHE PATH "Scenes folder (like ../shared/scenes) whose stanford/ models to install")
if(PRISM_INSTALL_SCENES)
  if(NOT IS_DIRECTORY ${PRISM_INSTALL_SCENES}/stanford)
    message(FATAL_ERROR "PRISM_INSTALL_SCENES=${PRISM_INSTALL_SCENES}: no stanford/ folder in it")
  endif()
  install(DIRECTORY ${PRISM_INSTALL_SCENES}/stanford DESTINATION ${CMAKE_INSTALL_DATADIR}/prism/scenes)
endif()

set(prism_exported prism_api prism_backends prism_core prism_kernels_cpu ${PRISM_BACKEND_LIBRARIES})
install(TARGETS ${prism_exported} EXPORT PrismTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT PrismTargets NAMESPACE Prism:: DESTINATION ${PRISM_INSTALL_CMAKEDIR})

# The API's headers (core/ includes kernels/ for the shared structs); backend internals stay private.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/core ${PROJECT_SOURCE_DIR}/kernels
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/prism FILES_MATCHING PATTERN "*.h")
install(FILES ${PROJECT_SOURCE_DIR}/backends/backend_list.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/prism/backends)

# The backends the exported libraries hold (backends/CMakeLists.txt), for PrismConfig.cmake to find what they link.
set(PRISM_PACKAGE_BACKENDS cpu-ref cpu)
foreach(api CUDA OPENCL VULKAN)
  if(PRISM_HAVE_${api} IN_LIST PRISM_BACKEND_DEFINITIONS)
    set(PRISM_PACKAGE_${api} TRUE)
    string(TOLOWER ${api} name)
    list(APPEND PRISM_PACKAGE_BACKENDS ${name})
  else()
    set(PRISM_PACKAGE_${api} FALSE)
  endif()
endforeach()
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/PrismConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/PrismConfig.cmake INSTALL_DESTINATION ${PRISM_INSTALL_CMAKEDIR})
# 0.x: a minor version may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/PrismConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/PrismConfig.cmake ${PROJECT_BINARY_DIR}/PrismConfigVersion.cmake
        DESTINATION ${PRISM_INSTALL_CMAKEDIR})
