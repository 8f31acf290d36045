# Install rules and the CMake package: `cmake --install build --prefix P` installs the rgbmesh
# tool, the public headers, the (static) libraries and P/lib/cmake/rgbmesh/, so that another
# project can say find_package(rgbmesh REQUIRED [COMPONENTS core fem adapt vtk_io fit parallel]) and link
# rgbmesh::core, rgbmesh::fem, ... The package offers the modules that were built here.
include(CMakePackageConfigHelpers)

set(RGBMESH_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/rgbmesh" CACHE STRING
    "Where the CMake package files are installed, relative to the prefix")

# Module (component name), its target and its source directory; only built ones are installed.
set(RGBMESH_BUILT_COMPONENTS core)
set(_rgbmesh_install_targets rgbmesh_core)
set(_rgbmesh_include_dirs "${PROJECT_SOURCE_DIR}/rgbmesh/include")
foreach(_entry fem:fem adapt:adapt vtk_io:vtk_io fit:fit parallel:parallel)
  string(REPLACE ":" ";" _entry "${_entry}")
  list(GET _entry 0 _component)
  list(GET _entry 1 _dir)
  if(TARGET rgbmesh_${_component})
    list(APPEND RGBMESH_BUILT_COMPONENTS ${_component})
    list(APPEND _rgbmesh_install_targets rgbmesh_${_component})
    list(APPEND _rgbmesh_include_dirs "${PROJECT_SOURCE_DIR}/${_dir}/include")
  endif()
endforeach()

# Exported names: rgbmesh::core, rgbmesh::fem, ... (the in-tree aliases have the same names).
foreach(_target IN LISTS _rgbmesh_install_targets)
  string(REPLACE "rgbmesh_" "" _name "${_target}")
  set_target_properties(${_target} PROPERTIES EXPORT_NAME ${_name})
endforeach()

install(TARGETS ${_rgbmesh_install_targets}
        EXPORT rgbmeshTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
foreach(_dir IN LISTS _rgbmesh_include_dirs)
  install(DIRECTORY "${_dir}/" DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.hpp")
endforeach()
if(TARGET rgbmesh_cli)
  install(TARGETS rgbmesh_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
install(FILES "${PROJECT_SOURCE_DIR}/LICENSE" DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/rgbmesh)

install(EXPORT rgbmeshTargets NAMESPACE rgbmesh:: DESTINATION ${RGBMESH_INSTALL_CMAKEDIR})

# What the config file needs to find the dependencies again.
if(TARGET rgbmesh_vtk_io)
  # The VTK components rgbmesh::vtk_io is linked with (VTK::CommonCore -> CommonCore).
  get_target_property(_links rgbmesh_vtk_io LINK_LIBRARIES)
  set(RGBMESH_VTK_COMPONENTS)
  foreach(_link IN LISTS _links)
    if(_link MATCHES "^VTK::(.+)$")
      list(APPEND RGBMESH_VTK_COMPONENTS ${CMAKE_MATCH_1})
    endif()
  endforeach()
endif()
# The checked-handles value rgbmesh::core is compiled with (rgbmesh/CMakeLists.txt), for the record.
get_target_property(_definitions rgbmesh_core INTERFACE_COMPILE_DEFINITIONS)
set(RGBMESH_CHECKED_HANDLES_VALUE)
foreach(_definition IN LISTS _definitions)
  if(_definition MATCHES "^RGBMESH_CHECKED_HANDLES=(.*)$")
    set(RGBMESH_CHECKED_HANDLES_VALUE "${CMAKE_MATCH_1}")
  endif()
endforeach()
if(NOT RGBMESH_FEM_USES_CHOLMOD)
  set(RGBMESH_FEM_USES_CHOLMOD OFF)
endif()
if(NOT RGBMESH_FEM_USES_PETSC)
  set(RGBMESH_FEM_USES_PETSC OFF)
endif()
# rgbmesh::parallel with MPI (its MPI functions counting the bytes sent, exported by programs).
set(RGBMESH_PARALLEL_USES_MPI OFF)
if(TARGET rgbmesh_parallel AND RGBMESH_PARALLEL_MPI)
  set(RGBMESH_PARALLEL_USES_MPI ON)
  install(FILES "${PROJECT_SOURCE_DIR}/parallel/src/traffic.symbols" DESTINATION ${RGBMESH_INSTALL_CMAKEDIR}
          RENAME rgbmesh-mpi-traffic.symbols)
endif()
configure_package_config_file("${CMAKE_CURRENT_LIST_DIR}/rgbmeshConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/rgbmeshConfig.cmake" INSTALL_DESTINATION ${RGBMESH_INSTALL_CMAKEDIR})
# 0.x: a minor version may change the interface, so only the same minor version is compatible.
write_basic_package_version_file("${PROJECT_BINARY_DIR}/rgbmeshConfigVersion.cmake"
  COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/rgbmeshConfig.cmake" "${PROJECT_BINARY_DIR}/rgbmeshConfigVersion.cmake"
        DESTINATION ${RGBMESH_INSTALL_CMAKEDIR})
