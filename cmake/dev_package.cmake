# causal-twin-dev (CPack component dev): what a plant integrator needs to write a sensor or a consumer of the
# twin's topics in C++ (docs/integrators.md):
#   <prefix>/include/causal_twin/                 causal_twin.h, causal_twinPubSubTypes.h, causal_twinTypeObject.h
#                                                 (generated at build time) and causal/dds/topics.hpp (names)
#   <prefix>/lib/libcausal_twin_types.so          the link to libcausal_twin_types.so.0 (in causal-twin)
#   <prefix>/lib/cmake/CausalTwin/                find_package(CausalTwin): CausalTwin::types
#   <prefix>/share/causal-twin/idl/causal_twin.idl the topics' IDL (other languages: fastddsgen)
#   <prefix>/share/doc/causal-twin-dev/examples/sensor_publisher/  an example sensor, built by the package test
include(CMakePackageConfigHelpers)
set(CAUSAL_TWIN_IDL_INSTALL_DIR ${CMAKE_INSTALL_DATADIR}/causal-twin/idl)
set(CAUSAL_TWIN_DDS_INSTALL_DIR ${CMAKE_INSTALL_DATADIR}/causal-twin/dds)
set(CAUSAL_TWIN_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/CausalTwin)

if(TARGET causal_twin_types_shared)
  install(TARGETS causal_twin_types_shared EXPORT CausalTwinTargets
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT runtime NAMELINK_COMPONENT dev)
  install(EXPORT CausalTwinTargets NAMESPACE CausalTwin:: DESTINATION ${CAUSAL_TWIN_CMAKE_INSTALL_DIR} COMPONENT dev)
  install(FILES ${CAUSAL_TWIN_GENERATED_HEADERS} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/causal_twin COMPONENT dev)
  install(FILES ${CMAKE_CURRENT_SOURCE_DIR}/common/dds/include/causal/dds/topics.hpp
    DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/causal_twin/causal/dds COMPONENT dev)
  install(FILES ${CMAKE_CURRENT_SOURCE_DIR}/idl/causal_twin.idl DESTINATION ${CAUSAL_TWIN_IDL_INSTALL_DIR} COMPONENT dev)
  configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/CausalTwinConfig.cmake.in
    ${CMAKE_CURRENT_BINARY_DIR}/CausalTwinConfig.cmake INSTALL_DESTINATION ${CAUSAL_TWIN_CMAKE_INSTALL_DIR}
    PATH_VARS CAUSAL_TWIN_IDL_INSTALL_DIR CAUSAL_TWIN_DDS_INSTALL_DIR)
  write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/CausalTwinConfigVersion.cmake
    VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
  install(FILES ${CMAKE_CURRENT_BINARY_DIR}/CausalTwinConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/CausalTwinConfigVersion.cmake
    DESTINATION ${CAUSAL_TWIN_CMAKE_INSTALL_DIR} COMPONENT dev)
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/examples/ DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/causal-twin-dev/examples
    COMPONENT dev)
endif()
