# cmake --install: programs, the client library with its headers and the libraries it links
# (idl, core, wire, dds), a CMake package so that a user's project can find_package(semfuse) and
# link semfuse::client, and the licence.
include(CMakePackageConfigHelpers)

install(TARGETS semfuse_idl ${SEMFUSE_INSTALLED_COMMON_TARGETS} semfuse_client
  EXPORT semfuseTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT semfuseTargets NAMESPACE semfuse::
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/semfuse)

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/semfuseConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/semfuseConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/semfuse)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/semfuseConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES
  ${CMAKE_CURRENT_BINARY_DIR}/semfuseConfig.cmake
  ${CMAKE_CURRENT_BINARY_DIR}/semfuseConfigVersion.cmake
  ${CMAKE_CURRENT_LIST_DIR}/FindSemfuseOpenCV.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/semfuse)
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR})
