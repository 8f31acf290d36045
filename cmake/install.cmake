# Install rules and the CMake package: `cmake --install build --prefix P` installs the rgbmesh
# tool, the public headers, the (static) libraries and P/lib/cmake/rgbmesh/, so that another
# project can say find_package(rgbmesh REQUIRED [COMPONENTS core fem adapt vtk_io fit parallel repair]) and link
# rgbmesh::core, rgbmesh::fem, ... The package offers the modules that were built here.
include(CMakePackageConfigHelpers)

set(RGBMESH_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/rgbmesh" CACHE STRING
    "Where the CMake package files are installed, relative to the prefix")

# Module (component name), its target and its source directory; only built ones are installed.
set(RGBMESH_BUILT_COMPONENTS core)
set(_rgbmesh_install_targets rgbmesh_core)
set(_rgbmesh_include_dirs "${PROJECT_SOURCE_DIR}/rgbmesh/include")
foreach(_entry fem:fem adapt:adapt vtk_io:vtk_io fit:fit parallel:parallel repair:repair)
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

# The Python package (issue 14), when it is built: the extension and the package's .py files
# into RGBMESH_PYTHON_INSTALL_DIR/rgbmesh, as the component `python` (setup.py installs that
# component alone to make its wheel, so `cmake --install` and pip give the same files). The
# libraries are static, so the extension needs nothing of this build at run time; its build-tree
# RUNPATH is dropped, and the system libraries it needs (VTK, PETSc, ...) are found by ld.so.
if(RGBMESH_HAVE_PYTHON)
  # The interpreter's own site-packages directory relative to its prefix: for Debian's
  # /usr/bin/python3 that is lib/python3/dist-packages (its `deb_system` scheme, the directory
  # Debian's packages use and FindPython reports as Python3_SITEARCH), for a virtual environment's
  # or another Python's lib/python3.X/site-packages. So `--prefix /usr` or `--prefix <venv>` puts
  # the package on that interpreter's path; other prefixes need PYTHONPATH.
  execute_process(
    COMMAND "${RGBMESH_PYTHON_EXECUTABLE}" -c [=[
import os, sys, sysconfig
if sys.prefix == sys.base_prefix and "deb_system" in sysconfig.get_scheme_names():
    scheme = "deb_system"
else:
    scheme = sysconfig.get_default_scheme() if hasattr(sysconfig, "get_default_scheme") else sysconfig._get_default_scheme()
# Debian's default scheme for its system interpreter is posix_local (/usr/local/...), which would
# not be under the prefix at all: hence deb_system above.
root = os.path.join(os.sep, "PREFIX")
path = sysconfig.get_path("platlib", scheme, vars={"base": root, "platbase": root})
sys.stdout.write(os.path.relpath(path, root))
]=]
    RESULT_VARIABLE _rgbmesh_site_result OUTPUT_VARIABLE _rgbmesh_site ERROR_VARIABLE _rgbmesh_site_error)
  if(NOT _rgbmesh_site_result EQUAL 0 OR _rgbmesh_site STREQUAL "" OR _rgbmesh_site MATCHES "^\\.\\.")
    message(WARNING "rgbmesh: could not ask ${RGBMESH_PYTHON_EXECUTABLE} for its site-packages directory "
                    "(${_rgbmesh_site_error}); the Python package installs into lib/python3/dist-packages")
    set(_rgbmesh_site lib/python3/dist-packages)
  endif()
  set(RGBMESH_PYTHON_INSTALL_DIR "${_rgbmesh_site}" CACHE STRING
      "Where the Python package rgbmesh is installed (the directory holding rgbmesh/), relative to the prefix or absolute")
  install(TARGETS rgbmesh_python LIBRARY DESTINATION "${RGBMESH_PYTHON_INSTALL_DIR}/rgbmesh" COMPONENT python)
  # fem's AMG solver module beside the extension, where the extension looks for it first.
  if(TARGET rgbmesh_petsc_module)
    install(TARGETS rgbmesh_petsc_module LIBRARY DESTINATION "${RGBMESH_PYTHON_INSTALL_DIR}/rgbmesh" COMPONENT python)
  endif()
  # The same files python/CMakeLists.txt copies next to the extension in the build tree.
  file(GLOB _rgbmesh_python_files CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/python/rgbmesh/*.py")
  install(FILES ${_rgbmesh_python_files} DESTINATION "${RGBMESH_PYTHON_INSTALL_DIR}/rgbmesh" COMPONENT python)
  message(STATUS "rgbmesh: the Python package installs into <prefix>/${RGBMESH_PYTHON_INSTALL_DIR} (RGBMESH_PYTHON_INSTALL_DIR)")
endif()
