# Driver of the Install.* tests (tests/install/CMakeLists.txt). cmake -P with:
#   MODE=install        BUILD_DIR, PREFIX, LIBDIR, HAS_TOOL: install BUILD_DIR into a fresh PREFIX
#   MODE=consumer       CONSUMER (core_only|all_modules), PREFIX, BUILD_TYPE, CHECKED_HANDLES,
#                       HIDE_DEPENDENCIES: configure, build and run the consumer, check its output
#   MODE=core_project   PROJECT_SOURCE: the project with every module off, then core_only on it
# and always CMAKE_COMMAND, GENERATOR, CXX, SOURCE_DIR (tests/install), WORK_DIR.

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT result EQUAL 0)
    string(REPLACE ";" " " command "${ARGN}")
    message(FATAL_ERROR "failed (${result}): ${command}\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

function(expect_files prefix)
  foreach(file IN LISTS ARGN)
    if(NOT EXISTS "${prefix}/${file}")
      message(FATAL_ERROR "not installed: ${prefix}/${file}")
    endif()
  endforeach()
endfunction()

# Packages a core-only build or consumer must not need: CMake acts as if they were not installed.
set(hidden_packages VTK Ceres CGAL Eigen3 CLI11 GTest benchmark)
set(hide)
foreach(p IN LISTS hidden_packages)
  list(APPEND hide -DCMAKE_DISABLE_FIND_PACKAGE_${p}=ON)
endforeach()

# Configures, builds and runs consumer `name` against `prefix`; checks the lines it prints.
function(consumer name prefix build_type checked_handles hide_dependencies)
  set(build "${WORK_DIR}/${name}-${build_type}")
  file(REMOVE_RECURSE "${build}")
  set(options)
  if(hide_dependencies)
    set(options ${hide})
  endif()
  run(${CMAKE_COMMAND} -S "${SOURCE_DIR}/${name}" -B "${build}" -G "${GENERATOR}" -DCMAKE_CXX_COMPILER=${CXX}
      -DCMAKE_BUILD_TYPE=${build_type} -DCMAKE_PREFIX_PATH=${prefix} ${options})
  run(${CMAKE_COMMAND} --build "${build}" -j 2)
  if(name STREQUAL "core_only")
    run("${build}/core_consumer")
    set(expected "level 3: 642 vertices, 1280 triangles, max level 3, valid"
                 "coarsened: 12 vertices, 20 triangles, valid")
  else()
    run("${build}/all_modules_consumer" "${build}/work")
    set(expected "vtk_io: read 42 vertices, 80 triangles, valid" "fem: 42 unknowns" "adapt: cycle 0"
                 "adapt: cycle 1" "fit: 642 targets" "repair: 12 vertices, 20 triangles, valid")
  endif()
  message("${run_output}")
  list(APPEND expected "checked handles: ${checked_handles}\n")
  foreach(line IN LISTS expected)
    string(FIND "${run_output}" "${line}" at)
    if(at EQUAL -1)
      message(FATAL_ERROR "${name}: expected '${line}' in its output")
    endif()
  endforeach()
endfunction()

if(MODE STREQUAL "install")
  file(REMOVE_RECURSE "${PREFIX}")
  run(${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${PREFIX}")
  expect_files("${PREFIX}" include/rgbmesh/mesh.hpp ${LIBDIR}/librgbmesh_core.a
               ${LIBDIR}/cmake/rgbmesh/rgbmeshConfig.cmake ${LIBDIR}/cmake/rgbmesh/rgbmeshConfigVersion.cmake
               ${LIBDIR}/cmake/rgbmesh/rgbmeshTargets.cmake share/doc/rgbmesh/LICENSE)
  if(HAS_TOOL)
    expect_files("${PREFIX}" bin/rgbmesh)
    run("${PREFIX}/bin/rgbmesh" --version)
    message("installed tool: ${run_output}")
  endif()
elseif(MODE STREQUAL "consumer")
  consumer(${CONSUMER} "${PREFIX}" ${BUILD_TYPE} ${CHECKED_HANDLES} "${HIDE_DEPENDENCIES}")
elseif(MODE STREQUAL "core_project")
  # Debug: quicker to compile, and the consumer (Release) then checks the other direction.
  set(build "${WORK_DIR}/core_only_project")
  set(prefix "${WORK_DIR}/core_only_prefix")
  run(${CMAKE_COMMAND} --fresh -S "${PROJECT_SOURCE}" -B "${build}" -G "${GENERATOR}" -DCMAKE_CXX_COMPILER=${CXX}
      -DCMAKE_BUILD_TYPE=Debug -DRGBMESH_WITH_VTK=OFF -DRGBMESH_WITH_FEM=OFF -DRGBMESH_WITH_CERES=OFF
      -DRGBMESH_WITH_REPAIR=OFF
      -DRGBMESH_BUILD_TESTS=OFF -DRGBMESH_BUILD_BENCH=ON -DRGBMESH_BUILD_EXAMPLES=ON ${hide})
  message("${run_output}")
  foreach(line "benchmarks skipped" "examples skipped" "the rgbmesh tool is not built")
    string(FIND "${run_output}" "${line}" at)
    if(at EQUAL -1)
      message(FATAL_ERROR "configuring the core alone: expected '${line}'")
    endif()
  endforeach()
  run(${CMAKE_COMMAND} --build "${build}" -j 2)
  file(REMOVE_RECURSE "${prefix}")
  run(${CMAKE_COMMAND} --install "${build}" --prefix "${prefix}")
  load_cache("${build}" READ_WITH_PREFIX core_ CMAKE_INSTALL_LIBDIR)
  expect_files("${prefix}" include/rgbmesh/mesh.hpp ${core_CMAKE_INSTALL_LIBDIR}/librgbmesh_core.a)
  foreach(absent include/rgbmesh/fem include/rgbmesh/vtk_io.hpp include/rgbmesh/repair bin/rgbmesh
                 ${core_CMAKE_INSTALL_LIBDIR}/librgbmesh_fem.a ${core_CMAKE_INSTALL_LIBDIR}/librgbmesh_repair.a)
    if(EXISTS "${prefix}/${absent}")
      message(FATAL_ERROR "a core-only installation has ${absent}")
    endif()
  endforeach()
  consumer(core_only "${prefix}" Release 1 ON)
  # Asking this installation for a module it does not have fails, naming the module.
  set(asks_fem "${WORK_DIR}/asks_fem")
  file(REMOVE_RECURSE "${asks_fem}")
  file(WRITE "${asks_fem}/src/CMakeLists.txt"
       "cmake_minimum_required(VERSION 3.20)\nproject(asks_fem LANGUAGES NONE)\n"
       "find_package(rgbmesh REQUIRED COMPONENTS core fem)\n")
  execute_process(COMMAND ${CMAKE_COMMAND} -S "${asks_fem}/src" -B "${asks_fem}/build" -G "${GENERATOR}"
                          -DCMAKE_PREFIX_PATH=${prefix}
                  RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(result EQUAL 0 OR NOT err MATCHES "has no module fem")
    message(FATAL_ERROR "find_package(rgbmesh COMPONENTS fem) on a core-only installation:\n${out}\n${err}")
  endif()
else()
  message(FATAL_ERROR "unknown MODE '${MODE}'")
endif()
