# SPDX-License-Identifier: MIT
# CMMCOMP_ARCH: the instruction set of everything built in this tree (one value for every
# target, because Eigen's vector alignment must agree across translation units).
#   ""      the compiler's default: portable x86-64 (SSE2), what a package or firmware build wants
#   auto    x86-64-v3 (AVX2, FMA, BMI2) when the machine configuring the build can run it, else
#           the default; the release preset uses it (benchmarks, the main job)
#   other   passed as -march=<value> (x86-64-v3, native, znver3, armv8.2-a, ...)
# Results do not depend on it: cmmcomp::core builds with -ffp-contract=off, so every SIMD width
# computes the same bits (tests/tools/replay checks recordings made by one build in another).
if(CMMCOMP_ARCH STREQUAL "")
  return()
endif()

set(_cmmcomp_march "${CMMCOMP_ARCH}")
if(CMMCOMP_ARCH STREQUAL "auto")
  set(_cmmcomp_march "")
  if(CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$" AND NOT CMAKE_CROSSCOMPILING)
    set(_probe "${CMAKE_BINARY_DIR}/CMakeFiles/cmmcomp_arch_probe.cpp")
    file(WRITE "${_probe}" [=[
int main() {
  __builtin_cpu_init();
  const bool v3 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
                  __builtin_cpu_supports("bmi2") && __builtin_cpu_supports("avx");
  return v3 ? 0 : 1;
}
]=])
    try_run(_run_result _compile_result "${CMAKE_BINARY_DIR}/CMakeFiles/cmmcomp_arch_probe"
            "${_probe}" CMAKE_FLAGS "-DCMAKE_CXX_FLAGS=-march=x86-64-v3")
    if(_compile_result AND _run_result EQUAL 0)
      set(_cmmcomp_march "x86-64-v3")
    endif()
  endif()
  if(_cmmcomp_march STREQUAL "")
    message(STATUS "cmmcomp: CMMCOMP_ARCH=auto: this machine does not run x86-64-v3; "
                   "building for the compiler's default instruction set")
    return()
  endif()
endif()

include(CheckCXXCompilerFlag)
check_cxx_compiler_flag("-march=${_cmmcomp_march}" CMMCOMP_HAS_MARCH_${_cmmcomp_march})
if(NOT CMMCOMP_HAS_MARCH_${_cmmcomp_march})
  message(FATAL_ERROR "CMMCOMP_ARCH=${CMMCOMP_ARCH}: the compiler rejects -march=${_cmmcomp_march}")
endif()
message(STATUS "cmmcomp: building for -march=${_cmmcomp_march} (CMMCOMP_ARCH=${CMMCOMP_ARCH})")
add_compile_options(-march=${_cmmcomp_march})
