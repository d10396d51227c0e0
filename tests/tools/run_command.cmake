# SPDX-License-Identifier: MIT
# run(COMMAND ARGS...): runs a command in a ctest script, fails the test with its output when it
# exits non-zero, and leaves its stdout in `run_out`.
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "command failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(run_out "${out}" PARENT_SCOPE)
endfunction()
