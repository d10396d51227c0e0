# SPDX-License-Identifier: MIT
# The one way a test program is declared (tests/, plugins/*/tests/, tools/*/tests/).
#
#   cmmcomp_add_test(<name> SOURCES <file>... [LIBS <target>...] [LABELS <label>...]
#                    [INCLUDES <dir>...] [DEFINITIONS <def>...] [TEST_PREFIX <prefix>]
#                    [NO_EXCEPTIONS] [ALLOCATION_COUNTER])
#
# - A GoogleTest program by default: one ctest test per TEST(), labelled LABELS (default unit).
# - NO_EXCEPTIONS: a plain program (its own main, no GoogleTest) built with -fno-exceptions and
#   -fno-rtti, registered as one test named <name> without its "test_" prefix. The real-time path
#   must build and work this way.
# - ALLOCATION_COUNTER: links tests/support/allocation_counter.cpp, which interposes malloc and
#   operator new. AddressSanitizer interposes the same functions, so sanitizer builds leave the
#   program out (the RT-guarantee tests run in the release and dev builds).
# tests/ (for support/*.hpp) and the calling directory are on the include path.
if(CMAKE_CROSSCOMPILING)
  # A cross build has no GoogleTest for its target; Debian's googletest package ships the
  # sources, built here for the target (docs/firmware.md).
  find_package(GTest QUIET)
  if(NOT GTest_FOUND)
    set(CMMCOMP_GTEST_SOURCE_DIR /usr/src/googletest CACHE PATH "GoogleTest sources (cross builds)")
    set(BUILD_GMOCK OFF CACHE BOOL "" FORCE)
    set(INSTALL_GTEST OFF CACHE BOOL "" FORCE)
    add_subdirectory(${CMMCOMP_GTEST_SOURCE_DIR} ${CMAKE_BINARY_DIR}/googletest EXCLUDE_FROM_ALL)
    if(NOT TARGET GTest::gtest_main)  # googletest >= 1.11 defines the aliases itself
      add_library(GTest::gtest ALIAS gtest)
      add_library(GTest::gtest_main ALIAS gtest_main)
    endif()
  endif()
else()
  find_package(GTest REQUIRED)
endif()
include(GoogleTest)

function(cmmcomp_add_test name)
  cmake_parse_arguments(ARG "NO_EXCEPTIONS;ALLOCATION_COUNTER" "TEST_PREFIX"
                        "SOURCES;LIBS;LABELS;INCLUDES;DEFINITIONS" ${ARGN})
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "cmmcomp_add_test(${name}): unknown arguments ${ARG_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "cmmcomp_add_test(${name}): no SOURCES")
  endif()
  if(ARG_ALLOCATION_COUNTER AND CMMCOMP_SANITIZERS)
    return()
  endif()
  if(NOT ARG_LABELS)
    set(ARG_LABELS unit)
  endif()
  set(sources ${ARG_SOURCES})
  if(ARG_ALLOCATION_COUNTER)
    list(APPEND sources ${PROJECT_SOURCE_DIR}/tests/support/allocation_counter.cpp)
  endif()
  add_executable(${name} ${sources})
  target_include_directories(${name} PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}
                                             ${PROJECT_SOURCE_DIR}/tests ${ARG_INCLUDES})
  if(ARG_DEFINITIONS)
    target_compile_definitions(${name} PRIVATE ${ARG_DEFINITIONS})
  endif()

  if(ARG_NO_EXCEPTIONS)
    target_link_libraries(${name} PRIVATE ${ARG_LIBS} cmmcomp_warnings)
    target_compile_options(${name} PRIVATE -fno-exceptions -fno-rtti)
    string(REGEX REPLACE "^test_" "" test_name "${name}")
    add_test(NAME ${ARG_TEST_PREFIX}${test_name} COMMAND ${name})
    set_tests_properties(${ARG_TEST_PREFIX}${test_name} PROPERTIES LABELS "${ARG_LABELS}")
    return()
  endif()

  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest_main cmmcomp_warnings)
  list(LENGTH ARG_LABELS label_count)
  if(label_count GREATER 1)
    # gtest_discover_tests (CMake 3.25) passes only the first item of a list-valued property;
    # gtest_add_tests (the sources' TEST() lines, at configure time) lets us set all labels.
    gtest_add_tests(TARGET ${name} SOURCES ${ARG_SOURCES} TEST_PREFIX "${ARG_TEST_PREFIX}"
                    TEST_LIST tests)
    set_tests_properties(${tests} PROPERTIES LABELS "${ARG_LABELS}")
  else()
    gtest_discover_tests(${name} TEST_PREFIX "${ARG_TEST_PREFIX}"
                         PROPERTIES LABELS "${ARG_LABELS}" DISCOVERY_TIMEOUT 60)
  endif()
endfunction()
