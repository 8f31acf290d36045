# Runs an example with --help in an empty folder and fails if it exits non-zero or leaves
# anything behind (cmake -DEXAMPLE=<program> -DWORK=<folder> -P help_writes_nothing.cmake).
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
execute_process(COMMAND "${EXAMPLE}" --help WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE code OUTPUT_QUIET)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "${EXAMPLE} --help exited with ${code}")
endif()
file(GLOB left "${WORK}/*")
if(left)
  message(FATAL_ERROR "${EXAMPLE} --help created ${left}")
endif()
