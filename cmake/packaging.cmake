# Install rules and the Debian package (CPack DEB): `cmake --build build && cd build && cpack -G DEB` writes
# causal-twin_<version>_<arch>.deb. Layout (README, "Install on a plant"):
#   <prefix>/bin                      every service and tool, and causal-twin-demo (deploy/launch.sh)
#   <prefix>/share/causal-twin/       dds/ and config/ (the shipped defaults), data/ (the IMS slice and feature
#                                     tables), security/ (the PKI scripts)
#   /etc/causal-twin/                 the operator's copies (conffiles): DDS profiles, parameters, unit options
#                                     (<prefix>/etc/causal-twin for any prefix but /usr)
#   <prefix>/lib/systemd/system       one unit per service and causal-twin.target
# Installed services find /etc/causal-twin first, then share/causal-twin next to their binary
# (causal/config/config_search.hpp), so nothing refers to the source tree.
include(GNUInstallDirs)
# Two packages (CPack components): causal-twin (component runtime: every rule without a COMPONENT) and
# causal-twin-dev (component dev: cmake/dev_package.cmake).
set(CMAKE_INSTALL_DEFAULT_COMPONENT_NAME runtime)

# Tools (a folder left out with CAUSAL_TWIN_SKIP has no target).
foreach(tool sensor-replay sensor-sim sensor-ingest causal-estimator alarm-recommender causal-recorder causal-ask causal-alarm-action causal-approve
    causal-report causal-offline causal-whatif causal-alarm-eval twin-web causal-plant-profiles)
  if(TARGET ${tool})
    install(TARGETS ${tool} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
endforeach()
# The launcher finds the binaries next to itself when installed (and in the build tree otherwise).
install(PROGRAMS deploy/launch.sh DESTINATION ${CMAKE_INSTALL_BINDIR} RENAME causal-twin-demo)

set(CAUSAL_TWIN_SHARE ${CMAKE_INSTALL_DATADIR}/causal-twin)
install(DIRECTORY deploy/dds deploy/config deploy/data deploy/plant DESTINATION ${CAUSAL_TWIN_SHARE}
  PATTERN localhost.xml EXCLUDE)
# An installed host runs services and tools as several users: its localhost.xml is the UDP-only profile (Fast DDS
# 2.9's shared-memory segments belong to one user; docs/cross-user-and-restarts.md). The source tree's shared-memory
# localhost.xml (one-user test runs) is installed as localhost-shm.xml, to be chosen on purpose.
install(FILES deploy/dds/localhost-udp.xml DESTINATION ${CAUSAL_TWIN_SHARE}/dds RENAME localhost.xml)
install(FILES deploy/dds/localhost.xml DESTINATION ${CAUSAL_TWIN_SHARE}/dds RENAME localhost-shm.xml)
install(PROGRAMS deploy/security/make-pki.sh deploy/security/issue-identity.sh deploy/security/revoke-identity.sh
  deploy/security/install-unit-keys.sh
  DESTINATION ${CAUSAL_TWIN_SHARE}/security)

# The site configuration: /etc/causal-twin (where config_search looks) for the package (prefix /usr), else
# <prefix>/etc/causal-twin, so `cmake --install build --prefix DIR` writes nothing outside DIR (its binaries
# read DIR/share/causal-twin). Decided at install time: cpack installs with prefix /usr.
set(CAUSAL_TWIN_ETC_DIR /etc/causal-twin)
file(GLOB causal_twin_etc_files CONFIGURE_DEPENDS
  ${CMAKE_CURRENT_SOURCE_DIR}/deploy/dds/*.xml ${CMAKE_CURRENT_SOURCE_DIR}/deploy/config/*.yaml
  ${CMAKE_CURRENT_SOURCE_DIR}/deploy/systemd/env/*.env)
list(FILTER causal_twin_etc_files EXCLUDE REGEX "/deploy/dds/localhost\\.xml$")  # installed renamed, below
install(CODE "
  if(CMAKE_INSTALL_PREFIX STREQUAL \"/usr\")
    set(causal_twin_etc ${CAUSAL_TWIN_ETC_DIR})
  else()
    set(causal_twin_etc \"\${CMAKE_INSTALL_PREFIX}/etc/causal-twin\")
  endif()
  # file(INSTALL) puts \$DESTDIR in front, as for every other install rule.
  file(INSTALL DESTINATION \"\${causal_twin_etc}\" TYPE FILE FILES ${causal_twin_etc_files})
  # The UDP-only profile is the installed localhost.xml, the shared-memory one localhost-shm.xml (see above).
  file(INSTALL DESTINATION \"\${causal_twin_etc}\" TYPE FILE
       FILES ${CMAKE_CURRENT_SOURCE_DIR}/deploy/dds/localhost-udp.xml RENAME localhost.xml)
  file(INSTALL DESTINATION \"\${causal_twin_etc}\" TYPE FILE
       FILES ${CMAKE_CURRENT_SOURCE_DIR}/deploy/dds/localhost.xml RENAME localhost-shm.xml)
")

# systemd units: ExecStart names the binaries by the prefix seen at install time (/usr in the package, where
# `cmake --install --prefix P` put them otherwise), so the units are written when installing.
file(GLOB causal_twin_units CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/deploy/systemd/*.service
  ${CMAKE_CURRENT_SOURCE_DIR}/deploy/systemd/*.target)
# Written under build/systemd/<hash of destination>/, so a cpack and a `cmake --install --prefix` at the same
# time do not overwrite each other's units.
foreach(unit ${causal_twin_units})
  get_filename_component(unit_name ${unit} NAME)
  install(CODE "
    set(CAUSAL_TWIN_BINDIR \"\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_BINDIR}\")
    string(MD5 causal_twin_dest \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}\")
    set(causal_twin_unit \"${CMAKE_CURRENT_BINARY_DIR}/systemd/\${causal_twin_dest}/${unit_name}\")
    configure_file(\"${unit}\" \"\${causal_twin_unit}\" @ONLY)
    file(INSTALL DESTINATION \"\${CMAKE_INSTALL_PREFIX}/lib/systemd/system\" TYPE FILE FILES \"\${causal_twin_unit}\")
  ")
endforeach()

# Debian documentation and manual pages of both packages (cmake/debian_docs.cmake), the -dev package's files.
include(${CMAKE_CURRENT_LIST_DIR}/debian_docs.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/dev_package.cmake)

# --- CPack: causal-twin_<version>_<arch>.deb and causal-twin-dev_<version>_<arch>.deb -------------------------
set(CPACK_GENERATOR DEB)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL runtime dev)
set(CPACK_PACKAGE_NAME causal-twin)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME causal-twin)
set(CPACK_DEBIAN_DEV_PACKAGE_NAME causal-twin-dev)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
# lintian refuses a maintainer address on a host that is not a domain (bogus-mail-host, e.g. @localhost); the
# .invalid domain (RFC 2606) says that this one is a placeholder: a distributor sets its own.
set(CAUSAL_TWIN_MAINTAINER "Causal Digital Twin maintainers <causal-twin@maintainers.invalid>" CACHE STRING
  "Maintainer field of the Debian packages")
set(CPACK_PACKAGE_CONTACT "${CAUSAL_TWIN_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${CAUSAL_TWIN_MAINTAINER}")
# Each description's first line is its package's synopsis. CPACK_PACKAGE_DESCRIPTION_SUMMARY stays unset: CPack
# would put it in front of both (one synopsis for two packages, and lintian's description-synopsis-is-duplicated).
# Debian: synopsis and description lines under 80 characters (lintian); CPack indents the lines itself.
set(CPACK_DEBIAN_RUNTIME_DESCRIPTION "causal digital twin over DDS: causal factors, alarms, advice
Learns who causes what between the channels of vibration streams, and how
that changes, and turns it into explained alarms and advice. Services
(sensor-replay, sensor-sim, sensor-ingest, causal-estimator,
alarm-recommender, causal-recorder, twin-web) talk over Fast DDS; tools
(causal-report, causal-ask, causal-offline, causal-whatif, causal-alarm-eval,
causal-plant-profiles); systemd units (causal-twin.target); an IMS test-2
data slice with causal-twin-demo to run the whole twin over loopback.")
set(CPACK_DEBIAN_DEV_DESCRIPTION "causal digital twin over DDS: development files
What a sensor or consumer of the twin's topics needs: the IDL, the headers
generated from it for Fast DDS 2.9 with the topic and QoS profile names, the
link to the types' shared library (CausalTwin::types), the CMake package
(find_package(CausalTwin)) and an example sensor publisher in
/usr/share/doc/causal-twin-dev/examples.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_STRIP_FILES ON)  # debug symbols stay in the build tree
set(CPACK_DEBIAN_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
# dpkg-shlibdeps derives the library packages (libfastrtps2.9, libspdlog1.10, libyaml-cpp0.7, ...) from the
# binaries; what is used at run time but not linked is named here.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_DEPENDS "adduser, libjs-chart.js")
set(CPACK_DEBIAN_RUNTIME_PACKAGE_RECOMMENDS "gnuplot-nox | gnuplot, graphviz, fastdds-tools")
# The library itself is in causal-twin (a sensor host runs the services' package anyway); -dev adds what a
# build needs: headers, the .so link, the CMake package, and Fast DDS's own development files.
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS "causal-twin (= ${PROJECT_VERSION}), libfastrtps-dev, libfastcdr-dev")
set(CPACK_DEBIAN_DEV_PACKAGE_RECOMMENDS "cmake, g++")
# libcausal_twin_types.so.0: a shlibs file and the ldconfig trigger (lintian: package-must-activate-ldconfig-trigger).
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS_POLICY "=")
# Tests and benchmarks are never installed: cpack installs what was built (build first) instead of building
# every test target again.
set(CMAKE_SKIP_INSTALL_ALL_DEPENDENCY ON)

# conffiles: every file installed under /etc, so dpkg keeps the operator's edits on upgrade and removes them on
# purge.
set(causal_twin_conffiles "")
foreach(f ${causal_twin_etc_files})
  get_filename_component(n ${f} NAME)
  string(APPEND causal_twin_conffiles "${CAUSAL_TWIN_ETC_DIR}/${n}\n")
endforeach()
string(APPEND causal_twin_conffiles "${CAUSAL_TWIN_ETC_DIR}/localhost.xml\n${CAUSAL_TWIN_ETC_DIR}/localhost-shm.xml\n")
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/debian/conffiles "${causal_twin_conffiles}")
foreach(script postinst prerm postrm)
  configure_file(${CMAKE_CURRENT_SOURCE_DIR}/deploy/packaging/${script} ${CMAKE_CURRENT_BINARY_DIR}/debian/${script}
    COPYONLY FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
endforeach()
# libcausal_twin_types.so.0 in a public folder: ldconfig must run after install and removal (lintian error
# lacks-ldconfig-trigger; CPack's GENERATE_SHLIBS writes the shlibs file but no trigger here).
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/debian/triggers "activate-noawait ldconfig\n")
set(CPACK_DEBIAN_RUNTIME_PACKAGE_CONTROL_EXTRA ${CMAKE_CURRENT_BINARY_DIR}/debian/triggers ${CMAKE_CURRENT_BINARY_DIR}/debian/conffiles
  ${CMAKE_CURRENT_BINARY_DIR}/debian/postinst ${CMAKE_CURRENT_BINARY_DIR}/debian/prerm
  ${CMAKE_CURRENT_BINARY_DIR}/debian/postrm)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)
