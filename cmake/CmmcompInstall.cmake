# SPDX-License-Identifier: MIT
include(CMakePackageConfigHelpers)

install(DIRECTORY "${PROJECT_SOURCE_DIR}/include/cmmcomp" DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES "${PROJECT_BINARY_DIR}/include/cmmcomp/version.hpp"
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/cmmcomp)
# The shipped default model (what io::default_model_file() compiles in), for tools and programs
# that take a model file path (the C ABI, cmmcomp-train export, cmmcomp-agent --model).
install(FILES "${PROJECT_SOURCE_DIR}/data/models/default.json"
        DESTINATION ${CMAKE_INSTALL_DATADIR}/cmmcomp/models)
# Two export sets, so that find_package(cmmcomp COMPONENTS core) needs no other package:
# the header-only core (and its opt-in FP contract), and the compiled libraries.
install(TARGETS cmmcomp_core cmmcomp_strict_fp EXPORT cmmcompCoreTargets)
install(EXPORT cmmcompCoreTargets NAMESPACE cmmcomp:: FILE cmmcompCoreTargets.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/cmmcomp)
install(TARGETS cmmcomp_lib cmmcomp_training cmmcomp_capi EXPORT cmmcompTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT cmmcompTargets NAMESPACE cmmcomp:: FILE cmmcompTargets.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/cmmcomp)

configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/cmmcompConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/cmmcompConfig.cmake"
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/cmmcomp)
write_basic_package_version_file("${PROJECT_BINARY_DIR}/cmmcompConfigVersion.cmake"
  COMPATIBILITY SameMajorVersion)
install(FILES "${PROJECT_BINARY_DIR}/cmmcompConfig.cmake"
              "${PROJECT_BINARY_DIR}/cmmcompConfigVersion.cmake"
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/cmmcomp)
