# SPDX-License-Identifier: MIT
include(CMakePackageConfigHelpers)

install(DIRECTORY "${PROJECT_SOURCE_DIR}/include/cmmcomp" DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES "${PROJECT_BINARY_DIR}/include/cmmcomp/version.hpp"
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/cmmcomp)
# The shipped default model (what io::default_model_file() compiles in), for tools and programs
# that take a model file path (the C ABI, cmmcomp-train export, cmmcomp-agent --model).
install(FILES "${PROJECT_SOURCE_DIR}/data/models/default.json"
        DESTINATION ${CMAKE_INSTALL_DATADIR}/cmmcomp/models)
# One export set per component, so that find_package(cmmcomp COMPONENTS ...) finds only the
# packages the requested components need (cmmcompConfig.cmake.in).
install(TARGETS cmmcomp_core cmmcomp_strict_fp EXPORT cmmcompCoreTargets)
set(_cmmcomp_components Core Io Twin Capi)
install(TARGETS cmmcomp_io EXPORT cmmcompIoTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS cmmcomp_twin cmmcomp_lib EXPORT cmmcompTwinTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS cmmcomp_capi EXPORT cmmcompCapiTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
if(TARGET cmmcomp_training)
  install(TARGETS cmmcomp_training EXPORT cmmcompTrainingTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  list(APPEND _cmmcomp_components Training)
endif()
foreach(_c IN LISTS _cmmcomp_components)
  install(EXPORT cmmcomp${_c}Targets NAMESPACE cmmcomp:: FILE cmmcomp${_c}Targets.cmake
          DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/cmmcomp)
endforeach()

configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/cmmcompConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/cmmcompConfig.cmake"
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/cmmcomp)
write_basic_package_version_file("${PROJECT_BINARY_DIR}/cmmcompConfigVersion.cmake"
  COMPATIBILITY SameMajorVersion)
install(FILES "${PROJECT_BINARY_DIR}/cmmcompConfig.cmake"
              "${PROJECT_BINARY_DIR}/cmmcompConfigVersion.cmake"
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/cmmcomp)
