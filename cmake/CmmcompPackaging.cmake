# SPDX-License-Identifier: MIT
# Debian packages by CPack (docs/agent.md, "Packages"): `cpack -G DEB` in a build tree, or the
# ctest package_debs. One package per install component:
#   cmmcomp-dev    headers, libraries, CMake package config, pkg-config files, default model
#   cmmcomp-tools  cmmcomp-sim, cmmcomp-train, cmmcomp-measure, cmmcomp-replay, cmmcomp-vc
#   cmmcomp-agent  cmmcomp-agent, its systemd unit and /etc/cmmcomp/agent.toml (a conffile)
# Dependencies come from dpkg-shlibdeps. The packages install under CMMCOMP_PACKAGE_PREFIX.
set(CMMCOMP_PACKAGE_PREFIX "/usr" CACHE PATH "Install prefix inside the Debian packages")

# Files only the agent's package carries: absolute paths (/etc, the unit pointing at the
# package's prefix), so a plain `cmake --install --prefix DIR` skips them (EXCLUDE_FROM_ALL).
if(TARGET cmmcomp-agent)
  configure_file("${PROJECT_SOURCE_DIR}/packaging/cmmcomp-agent.service.in"
                 "${PROJECT_BINARY_DIR}/packaging/cmmcomp-agent.service" @ONLY)
  install(FILES "${PROJECT_BINARY_DIR}/packaging/cmmcomp-agent.service"
          DESTINATION "${CMMCOMP_PACKAGE_PREFIX}/lib/systemd/system"
          COMPONENT agent EXCLUDE_FROM_ALL)
  install(FILES "${PROJECT_SOURCE_DIR}/packaging/agent.toml" DESTINATION /etc/cmmcomp
          COMPONENT agent EXCLUDE_FROM_ALL)
  # The compensating I++ DME proxy (cmmcomp-agent --ipp-proxy) as a second unit.
  configure_file("${PROJECT_SOURCE_DIR}/packaging/cmmcomp-ipp-proxy.service.in"
                 "${PROJECT_BINARY_DIR}/packaging/cmmcomp-ipp-proxy.service" @ONLY)
  install(FILES "${PROJECT_BINARY_DIR}/packaging/cmmcomp-ipp-proxy.service"
          DESTINATION "${CMMCOMP_PACKAGE_PREFIX}/lib/systemd/system"
          COMPONENT agent EXCLUDE_FROM_ALL)
  install(FILES "${PROJECT_SOURCE_DIR}/packaging/ipp-proxy.env" DESTINATION /etc/cmmcomp
          COMPONENT agent EXCLUDE_FROM_ALL)
  file(WRITE "${PROJECT_BINARY_DIR}/packaging/conffiles"
       "/etc/cmmcomp/agent.toml\n/etc/cmmcomp/ipp-proxy.env\n")
endif()

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME cmmcomp)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_PACKAGE_VENDOR "cmmcomp")
set(CPACK_PACKAGE_CONTACT "cmmcomp developers <cmmcomp-dev@localhost>")
set(CPACK_PACKAGING_INSTALL_PREFIX "${CMMCOMP_PACKAGE_PREFIX}")
set(CPACK_RESOURCE_FILE_LICENSE "${PROJECT_SOURCE_DIR}/README.md")
set(CPACK_PACKAGE_DIRECTORY "${PROJECT_BINARY_DIR}/packages")
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL dev tools agent)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_COMPRESSION_TYPE gzip)
set(CPACK_DEBIAN_DEV_PACKAGE_NAME cmmcomp-dev)
set(CPACK_DEBIAN_TOOLS_PACKAGE_NAME cmmcomp-tools)
set(CPACK_DEBIAN_AGENT_PACKAGE_NAME cmmcomp-agent)
set(CPACK_COMPONENT_DEV_DESCRIPTION
    "cmmcomp headers and libraries: the header-only real-time core, model and dataset I/O, the digital twin, training, the C ABI")
set(CPACK_COMPONENT_TOOLS_DESCRIPTION
    "cmmcomp tools: the twin (cmmcomp-sim), training (cmmcomp-train), the measurement workflow (cmmcomp-measure), replay and the virtual controller")
set(CPACK_COMPONENT_AGENT_DESCRIPTION
    "cmmcomp-agent: serves the per-move compensator to a CMM controller over SocketCAN and Modbus, as a systemd service")
# What a CMake consumer of the dev package needs to find (cmmcompConfig.cmake): io's packages
# always, the twin's and training's when those components are asked for.
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS "libfmt-dev, nlohmann-json3-dev")
set(CPACK_DEBIAN_DEV_PACKAGE_SUGGESTS "libsundials-dev, libtomlplusplus-dev, libceres-dev")
set(CPACK_DEBIAN_AGENT_PACKAGE_CONTROL_EXTRA "${PROJECT_BINARY_DIR}/packaging/conffiles")
include(CPack)
