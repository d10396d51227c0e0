# SPDX-License-Identifier: MIT
# Identification round trip, as a user runs it: simulate "measured" moves on the default machine,
# move one parameter (KEY in SECTION) away by FACTOR, identify it back, and check the fitted value
# is within 0.1 % of the truth. Variables: SIM, WORK_DIR, SECTION, KEY, FACTOR.
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
include(${CMAKE_CURRENT_LIST_DIR}/run_command.cmake)

# In machine-file text `text`, the offset of SECTION.KEY's value (`at`) and the value (`out`).
# Works on the whole text (no CMake lists: a description may contain ';').
function(find_value text out at)
  string(FIND "${text}" "\n[${SECTION}]\n" section_at)
  if(section_at EQUAL -1)
    message(FATAL_ERROR "no section [${SECTION}]")
  endif()
  string(SUBSTRING "${text}" ${section_at} -1 rest)
  string(FIND "${rest}" "\n${KEY} = " key_at)
  if(key_at EQUAL -1)
    message(FATAL_ERROR "no ${SECTION}.${KEY}")
  endif()
  string(LENGTH "\n${KEY} = " prefix)
  math(EXPR value_at "${section_at} + ${key_at} + ${prefix}")
  string(SUBSTRING "${text}" ${value_at} -1 tail)
  string(REGEX MATCH "^[^ \n]+" value "${tail}")
  set(${out} "${value}" PARENT_SCOPE)
  set(${at} ${value_at} PARENT_SCOPE)
endfunction()

run("${SIM}" machine -o "${WORK_DIR}/true.toml")
run("${SIM}" dataset --design l9 --y 400 -o "${WORK_DIR}/measured.csv")

# The start machine: the truth with SECTION.KEY scaled by FACTOR (awk does the floating point).
file(READ "${WORK_DIR}/true.toml" true_text)
find_value("${true_text}" truth at)
execute_process(COMMAND awk "BEGIN{printf \"%.9g\", ${truth} * ${FACTOR}}" OUTPUT_VARIABLE moved)
string(SUBSTRING "${true_text}" 0 ${at} head)
string(LENGTH "${truth}" truth_length)
math(EXPR after "${at} + ${truth_length}")
string(SUBSTRING "${true_text}" ${after} -1 tail)
file(WRITE "${WORK_DIR}/start.toml" "${head}${moved}${tail}")

run("${SIM}" identify "${WORK_DIR}/measured.csv" --machine "${WORK_DIR}/start.toml"
    --free "${SECTION}.${KEY}" -o "${WORK_DIR}/fitted.toml")
file(READ "${WORK_DIR}/fitted.toml" fitted_text)
find_value("${fitted_text}" fitted unused)
execute_process(
  COMMAND awk "BEGIN{d = ${fitted} / ${truth} - 1; if (d < 0) d = -d; exit !(d < 1e-3)}"
  RESULT_VARIABLE close)
if(NOT close EQUAL 0)
  message(FATAL_ERROR "identified ${SECTION}.${KEY} = ${fitted}, truth ${truth} (start ${moved})")
endif()
message(STATUS "identified ${SECTION}.${KEY} = ${fitted} (truth ${truth}, start ${moved})")
