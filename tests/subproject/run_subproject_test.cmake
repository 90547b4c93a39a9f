# Configures, builds and runs tests/subproject (a parent project adding secchi's source tree
# with add_subdirectory); it fails if secchi defines a test or program target there, or sets
# the build type.
file(REMOVE_RECURSE ${WORK})
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE}/tests/subproject -B ${WORK} -DSECCHI_SOURCE=${SOURCE}
                RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "configuring the parent project failed")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK} RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "building the parent project failed")
endif()
execute_process(COMMAND ${WORK}/consumer RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "the parent project's program failed")
endif()
