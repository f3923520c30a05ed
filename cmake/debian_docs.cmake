# Debian documentation of both packages (Debian policy 12.5-12.7; lintian):
#   /usr/share/doc/<package>/copyright          machine-readable (DEP-5), deploy/packaging/copyright
#   /usr/share/doc/<package>/changelog.Debian.gz deploy/packaging/changelog, gzip -9n
#   /usr/share/doc/<package>/README.md           the project README (causal-twin), docs/integrators.md (-dev)
#   /usr/share/man/man1/<tool>.1.gz              one page per installed command, made at build time from its
#                                                --help by help2man (deploy/packaging/make_man_page.sh)
set(causal_twin_debian_dir ${CMAKE_CURRENT_BINARY_DIR}/debian)
add_custom_command(OUTPUT ${causal_twin_debian_dir}/changelog.Debian.gz
  COMMAND ${CMAKE_COMMAND} -E make_directory ${causal_twin_debian_dir}
  COMMAND ${CMAKE_COMMAND} -E copy ${CMAKE_CURRENT_SOURCE_DIR}/deploy/packaging/changelog ${causal_twin_debian_dir}/changelog.Debian
  COMMAND gzip -9nf ${causal_twin_debian_dir}/changelog.Debian
  DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/deploy/packaging/changelog
  COMMENT "changelog.Debian.gz"
  VERBATIM)

# One line per command for the NAME section of its page.
set(causal_twin_man_names
  "sensor-replay|replay IMS snapshots or feature tables as DDS vibration frames or condition inputs"
  "sensor-sim|simulate a structural VAR vibration source with known causal factors"
  "sensor-ingest|publish MQTT, UDP or stdin sensor blocks as DDS vibration frames"
  "causal-estimator|learn time-varying causal factors per asset group from DDS vibration frames"
  "alarm-recommender|explained alarms, prognoses and advice from causal factors"
  "causal-recorder|record the twin's DDS topics to CSV files"
  "causal-ask|ask the live twin a what-if question over DDS"
  "causal-alarm-action|acknowledge, shelve or unshelve an alarm of the live twin over DDS"
  "causal-approve|approve a recommended lever: publish it as an intervention"
  "causal-report|write a report (markdown, plots, causal graph) from recorded CSV files"
  "causal-offline|run the estimator on recorded files without DDS"
  "causal-whatif|answer what-if questions from recorded causal factors"
  "causal-alarm-eval|evaluate the alarm rules on the IMS run"
  "twin-web|the live view of the causal twin (HTTP)"
  "causal-plant-profiles|write each host's Fast DDS profile from a plant description"
  "causal-twin-demo|run the whole causal twin over loopback on the shipped IMS data")
find_program(HELP2MAN help2man)
set(causal_twin_man_pages "")
if(NOT HELP2MAN)
  message(WARNING "help2man not found (deploy/install_deps.sh installs it): the package gets no manual pages")
else()
  foreach(entry ${causal_twin_man_names})
    string(REPLACE "|" ";" parts "${entry}")
    list(GET parts 0 tool)
    list(GET parts 1 description)
    if(tool STREQUAL "causal-twin-demo")
      set(tool_path ${CMAKE_CURRENT_SOURCE_DIR}/deploy/launch.sh)
      set(tool_dep ${tool_path})
    elseif(TARGET ${tool})
      set(tool_path $<TARGET_FILE:${tool}>)
      set(tool_dep ${tool})
    else()
      continue()  # left out with CAUSAL_TWIN_SKIP
    endif()
    set(page ${CMAKE_CURRENT_BINARY_DIR}/man/${tool}.1.gz)
    add_custom_command(OUTPUT ${page}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_CURRENT_BINARY_DIR}/man
      COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/deploy/packaging/make_man_page.sh ${tool_path} ${tool} "${description}"
        ${PROJECT_VERSION} ${CMAKE_CURRENT_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR} ${page}
      DEPENDS ${tool_dep} ${CMAKE_CURRENT_SOURCE_DIR}/deploy/packaging/make_man_page.sh
      COMMENT "manual page ${tool}.1"
      VERBATIM)
    list(APPEND causal_twin_man_pages ${page})
  endforeach()
endif()
add_custom_target(causal_twin_debian_docs ALL DEPENDS ${causal_twin_debian_dir}/changelog.Debian.gz ${causal_twin_man_pages})
install(FILES ${causal_twin_man_pages} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT runtime)

foreach(package causal-twin causal-twin-dev)
  if(package STREQUAL causal-twin)
    set(component runtime)
    set(readme ${CMAKE_CURRENT_SOURCE_DIR}/README.md)
  else()
    set(component dev)
    set(readme ${CMAKE_CURRENT_SOURCE_DIR}/docs/integrators.md)
  endif()
  install(FILES ${CMAKE_CURRENT_SOURCE_DIR}/deploy/packaging/copyright ${causal_twin_debian_dir}/changelog.Debian.gz
    DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/${package} COMPONENT ${component})
  install(FILES ${readme} DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/${package} RENAME README.md COMPONENT ${component})
endforeach()
