# SPDX-License-Identifier: MIT
# Identification round trip, as a user runs it: simulate "measured" moves on the default machine,
# move one parameter (KEY in SECTION) away by FACTOR, identify it back, and check the fitted value
# is within 0.1 % of the truth. Variables: SIM, WORK_DIR, SECTION, KEY, FACTOR.
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

run("${SIM}" machine -o "${WORK_DIR}/true.toml")
run("${SIM}" dataset --design l9 --y 400 -o "${WORK_DIR}/measured.csv")

# Read the true value of SECTION.KEY and write a start machine with it scaled by FACTOR.
file(STRINGS "${WORK_DIR}/true.toml" lines)
set(section "")
set(start_text "")
foreach(line IN LISTS lines)
  if(line MATCHES "^\\[(.*)\\]$")
    set(section "${CMAKE_MATCH_1}")
  endif()
  if(section STREQUAL "${SECTION}" AND line MATCHES "^${KEY} = ([^ ]+)")
    set(truth "${CMAKE_MATCH_1}")
    string(REGEX REPLACE "^${KEY} = [^ ]+" "${KEY} = ${truth}*" line "${line}")
  endif()
  string(APPEND start_text "${line}\n")
endforeach()
if(NOT DEFINED truth)
  message(FATAL_ERROR "no ${SECTION}.${KEY} in the default machine")
endif()
# CMake has no floating-point math: let the tool's own TOML writer do it via a scaled literal.
execute_process(COMMAND awk "BEGIN{printf \"%.9g\", ${truth} * ${FACTOR}}" OUTPUT_VARIABLE moved)
string(REPLACE "${KEY} = ${truth}*" "${KEY} = ${moved}" start_text "${start_text}")
file(WRITE "${WORK_DIR}/start.toml" "${start_text}")

run("${SIM}" identify "${WORK_DIR}/measured.csv" --machine "${WORK_DIR}/start.toml"
    --free "${SECTION}.${KEY}" -o "${WORK_DIR}/fitted.toml")
message(STATUS "${last_output}")
set(section "")
file(STRINGS "${WORK_DIR}/fitted.toml" lines)
foreach(line IN LISTS lines)
  if(line MATCHES "^\\[(.*)\\]$")
    set(section "${CMAKE_MATCH_1}")
  endif()
  if(section STREQUAL "${SECTION}" AND line MATCHES "^${KEY} = ([^ ]+)")
    set(fitted "${CMAKE_MATCH_1}")
  endif()
endforeach()
execute_process(
  COMMAND awk "BEGIN{d = ${fitted} / ${truth} - 1; if (d < 0) d = -d; exit !(d < 1e-3)}"
  RESULT_VARIABLE close)
if(NOT close EQUAL 0)
  message(FATAL_ERROR "identified ${SECTION}.${KEY} = ${fitted}, truth ${truth} (start ${moved})")
endif()
message(STATUS "identified ${SECTION}.${KEY} = ${fitted} (truth ${truth}, start ${moved})")
