# Configuring without Embree: a missing Embree names the switch that builds without it, and
# with that switch the project (tests and benchmarks included) configures.
# Run by CTest: cmake -DSOURCE=<source dir> -DWORK=<dir> -P configure_without_embree.cmake
file(REMOVE_RECURSE ${WORK})
# CMAKE_DISABLE_FIND_PACKAGE_embree: as if libembree-dev were not installed.
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE} -B ${WORK}/missing -DCMAKE_DISABLE_FIND_PACKAGE_embree=TRUE
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT err MATCHES "Embree 3 not found.*-DRAYSCOUT_WITH_EMBREE=OFF")
  message(FATAL_ERROR "a missing Embree did not name -DRAYSCOUT_WITH_EMBREE=OFF (exit ${rc}):\n${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE} -B ${WORK}/off -DRAYSCOUT_WITH_EMBREE=OFF
                -DCMAKE_DISABLE_FIND_PACKAGE_embree=TRUE RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "-DRAYSCOUT_WITH_EMBREE=OFF did not configure (exit ${rc}):\n${err}")
endif()
file(REMOVE_RECURSE ${WORK})
