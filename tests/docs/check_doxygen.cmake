# Docs.DoxygenHasNoWarnings: runs doxygen with docs/Doxyfile (output into WORK_DIR) and fails
# when it reports any warning about the public headers.
#   cmake -DDOXYGEN=... -DSOURCE_DIR=<repository> -DWORK_DIR=<folder> -P check_doxygen.cmake
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
file(WRITE "${WORK_DIR}/Doxyfile"
     "@INCLUDE = ${SOURCE_DIR}/docs/Doxyfile\nOUTPUT_DIRECTORY = ${WORK_DIR}\nWARN_LOGFILE = ${WORK_DIR}/warnings.log\n")
execute_process(COMMAND "${DOXYGEN}" "${WORK_DIR}/Doxyfile" WORKING_DIRECTORY "${SOURCE_DIR}"
                RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "doxygen failed (${result}):\n${out}\n${err}")
endif()
file(READ "${WORK_DIR}/warnings.log" warnings)
if(NOT warnings STREQUAL "" OR NOT err STREQUAL "")
  message(FATAL_ERROR "doxygen warnings on the public headers:\n${warnings}${err}")
endif()
if(NOT EXISTS "${WORK_DIR}/html/classrgbmesh_1_1RgbMesh.html")
  message(FATAL_ERROR "doxygen wrote no page for rgbmesh::RgbMesh")
endif()
