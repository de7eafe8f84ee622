# Installation and the CMake package: find_package(npend) then
# target_link_libraries(app PRIVATE npend::runtime) (tested by tests/package_consumer).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set_target_properties(npend_runtime PROPERTIES EXPORT_NAME runtime)
set_target_properties(npend_generated PROPERTIES EXPORT_NAME generated)
target_include_directories(npend_runtime PUBLIC "$<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>")

install(TARGETS npend_runtime npend_generated EXPORT npendTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS npend RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# npend-gen and the Python module are outside `all` unless NPEND_BUILD_ALL is on: installed
# when they were built.
if(TARGET npend-gen)
  install(TARGETS npend-gen RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} OPTIONAL)
endif()
# The headers of npend_spec (npend/spec/), the front ends' parsing, are not installed: the
# package is the numerical library.
install(DIRECTORY "${PROJECT_SOURCE_DIR}/runtime/include/npend"
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} PATTERN spec EXCLUDE)
get_property(npend_generated_headers GLOBAL PROPERTY NPEND_GENERATED_HEADERS)
install(FILES ${npend_generated_headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/npend/generated)

set(npend_config_dir "${CMAKE_INSTALL_LIBDIR}/cmake/npend")
install(EXPORT npendTargets NAMESPACE npend:: DESTINATION ${npend_config_dir})
configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/npendConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/npendConfig.cmake" INSTALL_DESTINATION ${npend_config_dir})
write_basic_package_version_file("${PROJECT_BINARY_DIR}/npendConfigVersion.cmake"
  COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/npendConfig.cmake"
              "${PROJECT_BINARY_DIR}/npendConfigVersion.cmake"
        DESTINATION ${npend_config_dir})
