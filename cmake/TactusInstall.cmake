# Install rules and the CMake package: find_package(Tactus) then link Tactus::tactus.
include(CMakePackageConfigHelpers)
get_property(_libs GLOBAL PROPERTY TACTUS_LIBRARIES)
install(TARGETS tactus ${_libs} EXPORT TactusTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/src/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/tactus
  FILES_MATCHING PATTERN "*.hpp" PATTERN "app" EXCLUDE)
install(DIRECTORY ${PROJECT_BINARY_DIR}/src/core/generated/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/tactus)
# The fabric database a cloth body reads when its scene names no other (scene/load_cloth.cpp).
install(FILES ${PROJECT_SOURCE_DIR}/data/fabrics.toml DESTINATION ${CMAKE_INSTALL_DATADIR}/tactus)
install(EXPORT TactusTargets NAMESPACE Tactus:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/Tactus)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/TactusConfig.cmake.in
  ${PROJECT_BINARY_DIR}/TactusConfig.cmake INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/Tactus)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/TactusConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/TactusConfig.cmake ${PROJECT_BINARY_DIR}/TactusConfigVersion.cmake
  ${PROJECT_SOURCE_DIR}/cmake/FindTetGen.cmake ${PROJECT_SOURCE_DIR}/cmake/FindCHOLMOD.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/Tactus)
