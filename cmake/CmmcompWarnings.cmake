# SPDX-License-Identifier: MIT
# Warnings for our own targets only (linked PRIVATE), never set globally.
add_library(cmmcomp_warnings INTERFACE)
target_compile_options(cmmcomp_warnings INTERFACE
  $<$<COMPILE_LANG_AND_ID:CXX,GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wconversion
      -Wold-style-cast -Wnon-virtual-dtor>
  $<$<COMPILE_LANG_AND_ID:C,GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wconversion>
  $<$<BOOL:${CMMCOMP_WERROR}>:-Werror>)
