# SPDX-License-Identifier: MIT
# Installs the build tree into WORK_DIR/prefix and builds + runs the consumer project against it.
file(REMOVE_RECURSE "${WORK_DIR}")
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "consumer test: command failed (${rc}): ${ARGN}")
  endif()
endfunction()
run(${CMAKE_COMMAND} --install "${CMMCOMP_BUILD_DIR}" --prefix "${WORK_DIR}/prefix")
run(${CMAKE_COMMAND} -S "${CONSUMER_SOURCE_DIR}" -B "${WORK_DIR}/build" -G "${GENERATOR}"
    "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix" -DCMAKE_BUILD_TYPE=Release)
run(${CMAKE_COMMAND} --build "${WORK_DIR}/build")
run("${WORK_DIR}/build/consumer_core")
run("${WORK_DIR}/build/consumer_lib")

# Each component alone, with the packages it must not need made unfindable.
function(component_consumer dir program)
  set(_disabled "")
  foreach(pkg ${ARGN})
    list(APPEND _disabled "-DCMAKE_DISABLE_FIND_PACKAGE_${pkg}=ON")
  endforeach()
  run(${CMAKE_COMMAND} -S "${CONSUMER_SOURCE_DIR}/${dir}" -B "${WORK_DIR}/build-${dir}"
      -G "${GENERATOR}" "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix" -DCMAKE_BUILD_TYPE=Release
      ${_disabled})
  run(${CMAKE_COMMAND} --build "${WORK_DIR}/build-${dir}")
  run("${WORK_DIR}/build-${dir}/${program}")
endfunction()
set(_all Eigen3 Ceres SUNDIALS tomlplusplus nlohmann_json fmt Threads)
component_consumer(core_only consumer_core_only ${_all})
component_consumer(capi_only consumer_capi_only ${_all})
component_consumer(io_only consumer_io_only Eigen3 Ceres SUNDIALS tomlplusplus)

# The examples (examples/), built and run against the installed package as a user does.
if(EXAMPLES_SOURCE_DIR)
  run(${CMAKE_COMMAND} -S "${EXAMPLES_SOURCE_DIR}" -B "${WORK_DIR}/build-examples"
      -G "${GENERATOR}" "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix" -DCMAKE_BUILD_TYPE=Release)
  run(${CMAKE_COMMAND} --build "${WORK_DIR}/build-examples")
  run(${CMAKE_CTEST_COMMAND} --test-dir "${WORK_DIR}/build-examples" --output-on-failure)
endif()
