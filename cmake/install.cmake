# `cmake --install build --prefix P` (docs/cli.md "Installing"): a relocatable tree
#   P/bin/caliper                      the command (finds P/share/caliper from its own path)
#   P/share/caliper/models/*.npz       the built-in body models
#   P/share/caliper/web/               the desktop tool's page (when web/dist was built)
#   P/include/caliper/, P/lib/libcaliper.a, P/lib/cmake/caliper/   for find_package(caliper)
# Nothing installed holds an absolute path: the package configuration locates itself.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(CALIPER_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/caliper)
set(CALIPER_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/caliper)

install(TARGETS caliper EXPORT caliperTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY include/caliper DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT caliperTargets NAMESPACE caliper:: DESTINATION ${CALIPER_INSTALL_CMAKEDIR})
configure_package_config_file(cmake/caliperConfig.cmake.in ${PROJECT_BINARY_DIR}/caliperConfig.cmake
  INSTALL_DESTINATION ${CALIPER_INSTALL_CMAKEDIR}
  PATH_VARS CALIPER_INSTALL_DATADIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/caliperConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/caliperConfig.cmake ${PROJECT_BINARY_DIR}/caliperConfigVersion.cmake
  DESTINATION ${CALIPER_INSTALL_CMAKEDIR})

install(DIRECTORY models/ DESTINATION ${CALIPER_INSTALL_DATADIR}/models FILES_MATCHING PATTERN "*.npz")
if(CALIPER_BUILD_APPS)
  install(TARGETS caliper_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  # web/dist is built by `node web/build.mjs` (scripts/build.sh), not by CMake: installed when present.
  install(DIRECTORY web/dist/ DESTINATION ${CALIPER_INSTALL_DATADIR}/web OPTIONAL)
endif()
