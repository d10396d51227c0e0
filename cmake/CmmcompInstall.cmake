# SPDX-License-Identifier: MIT
include(CMakePackageConfigHelpers)

# Install components (the Debian packages of cmake/CmmcompPackaging.cmake): dev (headers,
# libraries, CMake and pkg-config files, the default model), tools, agent.
# measure/ is cmmcomp::measure's, which is not installed yet (src/CMakeLists.txt).
install(DIRECTORY "${PROJECT_SOURCE_DIR}/include/cmmcomp" DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        COMPONENT dev PATTERN "measure" EXCLUDE)
install(FILES "${PROJECT_BINARY_DIR}/include/cmmcomp/version.hpp"
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/cmmcomp COMPONENT dev)
# The shipped default model (what io::default_model_file() compiles in), for tools and programs
# that take a model file path (the C ABI, cmmcomp-train export, cmmcomp-agent --model).
install(FILES "${PROJECT_SOURCE_DIR}/data/models/default.json"
        DESTINATION ${CMAKE_INSTALL_DATADIR}/cmmcomp/models COMPONENT dev)
# One export set per component, so that find_package(cmmcomp COMPONENTS ...) finds only the
# packages the requested components need (cmmcompConfig.cmake.in).
install(TARGETS cmmcomp_core cmmcomp_strict_fp EXPORT cmmcompCoreTargets COMPONENT dev)
set(_cmmcomp_components Core Io Twin Capi)
install(TARGETS cmmcomp_io EXPORT cmmcompIoTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev)
install(TARGETS cmmcomp_twin cmmcomp_lib EXPORT cmmcompTwinTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev)
install(TARGETS cmmcomp_capi EXPORT cmmcompCapiTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT dev)
if(TARGET cmmcomp_training)
  install(TARGETS cmmcomp_training EXPORT cmmcompTrainingTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev)
  list(APPEND _cmmcomp_components Training)
endif()
foreach(_c IN LISTS _cmmcomp_components)
  install(EXPORT cmmcomp${_c}Targets NAMESPACE cmmcomp:: FILE cmmcomp${_c}Targets.cmake
          DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/cmmcomp COMPONENT dev)
endforeach()

configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/cmmcompConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/cmmcompConfig.cmake"
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/cmmcomp)
write_basic_package_version_file("${PROJECT_BINARY_DIR}/cmmcompConfigVersion.cmake"
  COMPATIBILITY SameMajorVersion)
install(FILES "${PROJECT_BINARY_DIR}/cmmcompConfig.cmake"
              "${PROJECT_BINARY_DIR}/cmmcompConfigVersion.cmake"
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/cmmcomp COMPONENT dev)

# pkg-config files (relocatable: paths from the .pc file's own folder).
foreach(_pc cmmcomp-core cmmcomp-capi)
  configure_file("${PROJECT_SOURCE_DIR}/packaging/${_pc}.pc.in" "${PROJECT_BINARY_DIR}/${_pc}.pc"
                 @ONLY)
  install(FILES "${PROJECT_BINARY_DIR}/${_pc}.pc" DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig
          COMPONENT dev)
endforeach()

# The agent's example config (also /etc/cmmcomp/agent.toml in the package) and documentation.
if(TARGET cmmcomp-agent)
  install(FILES "${PROJECT_SOURCE_DIR}/packaging/agent.toml"
          DESTINATION ${CMAKE_INSTALL_DATADIR}/cmmcomp COMPONENT agent)
  install(FILES "${PROJECT_SOURCE_DIR}/docs/agent.md" "${PROJECT_SOURCE_DIR}/docs/protocol-ippdme.md"
          DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/cmmcomp-agent COMPONENT agent)
endif()

include(CmmcompPackaging)
