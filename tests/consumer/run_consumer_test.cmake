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

# COMPONENTS core with every other package made unfindable.
set(_disabled "")
foreach(pkg Eigen3 Ceres SUNDIALS tomlplusplus nlohmann_json fmt Threads)
  list(APPEND _disabled "-DCMAKE_DISABLE_FIND_PACKAGE_${pkg}=ON")
endforeach()
run(${CMAKE_COMMAND} -S "${CONSUMER_SOURCE_DIR}/core_only" -B "${WORK_DIR}/build-core" -G "${GENERATOR}"
    "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix" -DCMAKE_BUILD_TYPE=Release ${_disabled})
run(${CMAKE_COMMAND} --build "${WORK_DIR}/build-core")
run("${WORK_DIR}/build-core/consumer_core_only")
